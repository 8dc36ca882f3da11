"""The combined map's compiled loops: local walls on the map, doors the map confirms (the
maths in combined.py's docstring; here as single loops, without numpy's per-call cost on a
few dozen walls and the map's hundreds)."""

from __future__ import annotations

import math

import numpy as np

from pico_studio.core.localisation.match_kernels import _bilinear
from pico_studio.jit import kernel, njit


def _walls_example() -> tuple:
    field = np.arange(16, dtype=np.float32).reshape(4, 4) * np.float32(0.01)
    return field, 0.0, 0.0, 0.1, np.array([[0.05, 0.1, 0.25, 0.1], [0.0, 0.0, 0.0, 0.3]]), 0.05, 0.08, 0.6


@kernel(_walls_example)
def walls_on_map(field: np.ndarray, x0: float, y0: float, res: float, walls: np.ndarray, spacing: float,
                 match_distance: float, match_fraction: float) -> np.ndarray:
    """(W,) bool per wall a-b (global frame): at least `match_fraction` of its
    n = max(2, ceil(|b - a| / spacing) + 1) samples a + t (b - a), t = 0, 1/(n-1), ..., 1 (as
    numpy's linspace: j * (1 / (n - 1)), the last exactly 1) lie within `match_distance` of
    the map (the field's bilinear distance)."""
    out = np.empty(walls.shape[0], dtype=np.bool_)
    for i in range(walls.shape[0]):
        ax, ay = walls[i, 0], walls[i, 1]
        dx, dy = walls[i, 2] - ax, walls[i, 3] - ay
        n = max(2, int(math.ceil(np.hypot(dx, dy) / spacing)) + 1)
        step = 1.0 / (n - 1)
        on = 0
        for j in range(n):
            t = j * step if j < n - 1 else 1.0
            on += _bilinear(field, x0, y0, res, ax + t * dx, ay + t * dy) <= match_distance
        out[i] = on / n >= match_fraction
    return out


@njit
def _point_segment_distance(px: float, py: float, ax: float, ay: float, bx: float, by: float) -> float:
    """|p - (a + t (b - a))|, t = ((p - a) . (b - a)) / |b - a|^2 clipped to [0, 1] (geometry's)."""
    dx, dy = bx - ax, by - ay
    t = min(max(((px - ax) * dx + (py - ay) * dy) / max(dx * dx + dy * dy, 1e-18), 0.0), 1.0)
    ex, ey = px - ax - t * dx, py - ay - t * dy
    return math.sqrt(ex * ex + ey * ey)


def _doors_example() -> tuple:
    walls = np.array([[0.0, 0.0, 2.0, 0.0], [3.0, 0.0, 5.0, 0.0]])
    return np.array([[2.0, 0.0, 3.0, 0.02]]), np.array([[2.0, 0.0, 3.0, 0.0]]), walls, 0.15, 0.3, 0.3


@kernel(_doors_example)
def doors_confirmed(doors: np.ndarray, map_doors: np.ndarray, map_walls: np.ndarray, jamb_distance: float,
                    door_distance: float, door_angle: float) -> np.ndarray:
    """(D,) bool: doors the map confirms (combined.confirmed_by_map): one end within
    `jamb_distance` of a map wall's corner and the other of a map wall, the middle farther than
    that from every map wall (the gap is open in the map, not along its walls); or the middle within
    `door_distance` of a map door line whose direction is within `door_angle` of the door's
    (undirected: |((a - b + pi/2) mod pi) - pi/2|)."""
    out = np.zeros(doors.shape[0], dtype=np.bool_)
    for d in range(doors.shape[0]):
        at_corner = np.zeros(2, dtype=np.bool_)
        on_wall = np.zeros(2, dtype=np.bool_)
        for e in range(2):
            px, py = doors[d, 2 * e], doors[d, 2 * e + 1]
            for w in range(map_walls.shape[0]):
                for c in range(2):
                    if np.hypot(px - map_walls[w, 2 * c], py - map_walls[w, 2 * c + 1]) <= jamb_distance:
                        at_corner[e] = True
                if _point_segment_distance(px, py, map_walls[w, 0], map_walls[w, 1], map_walls[w, 2],
                                           map_walls[w, 3]) <= jamb_distance:
                    on_wall[e] = True
        mx, my = (doors[d, 0] + doors[d, 2]) / 2, (doors[d, 1] + doors[d, 3]) / 2
        if (at_corner[0] and on_wall[1]) or (at_corner[1] and on_wall[0]):
            open_middle = True
            for w in range(map_walls.shape[0]):
                if _point_segment_distance(mx, my, map_walls[w, 0], map_walls[w, 1], map_walls[w, 2],
                                           map_walls[w, 3]) <= jamb_distance:
                    open_middle = False
                    break
            if open_middle:
                out[d] = True
                continue
        a = np.arctan2(doors[d, 3] - doors[d, 1], doors[d, 2] - doors[d, 0])
        for k in range(map_doors.shape[0]):
            if not _point_segment_distance(mx, my, map_doors[k, 0], map_doors[k, 1], map_doors[k, 2],
                                           map_doors[k, 3]) <= door_distance:
                continue
            b = np.arctan2(map_doors[k, 3] - map_doors[k, 1], map_doors[k, 2] - map_doors[k, 0])
            if abs((a - b + np.pi / 2) % np.pi - np.pi / 2) <= door_angle:
                out[d] = True
                break
    return out
