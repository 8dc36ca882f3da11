"""Angle clustering (seed 001): grow a wall while the next point keeps its average direction.

After resampling, the direction at point i is the angle of p[i + k] - p[i] (k = `lookahead`,
so the range noise is averaged over k spacings). Walking along a cluster, the wall's
direction is the running (circular) average of the directions of its points,

    mean direction = atan2(sum sin(angle_j), sum cos(angle_j))   over the wall's points j,

and the next point starts a new wall when its direction differs from that average by more
than `angle_tolerance` — that is where the scan turns a corner. (The test is made as cos of
the angle between the point's direction and the sum vector against cos(tol), a dot product;
only a case within rounding of the threshold is decided by the atan2 form above, so the
walls are those of the atan2 form.) The walk is a sequential
recurrence (the average resets at every corner), so it is one compiled loop (`_walk`) over
the whole scan.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config.perception_params import AngleClusterParams
from pico_studio.jit import kernel

# the atan2 form of "within tol of the average" and the dot-product form differ by a few
# 1e-15 (roundings of atan2, the wrap, the sums): far below this margin
MARGIN = 1e-12


def _example() -> tuple:
    pts = np.array([[1.0, 0.1 * i] for i in range(8)] + [[1.0 - 0.1 * i, 0.7] for i in range(1, 8)])
    return pts, np.array([[0, 15]], dtype=np.int64), 2, 0.3


@kernel(_example)
def _walk(points: np.ndarray, clusters: np.ndarray, k: int, tol: float) -> np.ndarray:
    """(S, 2) int64 inclusive [first, last] point index of every wall, in scan order."""
    out = np.empty((max(points.shape[0], 1), 2), dtype=np.int64)
    n_out = 0
    ang = np.empty(points.shape[0])
    cos_tol = math.cos(tol)
    for c in range(clusters.shape[0]):
        c0, c1 = clusters[c, 0], clusters[c, 1]
        n = c1 - c0
        if n < 2:
            continue
        kk = min(k, n - 1)
        m = n - kk  # direction of point i (i < m): towards point i + kk
        for i in range(m):
            ang[i] = math.atan2(points[c0 + i + kk, 1] - points[c0 + i, 1], points[c0 + i + kk, 0] - points[c0 + i, 0])
        start = 0
        sx, sy = math.cos(ang[0]), math.sin(ang[0])
        i = 1
        while i < m:
            ci, si = math.cos(ang[i]), math.sin(ang[i])
            # within tol of the average: cos of the angle between them against cos(tol), by
            # the dot product; only a case within rounding (MARGIN) of it takes the atan2s
            norm = math.sqrt(sx * sx + sy * sy)
            inside = False
            cos_between = (ci * sx + si * sy) / norm if norm > 1e-9 else cos_tol
            if cos_between >= cos_tol + MARGIN:
                inside = True
            elif cos_between > cos_tol - MARGIN:
                diff = (ang[i] - math.atan2(sy, sx) + math.pi) % (2 * math.pi) - math.pi
                inside = abs(diff) <= tol
            if inside:
                sx += ci
                sy += si
                i += 1
                continue
            # the corner lies about half a look-ahead past the first deviating direction;
            # the directions up to it straddle the corner, so the next wall starts after it
            cut = min(i + kk // 2, n - 1)
            out[n_out, 0], out[n_out, 1] = c0 + start, c0 + cut
            n_out += 1
            start = cut
            if cut + kk // 2 + 1 >= m:
                break
            i = cut + kk // 2 + 1
            sx, sy = math.cos(ang[i - 1]), math.sin(ang[i - 1])
        if n - 1 - start >= 1:
            out[n_out, 0], out[n_out, 1] = c0 + start, c0 + n - 1
            n_out += 1
    return out[:n_out].copy()


def cluster(points: np.ndarray, clusters: np.ndarray, params: AngleClusterParams) -> np.ndarray:
    """(S, 2) int inclusive [first, last] point index of every wall, in scan order."""
    return _walk(np.ascontiguousarray(points, dtype=np.float64), np.ascontiguousarray(clusters, dtype=np.int64),
                 int(params.lookahead), float(params.angle_tolerance))
