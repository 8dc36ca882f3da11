"""The combined map's compiled loops: local walls on the map, doors the map confirms (the
maths in combined.py's docstring; here as single loops, without numpy's per-call cost on a
few dozen walls and the map's hundreds). Doors the map confirms: `geometry.door_matches`."""

from __future__ import annotations

import math

import numpy as np

from pico_studio.core.localisation.match_kernels import _bilinear
from pico_studio.jit import kernel


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
