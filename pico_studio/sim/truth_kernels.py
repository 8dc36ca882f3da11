"""The truth's compiled loops: how much of the walls at each door jamb the scan's beams hit,
which map vertices are corners as seen from the robot, and how far rays run free (whether a
corner or a door's middle is in view).

Jamb seen length (`sim.truth.GroundTruth.jamb_seen_length`). A wall w = a + u (b - a),
u in [0, 1], *touches* jamb p when its point-to-segment distance is at most `touch`:

    u* = clip((p - a) . (b - a) / |b - a|^2, 0, 1),   |a + u* (b - a) - p| <= touch.

Every beam end point q that hit a touching wall k and lies within `reach` of p is placed
along that wall, s = (q - a_k) . (b_k - a_k) / |b_k - a_k|; the jamb's seen length is the
sum over those walls, in increasing k, of max s - min s. One pass over the beams per jamb.

Corner classes (`sim.map_features.classify_corners`). At each candidate vertex V the
directions of the segments leaving it, taken relative to the direction towards the viewpoint
R and wrapped to [0, 2 pi), cut the plane into sectors; R lies in the one from the largest
(as a negative angle) to the smallest: w = min + (2 pi - max); a single direction gives
w = 2 pi. |w - pi| <= tol: straight on, not a corner; w > pi: convex; else concave.

Free lengths (`GroundTruth._in_view`): `raycast.cast_rays`'s ray-segment test, one ray at a
time, without its (rays x segments) arrays; the rays' cosines and sines come from numpy, so
the answers are those of `cast_rays`.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel


def _jamb_example() -> tuple:
    walls = np.array([[0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 1.0, 1.0]])
    xy = np.array([[0.5, 0.0], [1.0, 0.5], [9.0, 9.0]])
    return np.array([[1.0, 0.0]]), xy, np.array([0, 1, -1], dtype=np.int64), walls, 0.16, 0.6


@kernel(_jamb_example)
def jamb_seen_lengths(jambs: np.ndarray, xy: np.ndarray, hits: np.ndarray, walls: np.ndarray,
                      touch: float, reach: float) -> np.ndarray:
    """(J,) seen length at each jamb (J, 2) from beam end points `xy` (B, 2) and the wall each
    hit `hits` (B,) (an index into `walls` (W, 4); anything else: not a wall)."""
    n_walls = walls.shape[0]
    out = np.zeros(jambs.shape[0])
    touching = np.zeros(n_walls, dtype=np.bool_)
    lo = np.empty(n_walls)
    hi = np.empty(n_walls)
    for j in range(jambs.shape[0]):
        px, py = jambs[j, 0], jambs[j, 1]
        for k in range(n_walls):
            ax, ay = walls[k, 0], walls[k, 1]
            abx, aby = walls[k, 2] - ax, walls[k, 3] - ay
            len2 = max(abx * abx + aby * aby, 1e-18)
            u = min(max(((px - ax) * abx + (py - ay) * aby) / len2, 0.0), 1.0)
            touching[k] = np.hypot(ax + u * abx - px, ay + u * aby - py) <= touch
            lo[k] = np.inf
            hi[k] = -np.inf
        for b in range(hits.shape[0]):
            k = hits[b]
            if k < 0 or k >= n_walls or not touching[k]:
                continue
            qx, qy = xy[b, 0], xy[b, 1]
            if np.hypot(qx - px, qy - py) > reach:
                continue
            ax, ay = walls[k, 0], walls[k, 1]
            abx, aby = walls[k, 2] - ax, walls[k, 3] - ay
            s = ((qx - ax) * abx + (qy - ay) * aby) / math.sqrt(max(abx * abx + aby * aby, 1e-18))
            lo[k] = min(lo[k], s)
            hi[k] = max(hi[k], s)
        total = 0.0
        for k in range(n_walls):
            if hi[k] >= lo[k]:
                total += hi[k] - lo[k]
        out[j] = total
    return out


def _corner_example() -> tuple:
    points = np.array([[0.0, 0.0], [1.0, 0.0]])
    return (points, np.array([0, 1], dtype=np.int64), np.array([0, 2, 3], dtype=np.int64),
            np.array([0.0, math.pi / 2, math.pi]), 2.0, 1.0, 0.15)


@kernel(_corner_example)
def corner_classes(points: np.ndarray, candidates: np.ndarray, starts: np.ndarray, directions: np.ndarray,
                   vx: float, vy: float, straight_tolerance: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(kept candidates, convex, loose end) as seen from (vx, vy). Candidate i's directions are
    `directions[starts[i]:starts[i + 1]]` (at least one each)."""
    n = candidates.shape[0]
    idx = np.empty(n, dtype=np.int64)
    convex = np.empty(n, dtype=np.bool_)
    loose = np.empty(n, dtype=np.bool_)
    two_pi = 2 * math.pi
    kept = 0
    for i in range(n):
        v = candidates[i]
        first, stop = starts[i], starts[i + 1]
        if stop - first == 1:
            w = two_pi
        else:
            toward = math.atan2(vy - points[v, 1], vx - points[v, 0])
            smallest, largest = np.inf, -np.inf
            for d in range(first, stop):
                rel = np.mod(directions[d] - toward, two_pi)
                smallest = min(smallest, rel)
                largest = max(largest, rel)
            w = smallest + (two_pi - largest)
        if abs(w - math.pi) <= straight_tolerance:
            continue
        idx[kept] = v
        convex[kept] = w > math.pi
        loose[kept] = stop - first == 1
        kept += 1
    return idx[:kept], convex[:kept], loose[:kept]


def _free_example() -> tuple:
    segs = np.array([[1.0, -1.0, 1.0, 1.0], [-1.0, 1.0, -1.0, -1.0]])
    return 0.0, 0.0, np.array([1.0, 0.0]), np.array([0.0, 1.0]), segs


@kernel(_free_example)
def free_lengths(ox: float, oy: float, cos_a: np.ndarray, sin_a: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """(K,) distance from (ox, oy) along each ray (cos_a, sin_a) to the nearest of `segments`
    (N, 4), inf where none: `raycast.cast_rays`'s test, ray by ray. With p1 = a - o, d = b - a
    and den = c d_y - s d_x, the ray meets the segment at t = (p1 x d) / den when t >= 0 and
    u = (p1 x (c, s)) / den lies in [0, 1]."""
    out = np.empty(cos_a.shape[0])
    for i in range(cos_a.shape[0]):
        c, s = cos_a[i], sin_a[i]
        best = np.inf
        for k in range(segments.shape[0]):
            p1x, p1y = segments[k, 0] - ox, segments[k, 1] - oy
            dx, dy = segments[k, 2] - segments[k, 0], segments[k, 3] - segments[k, 1]
            den = c * dy - s * dx
            t = (p1x * dy - p1y * dx) / den
            u = (p1x * s - p1y * c) / den
            if t >= 0.0 and u >= 0.0 and u <= 1.0 and t < best:
                best = t
        out[i] = best
    return out
