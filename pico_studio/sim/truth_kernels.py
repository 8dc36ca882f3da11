"""The truth's compiled loops: how much of the walls at each door jamb the scan's beams hit,
which map vertices are corners as seen from the robot, and whether a corner or a door's middle
is in view.

Jamb seen length (`sim.truth.GroundTruth.jamb_seen_length`). A wall w = a + u (b - a),
u in [0, 1], *touches* jamb p when its point-to-segment distance is at most `touch`:

    u* = clip((p - a) . (b - a) / |b - a|^2, 0, 1),   |a + u* (b - a) - p| <= touch.

Every beam end point q that hit a touching wall k and lies within `reach` of p is placed
along that wall, s = (q - a_k) . (b_k - a_k) / |b_k - a_k|; the jamb's seen length is the
sum over those walls, in increasing k, of max s - min s. One pass over the beams for all jambs.

Corner classes (`sim.map_features.classify_corners`). At each candidate vertex V the
directions of the segments leaving it, taken relative to the direction towards the viewpoint
R and wrapped to [0, 2 pi), cut the plane into sectors; R lies in the one from the largest
(as a negative angle) to the smallest: w = min + (2 pi - max); a single direction gives
w = 2 pi. |w - pi| <= tol: straight on, not a corner; w > pi: convex; else concave.

In view (`GroundTruth._in_view`, the corners and door middles of a frame): a point p seen
from the laser at (x, y, a), d = p - (x, y), is in view when

    |d| <= range_max,   angle_min <= wrap(atan2(d_y, d_x) - a) <= angle_max,
    free length along d / |d|  >=  |d| - tolerance

(within range and field of view, and nothing solid more than `tolerance` before it), the free
length by `json_map.openings.cast_rays`' ray-segment test: with p1 = a - o, e = b - a and
den = c e_y - s e_x, the ray (c, s) meets segment a b at t = (p1 x e) / den when t >= 0 and
u = (p1 x (c, s)) / den lies in [0, 1]. One pass over the points, a ray cast only for those in
the field of view, without `cast_rays`' (rays x segments) arrays.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel, njit


def _jamb_example() -> tuple:
    walls = np.array([[0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 1.0, 1.0]])
    ranges = np.array([0.5, 0.7, np.inf])
    return (np.array([[1.0, 0.0]]), 0.5, 0.5, 0.0, -1.6, 0.8, ranges, np.array([0, 1, -1], dtype=np.int64),
            walls, 0.16, 0.6)


@kernel(_jamb_example)
def jamb_seen_lengths(jambs: np.ndarray, x: float, y: float, a: float, angle_min: float, increment: float,
                      ranges: np.ndarray, hits: np.ndarray, walls: np.ndarray, touch: float, reach: float) -> np.ndarray:
    """(J,) seen length at each jamb (J, 2) from a scan taken at (x, y, a) (`ranges` (B,))
    and the wall each beam hit, `hits` (B,) (an index into `walls` (W, 4); anything else: not
    a wall). First the jambs touching each wall (wall k's: `by_wall[first[k]:first[k + 1]]`),
    then one pass over the beams: a beam on a wall no jamb touches (most of them) costs one
    look-up, and a beam whose length differs from the jamb's distance by more than `reach`
    ends farther than that from it (|q - p| >= | |q - o| - |p - o| |), as does a beam more
    than asin(reach / |p - o|) off the jamb's direction: only the rest need their end point."""
    n_jambs, n_walls = jambs.shape[0], walls.shape[0]
    touching = np.zeros((n_walls, n_jambs), dtype=np.bool_)
    for j in range(n_jambs):
        px, py = jambs[j, 0], jambs[j, 1]
        for k in range(n_walls):
            ax, ay, bx, by = walls[k, 0], walls[k, 1], walls[k, 2], walls[k, 3]
            # a wall within `touch` of p has p inside its box grown by `touch` (and a hair,
            # for the rounding of the exact test): most walls are ruled out by that
            grow = touch + 1e-9
            if px < min(ax, bx) - grow or px > max(ax, bx) + grow or py < min(ay, by) - grow or py > max(ay, by) + grow:
                continue
            abx, aby = bx - ax, by - ay
            len2 = max(abx * abx + aby * aby, 1e-18)
            u = min(max(((px - ax) * abx + (py - ay) * aby) / len2, 0.0), 1.0)
            touching[k, j] = np.hypot(ax + u * abx - px, ay + u * aby - py) <= touch
    first = np.zeros(n_walls + 1, dtype=np.int64)
    for k in range(n_walls):
        first[k + 1] = first[k]
        for j in range(n_jambs):
            first[k + 1] += touching[k, j]
    by_wall = np.empty(first[n_walls], dtype=np.int64)
    for k in range(n_walls):
        at = first[k]
        for j in range(n_jambs):
            if touching[k, j]:
                by_wall[at] = j
                at += 1
    far = np.empty(n_jambs)  # |p - o|, from the laser
    bearing = np.empty(n_jambs)  # the direction of p from the laser
    spread = np.empty(n_jambs)  # a beam farther off that direction passes p beyond `reach`
    for j in range(n_jambs):
        far[j] = np.hypot(jambs[j, 0] - x, jambs[j, 1] - y)
        bearing[j] = math.atan2(jambs[j, 1] - y, jambs[j, 0] - x)
        # (a hair wider for the rounding of the end points; near the laser every direction)
        spread[j] = math.asin(reach / far[j]) + 1e-9 if far[j] > reach else 4.0
    reach2_in, reach2_out = reach * reach * (1 - 1e-9), reach * reach * (1 + 1e-9)
    lo = np.full((n_jambs, n_walls), np.inf)  # the stretch of wall k hit near jamb j
    hi = np.full((n_jambs, n_walls), -np.inf)
    for b in range(hits.shape[0]):
        k = hits[b]
        if k < 0 or k >= n_walls or first[k] == first[k + 1]:
            continue
        r = ranges[b]
        qx = qy = np.nan  # the end point, computed once when needed
        for at in range(first[k], first[k + 1]):
            j = by_wall[at]
            if abs(r - far[j]) > reach + 1e-9:  # (a hair for the rounding of q)
                continue
            off = angle_min + b * increment + a - bearing[j]
            if abs(off - 2 * math.pi * math.floor(off / (2 * math.pi) + 0.5)) > spread[j]:
                continue
            if np.isnan(qx):
                qx, qy = _beam_end(x, y, a, angle_min, increment, r, b)
            dx, dy = qx - jambs[j, 0], qy - jambs[j, 1]
            # |d| <= reach by its square, except within a hair of reach where the rounding of
            # either could differ: there the exact np.hypot (slow)
            d2 = dx * dx + dy * dy
            if d2 > reach2_out or (d2 >= reach2_in and np.hypot(dx, dy) > reach):
                continue
            ax, ay = walls[k, 0], walls[k, 1]
            abx, aby = walls[k, 2] - ax, walls[k, 3] - ay
            s = ((qx - ax) * abx + (qy - ay) * aby) / math.sqrt(max(abx * abx + aby * aby, 1e-18))
            lo[j, k] = min(lo[j, k], s)
            hi[j, k] = max(hi[j, k], s)
    out = np.zeros(n_jambs)
    for j in range(n_jambs):
        total = 0.0
        for k in range(n_walls):
            if hi[j, k] >= lo[j, k]:
                total += hi[j, k] - lo[j, k]
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


def _in_view_example() -> tuple:
    segs = np.array([[1.0, -1.0, 1.0, 1.0], [-1.0, 1.0, -1.0, -1.0]])
    return np.array([[2.0, 0.0], [0.5, 0.5]]), 0.0, 0.0, 0.0, 10.0, -2.0, 2.0, segs, 0.05


@kernel(_in_view_example)
def in_view(points: np.ndarray, x: float, y: float, a: float, range_max: float, angle_min: float,
            angle_max: float, segments: np.ndarray, tolerance: float) -> np.ndarray:
    """(P,) bool: each point (P, 2) within range and field of view of the laser at (x, y, a)
    and not occluded by `segments` (N, 4) more than `tolerance` before it.

    Occluded: the ray towards p, (c, s) = d / |d|, meets a segment at some t < |d| - tolerance
    (the free length is below that). Such a hit lies between the laser and p and on the
    segment, so only segments whose box meets the box of the laser and p (grown by a hair for
    rounding) are tested, and the first hit settles it."""
    n = segments.shape[0]
    lo_x, lo_y, hi_x, hi_y = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    for k in range(n):
        lo_x[k], hi_x[k] = min(segments[k, 0], segments[k, 2]), max(segments[k, 0], segments[k, 2])
        lo_y[k], hi_y[k] = min(segments[k, 1], segments[k, 3]), max(segments[k, 1], segments[k, 3])
    hair = 1e-6
    out = np.zeros(points.shape[0], dtype=np.bool_)
    for i in range(points.shape[0]):
        px, py = points[i, 0], points[i, 1]
        dx, dy = px - x, py - y
        dist = np.hypot(dx, dy)
        bearing = np.mod(math.atan2(dy, dx) - a + math.pi, 2 * math.pi) - math.pi
        if not (dist <= range_max and bearing >= angle_min and bearing <= angle_max):
            continue
        if dist <= tolerance:  # free lengths are >= 0: nothing can be before it
            out[i] = True
            continue
        c, s = dx / dist, dy / dist
        limit = dist - tolerance
        box_lo_x, box_hi_x = min(x, px) - hair, max(x, px) + hair
        box_lo_y, box_hi_y = min(y, py) - hair, max(y, py) + hair
        blocked = False
        for k in range(n):
            if lo_x[k] > box_hi_x or hi_x[k] < box_lo_x or lo_y[k] > box_hi_y or hi_y[k] < box_lo_y:
                continue
            p1x, p1y = segments[k, 0] - x, segments[k, 1] - y
            sx, sy = segments[k, 2] - segments[k, 0], segments[k, 3] - segments[k, 1]
            den = c * sy - s * sx
            t = (p1x * sy - p1y * sx) / den
            u = (p1x * s - p1y * c) / den
            if t >= 0.0 and u >= 0.0 and u <= 1.0 and t < limit:
                blocked = True
                break
        out[i] = not blocked
    return out



def _corners_example() -> tuple:
    segs = np.array([[1.0, -1.0, 1.0, 1.0], [-1.0, 1.0, -1.0, -1.0]])
    return (np.array([[2.0, 0.0], [0.5, 0.5], [0.2, -0.1]]), np.array([1, 2], dtype=np.int64),
            np.array([True, False]), np.array([False, False]), 0.0, 0.0, 0.0, 10.0, -2.0, 2.0, segs, 0.05)


@kernel(_corners_example)
def corners_in_view(points: np.ndarray, idx: np.ndarray, convex: np.ndarray, loose: np.ndarray, x: float, y: float,
                    a: float, range_max: float, angle_min: float, angle_max: float, segments: np.ndarray,
                    tolerance: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The corners `points[idx]` (with their `convex` and `loose` flags) that are `in_view`:
    (C, 2), (C,), (C,) — the gather, the test and the selection in one call."""
    pts = np.empty((idx.shape[0], 2))
    for i in range(idx.shape[0]):
        pts[i, 0], pts[i, 1] = points[idx[i], 0], points[idx[i], 1]
    seen = in_view(pts, x, y, a, range_max, angle_min, angle_max, segments, tolerance)
    n = 0
    for i in range(seen.shape[0]):
        n += seen[i]
    out = np.empty((n, 2))
    out_convex = np.empty(n, dtype=np.bool_)
    out_loose = np.empty(n, dtype=np.bool_)
    k = 0
    for i in range(seen.shape[0]):
        if seen[i]:
            out[k, 0], out[k, 1] = pts[i, 0], pts[i, 1]
            out_convex[k], out_loose[k] = convex[i], loose[i]
            k += 1
    return out, out_convex, out_loose

@njit
def _beam_end(x: float, y: float, a: float, angle_min: float, increment: float, r: float, i: int) -> tuple[float, float]:
    """The map-frame end of beam i, r long, of a scan taken at (x, y, a): at angle
    angle_min + i increment + a (r inf: no hit, at infinity)."""
    angle = angle_min + i * increment + a
    return x + r * math.cos(angle), y + r * math.sin(angle)


def _beam_example() -> tuple:
    return 1.0, 2.0, 0.5, -2.0, 0.5, np.array([1.0, np.inf, 2.0, 3.0])


@kernel(_beam_example)
def beam_ends(x: float, y: float, a: float, angle_min: float, increment: float, ranges: np.ndarray) -> np.ndarray:
    """(B, 2) map-frame end points of a scan's beams (`ranges` (B,)) taken at (x, y, a)."""
    out = np.empty((ranges.shape[0], 2))
    for i in range(ranges.shape[0]):
        out[i, 0], out[i, 1] = _beam_end(x, y, a, angle_min, increment, ranges[i], i)
    return out


def _pieces_example() -> tuple:
    return 0.0, 0.0, 0.0, -1.0, 0.5, np.array([1.0, 1.0, 1.0, np.inf]), np.array([0, 0, 0, -1], dtype=np.int64), 2


@kernel(_pieces_example)
def hit_runs(x: float, y: float, a: float, angle_min: float, increment: float, ranges: np.ndarray,
             hits: np.ndarray, min_beams: int) -> tuple[np.ndarray, np.ndarray]:
    """The runs of consecutive beams of a scan (taken at (x, y, a), `ranges` (B,)) on one
    segment (`hits` (B,), -1: none), at least `min_beams` long: (R, 4) from the first beam's
    end point to the last's, and (R,) the segment of each."""
    n = hits.shape[0]
    pieces = np.empty((n, 4))
    sources = np.empty(n, dtype=np.int64)
    count = 0
    start = 0
    for i in range(1, n + 1):
        if i < n and hits[i] == hits[start]:
            continue
        if hits[start] >= 0 and i - start >= min_beams:  # the run start .. i - 1
            pieces[count, 0], pieces[count, 1] = _beam_end(x, y, a, angle_min, increment, ranges[start], start)
            pieces[count, 2], pieces[count, 3] = _beam_end(x, y, a, angle_min, increment, ranges[i - 1], i - 1)
            sources[count] = hits[start]
            count += 1
        start = i
    return pieces[:count].copy(), sources[:count].copy()
