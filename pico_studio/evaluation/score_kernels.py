"""Truth scoring's compiled loops: length-weighted wall coverage, nearest-vertex distances,
corners paired one to one and doors matched to openings (`frame_score.score_arrays`).

Wall coverage (a wall score's precision or recall): every segment of `segments` is sampled
about `step` apart — n = max(ceil(L / step), 1) samples at t = (k + 1/2) / n, each weighing
L / n metres — and a sample counts as covered when some segment of `targets` lies within
`wall_distance` of it and runs within `wall_angle` of the sampled segment's direction u:

    |u . (b - a) / |b - a|| >= cos(wall_angle)   and   |p - (a + t* (b - a))| <= wall_distance,
    t* = clip((p - a) . (b - a) / |b - a|^2, 0, 1)

(the point-to-segment distance, tested only inside the target's box grown by the distance).
Returned: the total sampled length and the covered length. One loop over samples and
targets, no (samples x targets) arrays: the targets a segment's samples can match (parallel
enough, their grown box meeting the segment's) are picked once per segment, and for each of
them only the run of samples that can lie in its box is tested.

Pairing (`match_nearest`): greedy, nearest first — of all pairs within the radius, sorted by
distance, a pair is taken unless one of its points is taken already. Door matches
(`geometry.door_matches`, the combined map's test too): middles within a distance and
directions within an angle.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel, njit


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
    near = np.empty(m, dtype=np.int64)  # the targets a segment's samples can match
    hair = 1e-9  # a sample lies in its segment's box up to rounding
    r2_in, r2_out = r * r * (1 - 1e-9), r * r * (1 + 1e-9)
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
        # broad phase, once per segment: targets parallel enough whose grown box meets the
        # segment's box (a sample outside it cannot be inside theirs)
        s_lo_x, s_hi_x = min(ax, segments[i, 2]) - hair, max(ax, segments[i, 2]) + hair
        s_lo_y, s_hi_y = min(ay, segments[i, 3]) - hair, max(ay, segments[i, 3]) + hair
        n_near = 0
        for j in range(m):
            if s_hi_x < lo_x[j] or s_lo_x > hi_x[j] or s_hi_y < lo_y[j] or s_lo_y > hi_y[j]:
                continue
            if abs(ux * tx[j] + uy * ty[j]) < cos_angle:
                continue
            near[n_near] = j
            n_near += 1
        # narrow phase, per near target: only the run of samples that can lie in its box
        covered = np.zeros(n, dtype=np.bool_)
        for q in range(n_near):
            j = near[q]
            x_first, x_last = _samples_within(ax, dx, lo_x[j], hi_x[j], n)
            y_first, y_last = _samples_within(ay, dy, lo_y[j], hi_y[j], n)
            for k in range(max(x_first, y_first), min(x_last, y_last) + 1):
                if covered[k]:
                    continue
                t = (k + 0.5) / n
                px, py = ax + t * dx, ay + t * dy
                if px < lo_x[j] or px > hi_x[j] or py < lo_y[j] or py > hi_y[j]:
                    continue
                qx, qy = px - targets[j, 0], py - targets[j, 1]
                abx, aby = targets[j, 2] - targets[j, 0], targets[j, 3] - targets[j, 1]
                s = min(max((qx * abx + qy * aby) / len2[j], 0.0), 1.0)
                ex, ey = qx - s * abx, qy - s * aby
                e2 = ex * ex + ey * ey
                # the squared distance settles all but a hair around r, where the rounding of
                # either could differ: only there the exact |e| <= r (math.hypot is slow)
                covered[k] = e2 < r2_in or (e2 <= r2_out and math.hypot(ex, ey) <= r)
        for k in range(n):  # summed sample by sample, in order
            total += w
            if covered[k]:
                ok += w
    return total, ok


@njit
def _samples_within(a: float, d: float, lo: float, hi: float, n: int) -> tuple[int, int]:
    """(first, last) sample k of n whose coordinate a + (k + 1/2) / n d can lie in [lo, hi]:
    k + 1/2 = n (c - a) / d solved at c = lo and c = hi, two samples wider each side for the
    rounding of both (a coordinate's rounding, ~1e-13 m, moves k by 1e-13 n / |d|); every
    sample when |d| < 1 mm (then the other coordinate narrows the run)."""
    if abs(d) < 1e-3:
        return 0, n - 1
    u0, u1 = (lo - a) / d * n - 0.5, (hi - a) / d * n - 0.5
    if d < 0:
        u0, u1 = u1, u0
    first = max(min(math.floor(u0) - 2.0, float(n)), -1.0)
    last = max(min(math.ceil(u1) + 2.0, float(n)), -1.0)
    return max(int(first), 0), min(int(last), n - 1)


def _nearest_example() -> tuple:
    return np.array([[0.0, 0.0], [1.0, 1.0]]), np.array([[0.1, 0.0], [2.0, 2.0], [1.0, 0.9]])


@kernel(_nearest_example)
def nearest_distances(points: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """(N,) distance from every point (N, 2) to the nearest of `vertices` (V, 2), V >= 1: the
    nearest by squared distance first (no square root), then np.hypot of the vertices within
    a hair of it (rounding can reorder only those), so the answer is the minimum of np.hypot."""
    out = np.empty(points.shape[0])
    d2 = np.empty(vertices.shape[0])
    for i in range(points.shape[0]):
        px, py = points[i, 0], points[i, 1]
        least = np.inf
        for j in range(vertices.shape[0]):
            dx, dy = px - vertices[j, 0], py - vertices[j, 1]
            d2[j] = dx * dx + dy * dy
            least = min(least, d2[j])
        best = np.inf
        for j in range(vertices.shape[0]):
            if d2[j] <= least * (1 + 1e-9):
                best = min(best, np.hypot(px - vertices[j, 0], py - vertices[j, 1]))
        out[i] = best
    return out


def _match_example() -> tuple:
    return np.array([[0.0, 0.0], [1.0, 1.0]]), np.array([[0.1, 0.0], [2.0, 2.0], [1.0, 0.9]]), 0.15


@kernel(_match_example)
def match_nearest(a: np.ndarray, b: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """One-to-one pairs (ia[k], ib[k]) of points a (A, 2) and b (B, 2), nearest first, with
    |a_i - b_j| <= radius: every pair within the radius, sorted by distance (stably: equal
    distances in (i, j) order), taken unless i or j is already paired."""
    nb = b.shape[0]
    dist = np.empty(a.shape[0] * nb)
    flat = np.empty(a.shape[0] * nb, dtype=np.int64)
    n = 0
    beyond = radius * radius * (1 + 1e-9)  # surely farther than the radius (np.hypot is slow)
    for i in range(a.shape[0]):
        for j in range(nb):
            dx, dy = a[i, 0] - b[j, 0], a[i, 1] - b[j, 1]
            if dx * dx + dy * dy > beyond:
                continue
            d = np.hypot(dx, dy)
            if d <= radius:
                dist[n] = d
                flat[n] = i * nb + j
                n += 1
    order = np.argsort(dist[:n], kind="mergesort")
    used_a = np.zeros(a.shape[0], dtype=np.bool_)
    used_b = np.zeros(nb, dtype=np.bool_)
    ia = np.empty(min(a.shape[0], nb), dtype=np.int64)
    ib = np.empty(min(a.shape[0], nb), dtype=np.int64)
    pairs = 0
    for k in order:
        i, j = flat[k] // nb, flat[k] % nb
        if used_a[i] or used_b[j]:
            continue
        used_a[i] = used_b[j] = True
        ia[pairs], ib[pairs] = i, j
        pairs += 1
    return ia[:pairs], ib[:pairs]
