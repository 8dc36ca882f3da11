"""The scan matcher's compiled loop: each point's nearest local wall (scan_match.py's maths).

For a point q (zero frame) and a wall from a with direction ab (length L, unit normal n):

    t = (q - a) . ab / L^2,   closest = a + clip(t, 0, 1) ab,   dist = |q - closest|

The nearest wall k is the one with the smallest dist (the first such); the point is usable
when its foot falls inside that wall (0 <= t_k <= 1) and dist_k < gate; its residual is the
signed distance to the wall's line, r = n_k . (q - a_k). One pass over points and walls, no
(points x walls) arrays; a wall whose bounding box is already farther than the nearest wall
so far is skipped (it cannot be nearer: the same answer, fewer exact distances).
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel

_SLACK = 1e-9  # m: far above the rounding of a distance in a map of metres (~1e-13)


def _example() -> tuple:
    walls = np.array([[0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 1.0, 1.0]])
    a = np.ascontiguousarray(walls[:, 0:2])
    ab = np.ascontiguousarray(walls[:, 2:4] - a)
    length = np.hypot(ab[:, 0], ab[:, 1])
    normal = np.ascontiguousarray(np.column_stack([-ab[:, 1], ab[:, 0]]) / length[:, None])
    q = np.array([[0.5, 0.05], [0.9, 0.5], [2.0, 2.0]])
    return q, a, ab, normal, length, 0.2


@kernel(_example)
def associate(q: np.ndarray, a: np.ndarray, ab: np.ndarray, normal: np.ndarray, length: np.ndarray,
              gate: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(nearest wall (M,) int64, signed distance to its line (M,), usable (M,) bool)."""
    m, w = q.shape[0], a.shape[0]
    k_out = np.zeros(m, dtype=np.int64)
    r_out = np.zeros(m)
    ok_out = np.zeros(m, dtype=np.bool_)
    # each wall's box: no point of the wall is nearer to q than the box, so a wall whose box
    # lies farther than the best distance so far (by more than any rounding, _SLACK) cannot
    # be the nearest, and its exact distance is not needed (the answer stays the same)
    lo_x, hi_x = np.empty(w), np.empty(w)
    lo_y, hi_y = np.empty(w), np.empty(w)
    for j in range(w):
        bx, by = a[j, 0] + ab[j, 0], a[j, 1] + ab[j, 1]
        lo_x[j], hi_x[j] = min(a[j, 0], bx), max(a[j, 0], bx)
        lo_y[j], hi_y[j] = min(a[j, 1], by), max(a[j, 1], by)
    for i in range(m):
        best = np.inf
        best_k = 0
        best_t = 0.0
        for j in range(w):
            if j > 0:
                ox = max(lo_x[j] - q[i, 0], 0.0, q[i, 0] - hi_x[j])
                oy = max(lo_y[j] - q[i, 1], 0.0, q[i, 1] - hi_y[j])
                if ox * ox + oy * oy > (best + _SLACK) * (best + _SLACK):
                    continue
            rx, ry = q[i, 0] - a[j, 0], q[i, 1] - a[j, 1]
            t = (rx * ab[j, 0] + ry * ab[j, 1]) / (length[j] * length[j])
            c = min(max(t, 0.0), 1.0)
            d = math.hypot(q[i, 0] - (a[j, 0] + c * ab[j, 0]), q[i, 1] - (a[j, 1] + c * ab[j, 1]))
            if j == 0 or d < best:  # the first smallest, as numpy's argmin
                best, best_k, best_t = d, j, t
        k = best_k
        k_out[i] = k
        ok_out[i] = best_t >= 0.0 and best_t <= 1.0 and best < gate
        rx, ry = q[i, 0] - a[k, 0], q[i, 1] - a[k, 1]
        r_out[i] = rx * normal[k, 0] + ry * normal[k, 1]
    return k_out, r_out, ok_out
