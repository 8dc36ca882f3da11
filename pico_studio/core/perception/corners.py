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
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config.perception_params import CornerParams
from pico_studio.core.perception.scan import ScanPoints


def spike_corners(scan: ScanPoints, params: CornerParams) -> np.ndarray:
    """(K, 2) outer corners, robot frame."""
    p = scan.points
    if len(p) < 2:
        return np.zeros((0, 2))
    r = np.hypot(p[:, 0], p[:, 1])
    gap = np.hypot(*np.diff(p, axis=0).T)
    nearer = np.where(r[:-1] <= r[1:], np.arange(len(p) - 1), np.arange(1, len(p)))
    hit = (gap > params.spike_gap) & (r[nearer] < params.spike_max_range)
    near = nearer[hit]  # non-decreasing: drop repeats instead of sorting (np.unique)
    if len(near) > 1:
        near = near[np.concatenate([[True], near[1:] != near[:-1]])]
    return p[near]


def vector_corners(scan: ScanPoints, params: CornerParams, spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """(V, 2) corners (robot frame) and (V,) bool: inner (concave) or not (outer)."""
    p = scan.points
    m = len(p)
    k = max(1, int(round(params.vector_step / max(spacing, 1e-3))))
    if m < 2 * k + 1:
        return np.zeros((0, 2)), np.zeros(0, dtype=bool)
    cid = np.repeat(np.arange(len(scan.clusters)), scan.clusters[:, 1] - scan.clusters[:, 0])
    i = np.arange(k, m - k)
    # slices, not index arrays: point i against its neighbours i - k and i + k
    mid = cid[k : m - k]
    same = (cid[: m - 2 * k] == mid) & (cid[2 * k :] == mid)
    pi = p[k : m - k]
    v1 = p[: m - 2 * k] - pi
    v2 = p[2 * k :] - pi
    ang = np.arctan2(v1[:, 0] * v2[:, 1] - v1[:, 1] * v2[:, 0], (v1 * v2).sum(axis=1))
    dev_in = np.abs(ang + math.pi / 2)
    dev_out = np.abs(ang - math.pi / 2)
    dev = np.minimum(dev_in, dev_out)
    hit = same & (dev < params.vector_tolerance)
    if not hit.any():
        return np.zeros((0, 2)), np.zeros(0, dtype=bool)
    h = np.flatnonzero(hit)
    run = np.concatenate([[0], np.cumsum(np.diff(h) > 1)])
    order = np.lexsort((dev[h], run))
    first = order[np.concatenate([[True], np.diff(run[order]) > 0])]
    best = h[first]
    return p[i[best]], dev_in[best] < dev_out[best]
