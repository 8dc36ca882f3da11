"""Door memory: a door judged from several places stays a door while it stays open.

A door's rules judge the local map and the current scan alone, and from many places a real
doorway's shape is also furniture's: seen edge-on nothing passes through it, a cabinet 0.6 m
inside the room backs it, its far jamb hides behind the near one. Driving past, the robot finds
such a doorway, loses it for a few metres, finds it again. So a door found in at least
`door_memory_scans` scans in a row, from places at least `door_memory_spread` apart (one place
only — a robot turning on the spot — is one judgement, made again and again), is remembered:
found no more, it stays a door of its kind while it stays open (`door_memory_kernels.still_open`:
its ends on the local map's walls, no wall across or in it, no beam ending in it). Found again it
takes the new judgement's geometry. A door found elsewhere than before is a new one: the same
door is one whose middle lies within half a door's least width (`door_min_width`) and whose
direction is within `door_angle` (`geometry.door_matches`).

What it trades: a place the rules take for a door from places a metre apart although the truth
has none (a corridor's mouth beside a room's wall, hospital_2021.png) is kept for longer too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pico_studio.config.perception_params import IdentifyParams
from pico_studio.core.geometry import door_matches
from pico_studio.core.perception.door_memory_kernels import still_open
from pico_studio.core.perception.identify import View, _view_arrays


@dataclass(frozen=True)
class DoorMemory:
    doors: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))  # (M, 4) zero frame
    kinds: tuple[str, ...] = ()  # (M,) the door kind each was last found as
    scans: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))  # (M,) found in a row
    first: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))  # (M, 2) where the robot first found it
    spread: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (M,) farthest from `first` it was found


def remember(memory: DoorMemory, doors: np.ndarray, kinds: list[str], walls: np.ndarray, view: View | None,
             robot_xy: tuple[float, float], params: IdentifyParams) -> tuple[np.ndarray, list[str], DoorMemory]:
    """(doors, their kinds, the memory after this scan): `doors` (D, 4) found now and the
    remembered ones not found now that are still open, in the zero frame; `walls` (W, 4) the
    local map's."""
    doors = np.ascontiguousarray(doors, dtype=float).reshape(-1, 4)
    if params.door_memory_scans <= 0:
        return doors, list(kinds), DoorMemory()
    robot = np.array(robot_xy, dtype=float)
    same = door_matches(doors, np.ascontiguousarray(memory.doors, dtype=float).reshape(-1, 4),
                        float(params.door_min_width) / 2, math.cos(params.door_angle))
    # found now: each takes the record of the same door (the longest run), or starts one
    scans = np.ones(len(doors), dtype=np.int64)
    first = np.tile(robot, (len(doors), 1))
    spread = np.zeros(len(doors))
    for i in range(len(doors)):
        js = np.flatnonzero(same[i])
        if len(js):
            j = js[np.argmax(memory.scans[js])]
            scans[i], first[i] = memory.scans[j] + 1, memory.first[j]
            spread[i] = max(float(memory.spread[j]), float(np.hypot(*(robot - memory.first[j]))))
    # not found now: kept while remembered and open; a record not yet remembered ends here
    lost = ~same.any(axis=0)
    lost &= (memory.scans >= params.door_memory_scans) & (memory.spread >= params.door_memory_spread)
    rows = np.flatnonzero(lost)
    if len(rows):
        has_view, ranges, valid, vx, vy, va, a0, inc = _view_arrays(view)
        open_ = still_open(np.ascontiguousarray(memory.doors[rows], dtype=float),
                           np.ascontiguousarray(walls, dtype=float).reshape(-1, 4), float(params.door_memory_reach),
                           has_view, ranges, valid, vx, vy, va, a0, inc)
        rows = rows[open_]
    kept_kinds = [memory.kinds[j] for j in rows.tolist()]
    out = DoorMemory(np.vstack([doors, memory.doors[rows]]), tuple(kinds) + tuple(kept_kinds),
                     np.concatenate([scans, memory.scans[rows]]), np.vstack([first, memory.first[rows]]),
                     np.concatenate([spread, memory.spread[rows]]))
    return out.doors, list(kinds) + kept_kinds, out
