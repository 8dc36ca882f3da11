"""Angle clustering (seed 001): grow a wall while the next point keeps its average direction.

After resampling, the direction at point i is the angle of p[i + k] - p[i] (k = `lookahead`,
so the range noise is averaged over k spacings). Walking along a cluster, the wall's
direction is the running (circular) average of the directions of its points; the next point
starts a new wall when its direction differs from that average by more than
`angle_tolerance` — that is where the scan turns a corner.

The directions are computed vectorised; the walk itself is a running average that resets at
every corner, a sequential recurrence, done on Python floats (one pass, a few hundred
points per scan).
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config.perception_params import AngleClusterParams


def cluster(points: np.ndarray, clusters: np.ndarray, params: AngleClusterParams) -> np.ndarray:
    """(S, 2) int inclusive [first, last] point index of every wall, in scan order."""
    out: list[tuple[int, int]] = []
    k = params.lookahead
    tol = params.angle_tolerance
    for c0, c1 in clusters.tolist():
        n = c1 - c0
        if n < 2:
            continue
        p = points[c0:c1]
        kk = min(k, n - 1)
        d = p[kk:] - p[:-kk]
        ang = np.arctan2(d[:, 1], d[:, 0]).tolist()  # direction of point i, i < n - kk
        m = len(ang)
        start = 0
        sx, sy = math.cos(ang[0]), math.sin(ang[0])
        i = 1
        while i < m:
            diff = (ang[i] - math.atan2(sy, sx) + math.pi) % (2 * math.pi) - math.pi
            if abs(diff) <= tol:
                sx += math.cos(ang[i])
                sy += math.sin(ang[i])
                i += 1
                continue
            # the corner lies about half a look-ahead past the first deviating direction;
            # the directions up to it straddle the corner, so the next wall starts after it
            cut = min(i + kk // 2, n - 1)
            out.append((c0 + start, c0 + cut))
            start = cut
            if cut + kk // 2 + 1 >= m:
                break
            i = cut + kk // 2 + 1
            sx, sy = math.cos(ang[i - 1]), math.sin(ang[i - 1])
        if n - 1 - start >= 1:
            out.append((c0 + start, c0 + n - 1))
    return np.array(out, dtype=np.int64).reshape(-1, 2)
