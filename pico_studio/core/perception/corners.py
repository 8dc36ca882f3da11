"""Corner detectors on the raw point sequence (seed 002): the spike and the vector method.

*Spike* (outer corners, also half-seen ones): two consecutive points more than `spike_gap`
apart, the nearer within `spike_max_range` of the robot: the nearer one is a corner — the
laser ran off the end of something into the distance.

*Vector* (inner and outer corners seen from both sides): at point i, the signed angle between
v1 = p[i-k] - p[i] and v2 = p[i+k] - p[i] (k points ~ `vector_step` apart, same cluster).
The scan runs counter-clockwise, so a corner pointing away from the robot (inner, concave,
90 deg on the robot's side) gives -90 deg and one pointing at the robot (outer, convex,
270 deg on the robot's side) gives +90 deg. Runs of neighbouring hits are one corner: the
point whose angle is closest to +-90 deg.

Both are one compiled pass over the scan's points (`_spikes`, `_vectors`).
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config.perception_params import CornerParams
from pico_studio.core.perception.scan import ScanPoints
from pico_studio.core.perception.scan_kernels import cheap_length, too_close
from pico_studio.jit import kernel


def _spike_example() -> tuple:
    return np.array([[1.0, 0.0], [1.0, 0.1], [3.0, 0.4], [3.0, 0.5]]), 0.5, 4.0


@kernel(_spike_example)
def _spikes(p: np.ndarray, gap_min: float, max_range: float) -> np.ndarray:
    """Indices (K,) of the spike corners: per gap wider than `gap_min`, its nearer point."""
    m = p.shape[0]
    out = np.empty(max(m, 1), dtype=np.int64)
    n = 0
    # lengths by the cheap sqrt(x^2 + y^2), each comparison too close to call by it made by
    # hypot (scan_kernels.cheap_length): the decisions are hypot's
    r1 = cheap_length(p[0, 0], p[0, 1]) if m else 0.0
    for i in range(m - 1):
        r0 = r1  # each point's range once
        r1 = cheap_length(p[i + 1, 0], p[i + 1, 1])
        a0, a1 = r0, r1
        if too_close(a0, a1):
            a0, a1 = math.hypot(p[i, 0], p[i, 1]), math.hypot(p[i + 1, 0], p[i + 1, 1])
        near, r = (i, a0) if a0 <= a1 else (i + 1, a1)
        if too_close(r, max_range):
            r = math.hypot(p[near, 0], p[near, 1])
        if not r < max_range:
            continue  # (the gap only matters near the robot)
        dx, dy = p[i + 1, 0] - p[i, 0], p[i + 1, 1] - p[i, 1]
        gap = cheap_length(dx, dy)
        if too_close(gap, gap_min):
            gap = math.hypot(dx, dy)
        if gap > gap_min and (n == 0 or out[n - 1] != near):
            out[n] = near  # non-decreasing: a point between two gaps counts once
            n += 1
    return out[:n].copy()


def spike_corners(scan: ScanPoints, params: CornerParams) -> np.ndarray:
    """(K, 2) outer corners, robot frame."""
    p = scan.points
    if len(p) < 2:
        return np.zeros((0, 2))
    return p[_spikes(np.ascontiguousarray(p, dtype=np.float64), float(params.spike_gap), float(params.spike_max_range))]


# |cos| of a vector-corner angle is compared with sin(tol) with this relative margin, far above
# the roundings (a few 1e-16) of the dot and cross products and of atan2
MARGIN = 1e-9


def _vector_example() -> tuple:
    pts = np.array([[1.0, 0.1 * i] for i in range(6)] + [[1.0 - 0.1 * i, 0.5] for i in range(1, 6)])
    return pts, np.array([[0, 11]], dtype=np.int64), 2, 0.3


@kernel(_vector_example)
def _vectors(p: np.ndarray, clusters: np.ndarray, k: int, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """(indices (V,), inner (V,)) of the vector corners: per run of neighbouring hits, the
    point whose angle between v1 = p[i-k] - p[i] and v2 = p[i+k] - p[i] is closest to +-90 deg."""
    m = p.shape[0]
    cid = np.empty(m, dtype=np.int64)
    for c in range(clusters.shape[0]):
        cid[clusters[c, 0]:clusters[c, 1]] = c
    out = np.empty(max(m, 1), dtype=np.int64)
    inner = np.empty(max(m, 1), dtype=np.bool_)
    n = 0
    last_hit = -2
    best_dev = 0.0
    # (the margin widens tol by at least MARGIN / 2 x tol: above rounding unless tol is tiny)
    near_square = math.sin(tol) ** 2 * (1 + MARGIN) if 1e-6 < tol < math.pi / 2 else np.inf
    for i in range(k, m - k):
        if cid[i - k] != cid[i] or cid[i + k] != cid[i]:
            continue
        v1x, v1y = p[i - k, 0] - p[i, 0], p[i - k, 1] - p[i, 1]
        v2x, v2y = p[i + k, 0] - p[i, 0], p[i + k, 1] - p[i, 1]
        cross, dot = v1x * v2y - v1y * v2x, v1x * v2x + v1y * v2y
        # the angle is within tol of +-90 deg only if |cos| = |dot| / |v1||v2| < sin(tol):
        # far from it (with a margin far above rounding), skip the atan2
        if dot * dot > near_square * (dot * dot + cross * cross):
            continue
        ang = math.atan2(cross, dot)
        dev_in = abs(ang + math.pi / 2)
        dev_out = abs(ang - math.pi / 2)
        dev = min(dev_in, dev_out)
        if not dev < tol:
            continue
        if i != last_hit + 1:  # a new run of hits: a new corner
            out[n] = i
            inner[n] = dev_in < dev_out
            best_dev = dev
            n += 1
        elif dev < best_dev:  # the same run: keep its point closest to +-90 deg
            out[n - 1] = i
            inner[n - 1] = dev_in < dev_out
            best_dev = dev
        last_hit = i
    return out[:n].copy(), inner[:n].copy()


def vector_corners(scan: ScanPoints, params: CornerParams, spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """(V, 2) corners (robot frame) and (V,) bool: inner (concave) or not (outer)."""
    p = scan.points
    k = max(1, int(round(params.vector_step / max(spacing, 1e-3))))
    if len(p) < 2 * k + 1:
        return np.zeros((0, 2)), np.zeros(0, dtype=bool)
    idx, inner = _vectors(np.ascontiguousarray(p, dtype=np.float64), np.ascontiguousarray(scan.clusters, dtype=np.int64),
                          k, float(params.vector_tolerance))
    return p[idx], inner
