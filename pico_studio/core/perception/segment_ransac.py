"""RANSAC line extraction (seed 002), recursive over contiguous runs of a cluster.

For a run of points [s, e]: draw `iterations` random point pairs, each a line hypothesis
through a and b (and always the run's own chord, so a clean wall is found even with few
draws); a point p is an inlier of it when its distance to the line is within `inlier_distance`:

    |(b - a) x (p - a)| <= inlier_distance * |b - a|

Keep the hypothesis with the most inliers (the first such). Its wall is the longest
contiguous run of inliers (at most `max_gap_points` outliers inside it), since a wall is a
contiguous piece of the scan; the points before and after that run are searched again the
same way (an explicit stack, the later run first). The random draws are numpy's
`default_rng(seed).integers`, made inside the loop (pcg64.py: the same integers, without the
cost of handing numpy's Generator over), from a fresh state per scan, so a scan always gives
the same walls and the perceptor stays a pure function. One compiled loop (`_extract`).
"""

from __future__ import annotations

import numpy as np

from pico_studio.config.perception_params import RansacParams
from pico_studio.core.perception.pcg64 import integers_into, seeded_state
from pico_studio.jit import kernel

MIN_RUN = 3  # fewer points cannot carry a line hypothesis and its check
BLOCK = 32  # points counted between checks whether a hypothesis can still win


def _example() -> tuple:
    pts = np.array([[1.0, 0.1 * i] for i in range(8)] + [[1.0 - 0.1 * i, 0.7] for i in range(1, 8)])
    return pts, np.array([[0, 15]], dtype=np.int64), seeded_state(0), 20, 0.02, 2


@kernel(_example)
def _extract(points: np.ndarray, clusters: np.ndarray, rng: np.ndarray, iterations: int,
             inlier_distance: float, max_gap: int) -> np.ndarray:
    """(S, 2) int64 inclusive [first, last] point index of every wall, in scan order; `rng`:
    the random state (pcg64.seeded_state), advanced by the draws."""
    m_all = points.shape[0]
    out = np.empty((max(m_all, 1), 2), dtype=np.int64)
    n_out = 0
    stack = np.empty((2 * m_all + clusters.shape[0] + 1, 2), dtype=np.int64)
    top = 0
    for c in range(clusters.shape[0]):
        stack[top, 0], stack[top, 1] = clusters[c, 0], clusters[c, 1] - 1
        top += 1
    hits = np.empty(m_all, dtype=np.int64)  # inlier indices of the best hypothesis
    i_draw = np.empty(iterations, dtype=np.int64)  # a run's random pairs (i, j)
    j_draw = np.empty(iterations, dtype=np.int64)
    xs = np.ascontiguousarray(points[:, 0])
    ys = np.ascontiguousarray(points[:, 1])
    while top > 0:
        top -= 1
        s, e = stack[top, 0], stack[top, 1]
        m = e - s + 1
        if m < MIN_RUN:
            continue
        # hypotheses: the chord, then `iterations` random pairs
        integers_into(rng, m, i_draw)  # numpy's rng.integers(0, m, size=iterations), twice
        integers_into(rng, m, j_draw)
        best_count = -1
        best_h = -1
        for h in range(iterations + 1):
            i = s + (0 if h == 0 else i_draw[h - 1])
            j = s + (m - 1 if h == 0 else j_draw[h - 1])
            ax, ay = xs[i], ys[i]
            abx, aby = xs[j] - ax, ys[j] - ay
            norm = np.hypot(abx, aby)
            if not norm > 1e-9:
                continue
            thr = inlier_distance * norm
            count = 0
            q = s
            while q <= e:  # in blocks (x and y apart: loops the compiler vectorises)...
                stop = min(q + BLOCK, e + 1)
                for t in range(q, stop):
                    count += abs(abx * (ys[t] - ay) - aby * (xs[t] - ax)) <= thr
                q = stop
                if count + (e + 1 - q) <= best_count:
                    break  # ...until even all the points left could not beat the best
            if count > best_count:
                best_count = count
                best_h = h
        if best_h < 0 or best_count < MIN_RUN:
            continue
        i = s + (0 if best_h == 0 else i_draw[best_h - 1])
        j = s + (m - 1 if best_h == 0 else j_draw[best_h - 1])
        ax, ay = points[i, 0], points[i, 1]
        abx, aby = points[j, 0] - ax, points[j, 1] - ay
        norm = np.hypot(abx, aby)
        n_hit = 0
        for q in range(s, e + 1):
            if abs(abx * (points[q, 1] - ay) - aby * (points[q, 0] - ax)) <= inlier_distance * norm:
                hits[n_hit] = q
                n_hit += 1
        # the longest run of inliers with gaps of at most `max_gap` outliers (the first such)
        first, last = hits[0], hits[0]
        run0 = hits[0]
        for t in range(1, n_hit + 1):
            if t == n_hit or hits[t] - hits[t - 1] - 1 > max_gap:
                if hits[t - 1] - run0 > last - first:
                    first, last = run0, hits[t - 1]
                if t < n_hit:
                    run0 = hits[t]
        if last - first + 1 < MIN_RUN:
            continue
        out[n_out, 0], out[n_out, 1] = first, last
        n_out += 1
        stack[top, 0], stack[top, 1] = s, first - 1
        stack[top + 1, 0], stack[top + 1, 1] = last + 1, e
        top += 2
    order = np.argsort(out[:n_out, 0])
    return out[:n_out][order].copy()


def extract(points: np.ndarray, clusters: np.ndarray, params: RansacParams) -> np.ndarray:
    """(S, 2) int inclusive [first, last] point index of every wall, in scan order."""
    return _extract(np.ascontiguousarray(points, dtype=np.float64), np.ascontiguousarray(clusters, dtype=np.int64),
                    seeded_state(int(params.seed)), int(params.iterations), float(params.inlier_distance),
                    int(params.max_gap_points))
