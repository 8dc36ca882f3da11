"""Door memory: a door judged from several places stays a door while it stays open.

A door's rules judge the local map and the current scan alone, and from many places a real
doorway's shape is also furniture's: seen edge-on nothing passes through it, a cabinet 0.6 m
inside the room backs it, its far jamb hides behind the near one. Driving past, the robot finds
such a doorway, loses it for a few metres, finds it again. So a door found in at least
`door_memory_scans` scans in a row, from places at least `door_memory_spread` apart (one place
only — a robot turning on the spot — is one judgement, made again and again), is remembered:
found no more, it stays a door of its kind while it stays open (`door_memory_kernels._open`:
its ends on the local map's walls, no wall across or in it, no beam ending in it). Found again it
takes the new judgement's geometry. A door found elsewhere than before is a new one: the same
door is one whose middle lies within half a door's least width (`door_min_width`) and whose
direction is within `door_angle` (`geometry.door_matches`).

What it trades: a place the rules take for a door from places a metre apart although the truth
has none is kept for longer too. A corridor's mouth beside a room's wall (hospital_2021.png),
taken for a doorway from the room while the corridor's side is unseen, is forgotten once the
local map shows that side (`door_memory_kernels._mouth_corner`): 725 of 2400 frames of a 120 s
run false, 189 with that test.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pico_studio.config.perception_params import IdentifyParams
from pico_studio.core.perception.door_memory_kernels import carry
from pico_studio.core.perception.identify import View, _view_arrays


@dataclass(frozen=True)
class DoorMemory:
    doors: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))  # (M, 4) zero frame
    kinds: tuple[str, ...] = ()  # (M,) the door kind each was last found as
    scans: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))  # (M,) found in a row
    first: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))  # (M, 2) where the robot first found it
    spread: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (M,) farthest from `first` it was found


def remember(memory: DoorMemory, doors: np.ndarray, kinds: list[str], walls: np.ndarray, connected: np.ndarray,
             view: View | None, robot_xy: tuple[float, float], params: IdentifyParams) -> tuple[np.ndarray, list[str], DoorMemory]:
    """(doors, their kinds, the memory after this scan): `doors` (D, 4) found now and the
    remembered ones not found now that are still open, in the zero frame; `walls` (W, 4) the
    local map's, `connected` (W, 2) the wall each end joins or -1 (the loop: door_memory_kernels.carry)."""
    doors = np.ascontiguousarray(doors, dtype=float).reshape(-1, 4)
    if params.door_memory_scans <= 0:
        return doors, list(kinds), DoorMemory()
    if len(doors) == 0 and len(memory.doors) == 0:
        return doors, [], memory
    rows, scans, first, spread = carry(
        doors, np.ascontiguousarray(memory.doors, dtype=float), np.ascontiguousarray(memory.scans, dtype=np.int64),
        np.ascontiguousarray(memory.first, dtype=float), np.ascontiguousarray(memory.spread, dtype=float),
        float(robot_xy[0]), float(robot_xy[1]), float(params.door_min_width) / 2, math.cos(params.door_angle),
        int(params.door_memory_scans), float(params.door_memory_spread),
        np.ascontiguousarray(walls, dtype=float).reshape(-1, 4),
        np.ascontiguousarray(connected, dtype=np.int64).reshape(-1, 2), float(params.door_memory_reach),
        float(params.jamb_cap_max), *_view_arrays(view))
    out_kinds = list(kinds) + [memory.kinds[j] for j in rows.tolist()]
    out = np.vstack([doors, memory.doors[rows]]) if len(rows) else doors
    return out, out_kinds, DoorMemory(out, tuple(out_kinds), scans, first, spread)
