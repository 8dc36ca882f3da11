"""Side rooms and their content (seed 000), from the beams on one side of the robot.

While the robot follows a wall, the side (right-hand by default) range jumps by between
`jump_min` and `jump_max` from one scan to the next when it passes a room's opening. Inside
the view of the room (beams within `content_half_angle` of the side bearing), a jump of more
than `edge_jump` between neighbouring beams is an object's edge; jumps within `edge_skip`
beams after an edge belong to the same edge; objects = ceil(edges / 2), since an object near
a wall may show only one edge.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from pico_studio.config.perception_params import RoomParams
from pico_studio.jit import kernel


def side_range(ranges: np.ndarray, angles: np.ndarray, valid: np.ndarray, params: RoomParams) -> float | None:
    if len(angles) == 0:
        return None
    r = _side_beam(np.ascontiguousarray(ranges, dtype=float), np.ascontiguousarray(angles, dtype=float),
                   np.ascontiguousarray(valid, dtype=bool), float(params.side_angle))
    return None if math.isnan(r) else r


def room_content(ranges: np.ndarray, angles: np.ndarray, valid: np.ndarray, params: RoomParams) -> tuple[int, int]:
    """(edges, objects) over the beams facing the side."""
    edges = _edges(np.ascontiguousarray(ranges, dtype=float), np.ascontiguousarray(angles, dtype=float),
                   np.ascontiguousarray(valid, dtype=bool), float(params.side_angle), float(params.content_half_angle),
                   float(params.edge_jump), int(params.edge_skip))
    return edges, int(math.ceil(edges / 2))


def _example() -> tuple:
    angles = np.linspace(-2.0, 2.0, 9)
    return np.array([1.0, 1.0, 3.0, 3.0, 1.0, 1.0, 2.0, 2.0, 2.0]), angles, np.ones(9, dtype=np.bool_), -1.57


@kernel(_example)
def _side_beam(ranges: np.ndarray, angles: np.ndarray, valid: np.ndarray, side: float) -> float:
    """The range of the beam nearest the side bearing (the first on ties); NaN when that beam
    is more than 0.05 rad off or invalid."""
    i, best = 0, np.inf
    for k in range(angles.shape[0]):
        if abs(angles[k] - side) < best:
            i, best = k, abs(angles[k] - side)
    if best > 0.05 or not valid[i]:
        return np.nan
    return ranges[i]


def _example_edges() -> tuple:
    return (*_example(), 1.0, 0.5, 1)


@kernel(_example_edges)
def _edges(ranges: np.ndarray, angles: np.ndarray, valid: np.ndarray, side: float, half_angle: float,
           edge_jump: float, edge_skip: int) -> int:
    """Edges among the valid beams within `half_angle` of the side: a jump above `edge_jump`
    from one such beam to the next (at beam j, the first of the two), jumps within
    `edge_skip` beams after an edge belonging to it."""
    edges, last, prev = 0, -(10**9), -1
    for j in range(ranges.shape[0]):
        if not (valid[j] and abs(angles[j] - side) <= half_angle):
            continue
        if prev >= 0 and abs(ranges[j] - ranges[prev]) > edge_jump and prev - last > edge_skip:
            edges += 1
            last = prev
        prev = j
    return edges


def rooms(
    ranges: np.ndarray, angles: np.ndarray, valid: np.ndarray, previous: float | None, params: RoomParams
) -> tuple[dict[str, Any], float | None]:
    """The room summary for the world model and the side range to remember."""
    now = side_range(ranges, angles, valid, params)
    jump = None if now is None or previous is None else now - previous
    found = jump is not None and params.jump_min <= abs(jump) <= params.jump_max
    edges, objects = room_content(ranges, angles, valid, params)
    return {"side_range": now, "jump": jump, "room": bool(found), "edges": edges, "objects": objects}, now
