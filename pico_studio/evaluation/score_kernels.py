"""Truth scoring's compiled loops: length-weighted wall coverage and nearest-vertex distances.

Wall coverage (a wall score's precision or recall): every segment of `segments` is sampled
about `step` apart — n = max(ceil(L / step), 1) samples at t = (k + 1/2) / n, each weighing
L / n metres — and a sample counts as covered when some segment of `targets` lies within
`wall_distance` of it and runs within `wall_angle` of the sampled segment's direction u:

    |u . (b - a) / |b - a|| >= cos(wall_angle)   and   |p - (a + t* (b - a))| <= wall_distance,
    t* = clip((p - a) . (b - a) / |b - a|^2, 0, 1)

(the point-to-segment distance, tested only inside the target's box grown by the distance).
Returned: the total sampled length and the covered length. One loop over samples and
targets, no (samples x targets) arrays.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel


def _coverage_example() -> tuple:
    segs = np.array([[0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 1.0, 1.0]])
    return segs, 0.02, segs + 0.01, 0.1, math.cos(0.2)


@kernel(_coverage_example)
def wall_coverage(segments: np.ndarray, step: float, targets: np.ndarray, wall_distance: float,
                  cos_angle: float) -> tuple[float, float]:
    """(sampled length, covered length) of `segments` (N, 4) against `targets` (M, 4)."""
    m = targets.shape[0]
    # per target: its box grown by the distance, its direction, |b - a|^2
    lo_x = np.empty(m)
    lo_y = np.empty(m)
    hi_x = np.empty(m)
    hi_y = np.empty(m)
    tx = np.empty(m)
    ty = np.empty(m)
    len2 = np.empty(m)
    r = wall_distance
    for j in range(m):
        ax, ay, bx, by = targets[j, 0], targets[j, 1], targets[j, 2], targets[j, 3]
        lo_x[j], hi_x[j] = min(ax, bx) - r, max(ax, bx) + r
        lo_y[j], hi_y[j] = min(ay, by) - r, max(ay, by) + r
        abx, aby = bx - ax, by - ay
        len2[j] = max(abx * abx + aby * aby, 1e-18)
        norm = math.sqrt(len2[j])
        tx[j], ty[j] = abx / norm, aby / norm
    total = 0.0
    ok = 0.0
    for i in range(segments.shape[0]):
        ax, ay = segments[i, 0], segments[i, 1]
        dx, dy = segments[i, 2] - ax, segments[i, 3] - ay
        length = math.hypot(dx, dy)
        n = max(int(math.ceil(length / step)), 1)
        w = length / n
        unorm = max(length, 1e-12)
        ux, uy = dx / unorm, dy / unorm
        for k in range(n):
            t = (k + 0.5) / n
            px, py = ax + t * dx, ay + t * dy
            total += w
            for j in range(m):
                if px < lo_x[j] or px > hi_x[j] or py < lo_y[j] or py > hi_y[j]:
                    continue
                if abs(ux * tx[j] + uy * ty[j]) < cos_angle:
                    continue
                qx, qy = px - targets[j, 0], py - targets[j, 1]
                abx, aby = targets[j, 2] - targets[j, 0], targets[j, 3] - targets[j, 1]
                s = min(max((qx * abx + qy * aby) / len2[j], 0.0), 1.0)
                if math.hypot(qx - s * abx, qy - s * aby) <= r:
                    ok += w
                    break
    return total, ok


def _nearest_example() -> tuple:
    return np.array([[0.0, 0.0], [1.0, 1.0]]), np.array([[0.1, 0.0], [2.0, 2.0], [1.0, 0.9]])


@kernel(_nearest_example)
def nearest_distances(points: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """(N,) distance from every point (N, 2) to the nearest of `vertices` (V, 2), V >= 1."""
    out = np.empty(points.shape[0])
    for i in range(points.shape[0]):
        best = np.inf
        for j in range(vertices.shape[0]):
            best = min(best, math.hypot(points[i, 0] - vertices[j, 0], points[i, 1] - vertices[j, 1]))
        out[i] = best
    return out
