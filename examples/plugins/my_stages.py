"""An example plugin: a segmenter, a door detector and a behaviour with their own sliders.

    pico-studio serve --plugin examples/plugins/my_stages.py
    pico-studio config defaults --plugin examples/plugins/my_stages.py   # perception.plugins.chord_split
    pico-studio eval --map pico_studio/data/maps/hospital_2019.json --poses 5 \\
        --plugin examples/plugins/my_stages.py --config examples/plugins/use_my_stages.yaml
    pico-studio run --plugin examples/plugins/my_stages.py --behaviour creep --seconds 5

Everything here is plain numpy; the decorators are the only pico_studio in it besides
`param` (the same declaration the built-in stages use) and `emit` (an extra layer on the page).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pico_studio.core.io import Command
from pico_studio.core.world_model import CONVEX
from pico_studio.plugins import behaviour, door_detector, emit, param, segmenter


@dataclass(frozen=True)
class ChordSplitParams:
    split: float = param(0.04, lo=0.005, hi=0.5, step=0.005, unit="m",
                         help="Split a piece where a point is farther than this from its chord")


@segmenter("chord_split", ChordSplitParams, help="Example: split-and-merge in plain numpy")
def chord_split(points: np.ndarray, params: ChordSplitParams) -> list[tuple[int, int]]:
    """Iterative end-point fit: split [first, last] at the point farthest from the chord
    while that is farther than `split`; the pipeline refits, merges and filters the pieces."""
    pieces: list[tuple[int, int]] = []
    todo = [(0, len(points) - 1)] if len(points) >= 2 else []
    while todo:
        s, e = todo.pop()
        a, b = points[s], points[e]
        ab = b - a
        norm = float(np.hypot(*ab))
        inner = points[s + 1 : e]
        if norm < 1e-12 or len(inner) == 0:
            pieces.append((s, e))
            continue
        d = np.abs(ab[0] * (inner[:, 1] - a[1]) - ab[1] * (inner[:, 0] - a[0])) / norm
        k = int(np.argmax(d))
        if d[k] > params.split:
            todo += [(s + 1 + k, e), (s, s + 1 + k)]  # the left half first: pieces in scan order
        else:
            pieces.append((s, e))
    return pieces


@dataclass(frozen=True)
class GapDoorParams:
    min_width: float = param(0.6, lo=0.1, hi=3.0, step=0.05, unit="m", help="A door is at least this wide")
    max_width: float = param(1.2, lo=0.1, hi=3.0, step=0.05, unit="m", help="A door is at most this wide")


@door_detector("gap_doors", GapDoorParams, help="Example: a door between two free wall ends")
def gap_doors(world_model, params: GapDoorParams) -> np.ndarray:  # noqa: ANN001 - a WorldModel
    """A door wherever two convex (free, looked-past) ends of different walls of the local
    map are a door's width apart. The candidate ends go to the page as an extra layer."""
    walls = world_model.local_map.walls
    prop = world_model.local_map.endpoint_property
    ends = walls.reshape(-1, 2)  # end 0 and end 1 of each wall, in turn
    convex = np.flatnonzero(prop.reshape(-1) == CONVEX)
    emit("convex_ends", ends[convex], frame="zero")
    doors = []
    for i in range(len(convex)):
        for j in range(i + 1, len(convex)):
            p, q = convex[i], convex[j]
            if p // 2 == q // 2:
                continue  # two ends of one wall
            width = float(np.hypot(*(ends[p] - ends[q])))
            if params.min_width <= width <= params.max_width:
                doors.append([*ends[p], *ends[q]])
    return np.array(doors, dtype=float).reshape(-1, 4)


@dataclass(frozen=True)
class CreepParams:
    speed: float = param(0.3, lo=0.0, hi=1.0, step=0.05, unit="m/s", help="Forward speed when the way is clear")
    turn_rate: float = param(0.6, lo=0.0, hi=2.0, step=0.05, unit="rad/s", help="Turn rate when something is ahead")
    clearance: float = param(0.6, lo=0.1, hi=3.0, step=0.05, unit="m", help="Turn when a point is this close ahead")


@behaviour("creep", CreepParams, help="Example: drive ahead, turn away from what is in front")
class Creep:
    """Forward while the corridor ahead (robot width, `clearance` deep) is empty, else turn."""

    frame = "zero"

    def __init__(self, params: CreepParams):
        self.params = params
        self.state = "waiting for a scan"

    def step(self, world_model, laser, odometry, now: float, *, ok: bool = True) -> Command:  # noqa: ANN001
        if not ok or world_model is None:
            self.state = "stopped"
            return Command()
        pts = world_model.points  # robot frame, x ahead
        ahead = (pts[:, 0] > 0) & (pts[:, 0] < self.params.clearance) & (np.abs(pts[:, 1]) < 0.25)
        if ahead.any():
            self.state = "turning"
            return Command(0.0, 0.0, self.params.turn_rate)
        self.state = "driving"
        return Command(self.params.speed, 0.0, 0.0)
