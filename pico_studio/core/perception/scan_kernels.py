"""The scan stage's compiled loop: is a point on the wall's extended line (scan.py's maths).

For consecutive valid points i, i + 1 (robot frame): *forward*, does point i + 1 lie within
`line_distance` of the line through points i - 3 and i; *backward*, does point i lie within
it of the line through points i + 1 and i + 4? The distance of q to the line through a, b:

    |u x (q - a)| / |u|,   u = b - a       (a line of |u| <= 1e-6 m: no line, infinitely far)

Points without three neighbours on that side are on no line. One pass, no index arrays.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel, njit


@njit
def _line_distance(ax: float, ay: float, bx: float, by: float, qx: float, qy: float) -> float:
    ux, uy = bx - ax, by - ay
    n = math.hypot(ux, uy)
    if not n > 1e-6:
        return np.inf
    return abs(ux * (qy - ay) - uy * (qx - ax)) / max(n, 1e-12)


def _example() -> tuple:
    xy = np.array([[1.0, 0.1 * i] for i in range(8)])
    return xy, 0.02


@kernel(_example)
def on_line(xy: np.ndarray, line_distance: float) -> tuple[np.ndarray, np.ndarray]:
    """((m - 1,) forward, (m - 1,) backward) bool, as above."""
    m = xy.shape[0]
    fwd = np.zeros(max(m - 1, 0), dtype=np.bool_)
    bwd = np.zeros(max(m - 1, 0), dtype=np.bool_)
    if m < 5:
        return fwd, bwd
    for i in range(m - 1):
        if i >= 3:
            a = i - 3
            fwd[i] = _line_distance(xy[a, 0], xy[a, 1], xy[i, 0], xy[i, 1], xy[i + 1, 0], xy[i + 1, 1]) <= line_distance
        if i + 4 <= m - 1:
            b = i + 4
            bwd[i] = _line_distance(xy[b, 0], xy[b, 1], xy[i + 1, 0], xy[i + 1, 1], xy[i, 0], xy[i, 1]) <= line_distance
    return fwd, bwd
