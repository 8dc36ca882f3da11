"""The local map's wall ends as corners, compiled (identify.identify's first step).

Each wall end is floating (nothing seen there), or convex when the laser saw the end itself.
Where wall i's end P joins wall k:

* end to end (k's end joins i back): one corner for the pair. With u = F_i - P, v = F_k - P
  (the walls' far ends) and r_i = E_i - P, r_k = E_k - P (E: where the robot stood when it last
  saw the wall, on its free side — where it stands now for a wall it sees now), the corner is
  concave when each wall's far end lies on the other's free side, (u x v)(u x r_i) > 0 and
  (u x v)(r_k x v) > 0, else convex (both ends get it). Seen now from one place R this is the
  robot lying inside the wedge between the walls (the corner points away from it); a room's
  corner behind the wall the robot has since passed stays concave (from there it would point
  at the robot: a convex corner seen from behind, a door's jamb);
* a T (i's end on k's inside): concave — unless i lies behind k's face (away from where k
  was seen) and was itself seen from k's side: the laser saw it through k's line, k is no
  wall there (two cabinets' fronts fused across the slot between them), and i's end is the
  outer corner of the thing behind, convex (`_seen_through_the_bar`).

Corners are listed in wall order (i, then its end), then every seen free end, convex.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel, njit

_SIDE_MIN = 0.05  # m: a point closer to a wall's line is on neither side of it (noise, a graze)


def _example_junctions() -> tuple:
    walls = np.array([[0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 1.0, 1.0], [0.0, 0.5, 0.5, 0.5]])
    connected = np.array([[-1, 1], [0, -1], [-1, -1]], dtype=np.int64)
    seen_end = np.array([[True, True], [True, False], [False, True]])
    eyes = np.array([[0.5, -1.0], [0.5, -1.0], [0.2, 2.0]])
    return walls, connected, seen_end, eyes, 0, 2, 3


@njit
def _seen_through_the_bar(walls: np.ndarray, eyes: np.ndarray, i: int, a: int, k: int) -> bool:
    """Wall i's end `a` lies on wall k's inside (a T): does i lie behind k's face, on the side
    away from where k was seen, while i itself was seen from k's side? Then the laser saw i
    through k's line: k is no wall there (a slot between two cabinets, fused into one front at a
    graze), and i's end is an outer corner of the thing behind, convex. (From k's other side —
    a thin wall seen from both rooms — it is a T behind it, concave.) Each side is asked of a
    point at least `_SIDE_MIN` from k's line."""
    kx, ky = walls[k, 0], walls[k, 1]
    dx, dy = walls[k, 2] - kx, walls[k, 3] - ky
    length = math.hypot(dx, dy)
    if length <= 0.0:
        return False
    dx, dy = dx / length, dy / length
    far = dx * (walls[i, 2 * (1 - a) + 1] - ky) - dy * (walls[i, 2 * (1 - a)] - kx)
    eye_k = dx * (eyes[k, 1] - ky) - dy * (eyes[k, 0] - kx)
    eye_i = dx * (eyes[i, 1] - ky) - dy * (eyes[i, 0] - kx)
    if abs(far) < _SIDE_MIN or abs(eye_k) < _SIDE_MIN or abs(eye_i) < _SIDE_MIN:
        return False
    return far * eye_k < 0.0 and eye_i * eye_k > 0.0


@kernel(_example_junctions)
def junctions(walls: np.ndarray, connected: np.ndarray, seen_end: np.ndarray, eyes: np.ndarray, floating: int,
              convex: int, concave: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(prop (W, 2) int64: each end's property, corners (C, 2), convex (C,) bool); eyes (W, 2):
    where each wall was last seen from."""
    n = walls.shape[0]
    prop = np.full((n, 2), floating, dtype=np.int64)
    for i in range(n):
        for a in range(2):
            if seen_end[i, a]:
                prop[i, a] = convex
    corners = np.empty((2 * n, 2))
    is_convex = np.empty(2 * n, dtype=np.bool_)
    c = 0
    for i in range(n):
        for a in range(2):
            k = connected[i, a]
            if k < 0:
                continue
            cx, cy = walls[i, 2 * a], walls[i, 2 * a + 1]
            if connected[k, 0] == i or connected[k, 1] == i:  # end to end: one corner for the pair
                b = 0 if connected[k, 0] == i else 1
                if k < i:
                    continue
                ux, uy = walls[i, 2 * (1 - a)] - cx, walls[i, 2 * (1 - a) + 1] - cy
                vx, vy = walls[k, 2 * (1 - b)] - cx, walls[k, 2 * (1 - b) + 1] - cy
                uv = ux * vy - uy * vx
                ur = ux * (eyes[i, 1] - cy) - uy * (eyes[i, 0] - cx)  # k's far end on i's free side?
                rv = (eyes[k, 0] - cx) * vy - (eyes[k, 1] - cy) * vx  # i's far end on k's?
                out = not (uv * ur > 0 and uv * rv > 0)
                prop[i, a] = convex if out else concave
                prop[k, b] = prop[i, a]
            else:  # a T: i's end on k's inside, concave — unless seen through k (below)
                out = _seen_through_the_bar(walls, eyes, i, a, k)
                prop[i, a] = convex if out else concave
            corners[c, 0], corners[c, 1] = cx, cy
            is_convex[c] = out
            c += 1
    for i in range(n):
        for a in range(2):
            if seen_end[i, a] and connected[i, a] < 0:
                corners[c, 0], corners[c, 1] = walls[i, 2 * a], walls[i, 2 * a + 1]
                is_convex[c] = True
                c += 1
    return prop, corners[:c].copy(), is_convex[:c].copy()
