"""RANSAC line extraction (seed 002), recursive over contiguous runs of a cluster.

For a run of points [s, e]: draw `iterations` random point pairs, each a line hypothesis;
count for every hypothesis at once (an (H, M) array) the points within `inlier_distance`;
keep the best. Its wall is the longest contiguous run of inliers (at most `max_gap_points`
outliers inside it), since a wall is a contiguous piece of the scan; the points before and
after that run are searched again the same way. The random generator is seeded from
`seed`, so a scan always gives the same walls (the perceptor stays a pure function).
"""

from __future__ import annotations

import numpy as np

from pico_studio.config.perception_params import RansacParams

MIN_RUN = 3  # fewer points cannot carry a line hypothesis and its check


def extract(points: np.ndarray, clusters: np.ndarray, params: RansacParams) -> np.ndarray:
    """(S, 2) int inclusive [first, last] point index of every wall, in scan order."""
    rng = np.random.default_rng(params.seed)
    out: list[tuple[int, int]] = []
    stack = [(int(a), int(b) - 1) for a, b in clusters.tolist()]
    while stack:
        s, e = stack.pop()
        if e - s + 1 < MIN_RUN:
            continue
        run = _best_run(points, s, e, params, rng)
        if run is None:
            continue
        a, b = run
        out.append((a, b))
        stack.append((s, a - 1))
        stack.append((b + 1, e))
    out.sort()
    return np.array(out, dtype=np.int64).reshape(-1, 2)


def _best_run(
    points: np.ndarray, s: int, e: int, params: RansacParams, rng: np.random.Generator
) -> tuple[int, int] | None:
    p = points[s : e + 1]
    m = len(p)
    i = rng.integers(0, m, size=params.iterations)
    j = rng.integers(0, m, size=params.iterations)
    # always try the run's own chord too: a clean wall is found even with few draws
    i = np.concatenate([[0], i])
    j = np.concatenate([[m - 1], j])
    a, b = p[i], p[j]
    ab = b - a
    norm = np.hypot(ab[:, 0], ab[:, 1])
    ok = norm > 1e-9
    if not ok.any():
        return None
    a, ab, norm = a[ok], ab[ok], norm[ok]
    # (H, M) perpendicular distances of every point to every hypothesis
    d = np.abs(ab[:, 0:1] * (p[None, :, 1] - a[:, 1:2]) - ab[:, 1:2] * (p[None, :, 0] - a[:, 0:1]))
    inl = d <= params.inlier_distance * norm[:, None]
    best = int(np.argmax(inl.sum(axis=1)))
    mask = inl[best]
    if mask.sum() < MIN_RUN:
        return None
    # longest run of inliers allowing short gaps of outliers
    idx = np.flatnonzero(mask)
    gaps = np.diff(idx) - 1 > params.max_gap_points
    starts = np.concatenate([[0], np.flatnonzero(gaps) + 1])
    ends = np.concatenate([np.flatnonzero(gaps), [len(idx) - 1]])
    k = int(np.argmax(idx[ends] - idx[starts]))
    first, last = int(idx[starts[k]]), int(idx[ends[k]])
    if last - first + 1 < MIN_RUN:
        return None
    return s + first, s + last
