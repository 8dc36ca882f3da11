"""Door memory's compiled loop: is a remembered door still open (door_memory says when a door
is remembered and why).

A remembered door A -> B (zero frame) stays while

* each end lies within `reach` of a wall of the local map (point to segment: the foot
  t = clamp((P - a) . d / |d|^2, 0, 1), the distance |a + t d - P|): its jambs are still there;
* no wall crosses its inside (the two segments' crossing at s in (0.15, 0.85) along the door,
  u in [0, 1] along the wall: s = (q - p) x e / (r x e), u = (q - p) x r / (r x e), r the door,
  e the wall) and none passes within `reach` of its middle (a wall lying in its line: a door
  closed, a box pushed into it);
* the current scan's beams towards its points at a quarter, a half and three quarters do not
  end on it (within `reach` of the point) for two of the three in view: someone standing in the
  doorway, the door leaf closed. A beam ending before the point says nothing (something in
  front), nor one out of view.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.core.perception.identify_kernels import _beam_towards
from pico_studio.jit import kernel, njit


@njit
def _near_a_wall(px: float, py: float, walls: np.ndarray, reach: float) -> bool:
    for w in range(walls.shape[0]):
        ax, ay = walls[w, 0], walls[w, 1]
        dx, dy = walls[w, 2] - ax, walls[w, 3] - ay
        t = ((px - ax) * dx + (py - ay) * dy) / max(dx * dx + dy * dy, 1e-12)
        t = min(max(t, 0.0), 1.0)
        if math.hypot(ax + t * dx - px, ay + t * dy - py) <= reach:
            return True
    return False


@njit
def _closed(door: np.ndarray, walls: np.ndarray, reach: float) -> bool:
    px, py = door[0], door[1]
    rx, ry = door[2] - px, door[3] - py
    mx, my = px + 0.5 * rx, py + 0.5 * ry
    for w in range(walls.shape[0]):
        qx, qy = walls[w, 0], walls[w, 1]
        ex, ey = walls[w, 2] - qx, walls[w, 3] - qy
        t = ((mx - qx) * ex + (my - qy) * ey) / max(ex * ex + ey * ey, 1e-12)
        t = min(max(t, 0.0), 1.0)
        if math.hypot(qx + t * ex - mx, qy + t * ey - my) <= reach:
            return True  # a wall at its middle
        den = rx * ey - ry * ex
        if abs(den) < 1e-12:
            continue
        s = ((qx - px) * ey - (qy - py) * ex) / den
        u = ((qx - px) * ry - (qy - py) * rx) / den
        if 0.15 < s < 0.85 and 0.0 <= u <= 1.0:
            return True  # a wall across it
    return False


@njit
def _stood_in(door: np.ndarray, reach: float, has_view: bool, ranges: np.ndarray, valid: np.ndarray, vx: float,
              vy: float, va: float, a0: float, inc: float) -> bool:
    if not has_view:
        return False
    hits = 0
    for f in (0.25, 0.5, 0.75):
        qx, qy = door[0] + f * (door[2] - door[0]), door[1] + f * (door[3] - door[1])
        b = _beam_towards(qx, qy, ranges.shape[0], vx, vy, va, a0, inc)
        if b < 0 or not valid[b]:
            continue
        if abs(ranges[b] - math.hypot(qx - vx, qy - vy)) <= reach:
            hits += 1
    return hits >= 2


def _example() -> tuple:
    doors = np.array([[1.0, -0.4, 1.0, 0.4], [1.0, 1.0, 1.0, 2.0]])
    walls = np.array([[1.0, -2.0, 1.0, -0.4], [1.0, 0.4, 1.0, 2.5]])
    ranges = np.full(5, 3.0)
    return doors, walls, 0.1, True, ranges, np.ones(5, dtype=np.bool_), 0.0, 0.0, 0.0, -1.0, 0.5


@kernel(_example)
def still_open(doors: np.ndarray, walls: np.ndarray, reach: float, has_view: bool, ranges: np.ndarray,
               valid: np.ndarray, vx: float, vy: float, va: float, a0: float, inc: float) -> np.ndarray:
    """(M,) bool: each remembered door (M, 4) is still open (the module docstring)."""
    out = np.zeros(doors.shape[0], dtype=np.bool_)
    for m in range(doors.shape[0]):
        out[m] = _near_a_wall(doors[m, 0], doors[m, 1], walls, reach) \
            and _near_a_wall(doors[m, 2], doors[m, 3], walls, reach) \
            and not _closed(doors[m], walls, reach) \
            and not _stood_in(doors[m], reach, has_view, ranges, valid, vx, vy, va, a0, inc)
    return out
