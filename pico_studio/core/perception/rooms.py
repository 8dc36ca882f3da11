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


def side_range(ranges: np.ndarray, angles: np.ndarray, valid: np.ndarray, params: RoomParams) -> float | None:
    if len(angles) == 0:
        return None
    i = int(np.argmin(np.abs(angles - params.side_angle)))
    if abs(angles[i] - params.side_angle) > 0.05 or not valid[i]:
        return None
    return float(ranges[i])


def room_content(ranges: np.ndarray, angles: np.ndarray, valid: np.ndarray, params: RoomParams) -> tuple[int, int]:
    """(edges, objects) over the beams facing the side."""
    sel = np.flatnonzero(valid & (np.abs(angles - params.side_angle) <= params.content_half_angle))
    if len(sel) < 2:
        return 0, 0
    r = ranges[sel]
    jump = np.flatnonzero(np.abs(np.diff(r)) > params.edge_jump)
    edges = 0
    last = -(10**9)
    for j in (sel[jump]).tolist():  # at most a few dozen jumps
        if j - last > params.edge_skip:
            edges += 1
            last = j
    return edges, int(math.ceil(edges / 2))


def rooms(
    ranges: np.ndarray, angles: np.ndarray, valid: np.ndarray, previous: float | None, params: RoomParams
) -> tuple[dict[str, Any], float | None]:
    """The room summary for the world model and the side range to remember."""
    now = side_range(ranges, angles, valid, params)
    jump = None if now is None or previous is None else now - previous
    found = jump is not None and params.jump_min <= abs(jump) <= params.jump_max
    edges, objects = room_content(ranges, angles, valid, params)
    return {"side_range": now, "jump": jump, "room": bool(found), "edges": edges, "objects": objects}, now
