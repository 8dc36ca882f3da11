"""Merge's compiled loops: near pairs, and connecting wall ends into corners (merge.py's maths).

Near pairs. Walls i != k whose bounding boxes, grown by r, overlap — in row order (i, then
k), as numpy's nonzero lists them: the only pairs that can merge or connect.

Corner candidates. For a pair (i, k) of walls from p_i with unit direction d_i and length
l_i, the lines cross where p_i + s d_i = p_k + u d_k:

    c = d_i x d_k,   s = (p_k - p_i) x d_k / c,   u = (p_k - p_i) x d_i / c

(c replaced by 1 when |c| <= 1e-9). The crossing's distance from i's nearer end is
|s - l_i| (end 1, s > l_i / 2) or |s| (end 0), likewise for k. The pair is an end-to-end
corner when |c| > sin(connect_min_angle) and both distances are below r; a T (i's end on
k's inside) when i's distance is below r and -r < u < l_k + r instead. Its cost: the two
distances, plus r for each tentative wall (seen fewer than `confirm_hits` times).

Connecting. Corners in order of cost, then T's in order of i's distance, each taking ends
still free: the corner is the crossing x = p_i + s d_i pulled towards the previous corner
(the mean of the two ends) by the end weight w = min(max(w_i, w_k), max_weight):
(w prev + x) / (w + 1); a T pulls i's end towards x alike. Ends read p_i from the walls as
they move, so a moved end moves later crossings (the order matters, as in the Python).
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel


def _example_walls() -> tuple:
    return np.array([[0.0, 0.0, 1.0, 0.0], [1.0, 0.05, 1.0, 1.0], [3.0, 3.0, 4.0, 3.0]]), 0.1


@kernel(_example_walls)
def near_pairs(walls: np.ndarray, r: float) -> tuple[np.ndarray, np.ndarray]:
    """Ordered pairs (i, k), i != k, whose bounding boxes grown by r overlap."""
    n = walls.shape[0]
    lo = np.empty((n, 2))
    hi = np.empty((n, 2))
    for i in range(n):
        for c in range(2):
            lo[i, c] = min(walls[i, c], walls[i, 2 + c]) - r
            hi[i, c] = max(walls[i, c], walls[i, 2 + c]) + r
    ia = np.empty(n * n, dtype=np.int64)
    ka = np.empty(n * n, dtype=np.int64)
    m = 0
    for i in range(n):
        for k in range(n):
            if (i != k and lo[i, 0] <= hi[k, 0] and lo[k, 0] <= hi[i, 0]
                    and lo[i, 1] <= hi[k, 1] and lo[k, 1] <= hi[i, 1]):
                ia[m], ka[m] = i, k
                m += 1
    return ia[:m].copy(), ka[:m].copy()


def _example_candidates() -> tuple:
    walls, r = _example_walls()
    ia, ka = np.array([0, 1], dtype=np.int64), np.array([1, 0], dtype=np.int64)
    return walls, ia, ka, np.array([1.0, 3.0, 2.0]), r, 0.5, 2.0


@kernel(_example_candidates)
def connect_candidates(walls: np.ndarray, ia: np.ndarray, ka: np.ndarray, hits: np.ndarray, r: float,
                       sin_min: float, confirm_hits: float) -> tuple:
    """Per pair: (directions d (W, 2), ends ei, ek (P,) int64, s (P,), i's distance (P,),
    cost (P,), end-to-end (P,) bool, T (P,) bool)."""
    n, p = walls.shape[0], ia.shape[0]
    d = np.empty((n, 2))
    length = np.empty(n)
    for i in range(n):
        dx, dy = walls[i, 2] - walls[i, 0], walls[i, 3] - walls[i, 1]
        length[i] = np.hypot(dx, dy)
        den = max(length[i], 1e-12)
        d[i, 0], d[i, 1] = dx / den, dy / den
    ei, ek = np.empty(p, dtype=np.int64), np.empty(p, dtype=np.int64)
    s_out, dist_out, cost = np.empty(p), np.empty(p), np.empty(p)
    end_end, t_join = np.empty(p, dtype=np.bool_), np.empty(p, dtype=np.bool_)
    for m in range(p):
        i, k = ia[m], ka[m]
        cross = d[i, 0] * d[k, 1] - d[i, 1] * d[k, 0]
        fx, fy = walls[k, 0] - walls[i, 0], walls[k, 1] - walls[i, 1]
        safe = cross if abs(cross) > 1e-9 else 1.0
        s = (fx * d[k, 1] - fy * d[k, 0]) / safe
        u = (fx * d[i, 1] - fy * d[i, 0]) / safe
        li, lk = length[i], length[k]
        ei[m] = 1 if s > li / 2 else 0
        ek[m] = 1 if u > lk / 2 else 0
        dist_i = abs(s - li) if ei[m] == 1 else abs(s)
        dist_k = abs(u - lk) if ek[m] == 1 else abs(u)
        sin_ok = abs(cross) > sin_min
        end_end[m] = sin_ok and dist_i < r and dist_k < r
        t_join[m] = sin_ok and dist_i < r and u > -r and u < lk + r and not end_end[m]
        weak_i = r if hits[i] < confirm_hits else 0.0
        weak_k = r if hits[k] < confirm_hits else 0.0
        cost[m] = dist_i + dist_k + weak_i + weak_k
        s_out[m], dist_out[m] = s, dist_i
    return d, ei, ek, s_out, dist_out, cost, end_end, t_join


def _example_walk() -> tuple:
    walls, _ = _example_walls()
    d = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 0.0]])
    one = np.array([0], dtype=np.int64)
    return (walls.copy(), d, np.zeros((3, 2)), np.zeros((3, 2), dtype=np.bool_), np.array([0, 1], dtype=np.int64),
            np.array([1, 0], dtype=np.int64), np.array([1, 0], dtype=np.int64), np.array([0, 1], dtype=np.int64),
            np.array([1.0, 0.05]), one, np.zeros(0, dtype=np.int64), 5.0)


@kernel(_example_walk)
def connect_walk(walls: np.ndarray, d: np.ndarray, old_weight: np.ndarray, seen: np.ndarray, ia: np.ndarray,
                 ka: np.ndarray, ei: np.ndarray, ek: np.ndarray, s: np.ndarray, pairs: np.ndarray,
                 tees: np.ndarray, cap: float) -> tuple[np.ndarray, np.ndarray]:
    """Connect the corners `pairs` then the T's `tees` (pair indices, in order), moving
    `walls` and clearing `seen` in place: (connected (W, 2) int64, end weights (W, 2))."""
    n = walls.shape[0]
    conn = np.full((n, 2), -1, dtype=np.int64)
    ew = np.zeros((n, 2))
    for m in pairs:
        i, k, a, b = ia[m], ka[m], ei[m], ek[m]
        if conn[i, a] >= 0 or conn[k, b] >= 0:
            continue
        xx, xy = walls[i, 0] + s[m] * d[i, 0], walls[i, 1] + s[m] * d[i, 1]
        px = (walls[i, 2 * a] + walls[k, 2 * b]) / 2
        py = (walls[i, 2 * a + 1] + walls[k, 2 * b + 1]) / 2
        wt = min(max(old_weight[i, a], old_weight[k, b]), cap)
        cx, cy = (wt * px + xx) / (wt + 1.0), (wt * py + xy) / (wt + 1.0)
        walls[i, 2 * a], walls[i, 2 * a + 1] = cx, cy
        walls[k, 2 * b], walls[k, 2 * b + 1] = cx, cy
        conn[i, a], conn[k, b] = k, i
        ew[i, a] = ew[k, b] = wt + 1.0
        seen[i, a] = seen[k, b] = False
    for m in tees:
        i, k, a = ia[m], ka[m], ei[m]
        if conn[i, a] >= 0:
            continue
        xx, xy = walls[i, 0] + s[m] * d[i, 0], walls[i, 1] + s[m] * d[i, 1]
        wt = min(old_weight[i, a], cap)
        walls[i, 2 * a] = (wt * walls[i, 2 * a] + xx) / (wt + 1.0)
        walls[i, 2 * a + 1] = (wt * walls[i, 2 * a + 1] + xy) / (wt + 1.0)
        conn[i, a] = k
        ew[i, a] = wt + 1.0
        seen[i, a] = False
    return conn, ew


def _example_fuse() -> tuple:
    walls = np.array([[0.0, 0.0, 1.0, 0.0], [1.0, 0.05, 1.0, 1.0]])
    seg = np.array([[1.2, 0.02, 0.1, 0.01]])
    real = np.array([[True, False]])
    return (walls, np.array([3.0, 1.0]), np.zeros(2, dtype=np.int64), np.zeros(2, dtype=np.int64),
            np.zeros((2, 2), dtype=np.bool_), np.array([0], dtype=np.int64), seg, real, real.copy(), 1, 5.0, 0.3)


@kernel(_example_fuse)
def fuse(walls: np.ndarray, hits: np.ndarray, last_seen: np.ndarray, missed: np.ndarray, seen_end: np.ndarray,
         idx: np.ndarray, seg: np.ndarray, real: np.ndarray, seen: np.ndarray, step: int, max_weight: float,
         gap: float) -> None:
    """Fuse new walls seg (K, 4) into local walls idx (K,) (distinct), in place.

    Each new wall is oriented like its old one (flipped when d_new . d_old < 0). With the
    old wall's weight w = min(hits, max_weight): the direction turns from the old one by
    atan2(d_old x d_new, d_old . d_new) / (w + 1), the line's offset rho (along the normal
    n) is the weighted mean (w n.mid_old + n.mid_new) / (w + 1). On that line, with old ends
    at a and new ends at b (positions along d from rho n), `beyond` says how far the new
    end reaches past the old one. A real new end (seen past, or a corner of the scan) no
    further than `gap` inside: it wins when past the old end by more than `gap` (or past a
    floating old end), else pulls the old end to (w a + b) / (w + 1). Any other new end only
    extends the wall."""
    for r in range(idx.shape[0]):
        i = idx[r]
        ox0, oy0, ox1, oy1 = walls[i, 0], walls[i, 1], walls[i, 2], walls[i, 3]
        lo = max(np.hypot(ox1 - ox0, oy1 - oy0), 1e-12)
        dox, doy = (ox1 - ox0) / lo, (oy1 - oy0) / lo
        nx0, ny0, nx1, ny1 = seg[r, 0], seg[r, 1], seg[r, 2], seg[r, 3]
        ln = max(np.hypot(nx1 - nx0, ny1 - ny0), 1e-12)
        dnx, dny = (nx1 - nx0) / ln, (ny1 - ny0) / ln
        real0, real1, seen0, seen1 = real[r, 0], real[r, 1], seen[r, 0], seen[r, 1]
        if dnx * dox + dny * doy < 0:
            nx0, ny0, nx1, ny1 = nx1, ny1, nx0, ny0
            dnx, dny = -dnx, -dny
            real0, real1, seen0, seen1 = real1, real0, seen1, seen0
        wo = min(hits[i], max_weight)
        da = np.arctan2(dox * dny - doy * dnx, dox * dnx + doy * dny)
        ang = np.arctan2(doy, dox) + da / (wo + 1.0)
        dx, dy = np.cos(ang), np.sin(ang)
        mx, my = -dy, dx
        rho = (wo * (mx * ((ox0 + ox1) / 2) + my * ((oy0 + oy1) / 2))
               + (mx * ((nx0 + nx1) / 2) + my * ((ny0 + ny1) / 2))) / (wo + 1.0)
        cx, cy = rho * mx, rho * my
        a0, a1 = (ox0 - cx) * dx + (oy0 - cy) * dy, (ox1 - cx) * dx + (oy1 - cy) * dy
        b0, b1 = (nx0 - cx) * dx + (ny0 - cy) * dy, (nx1 - cx) * dx + (ny1 - cy) * dy
        out = np.empty(2)
        for e in range(2):
            a, b = (a0, b0) if e == 0 else (a1, b1)
            beyond = (b - a) * (-1.0 if e == 0 else 1.0)
            old_seen = seen_end[i, e]
            blend = (wo * a + b) / (wo + 1.0)
            is_real = real0 if e == 0 else real1
            near_real = is_real and beyond > -gap
            take_new = beyond > gap or (beyond >= 0 and not old_seen)
            if near_real:
                out[e] = b if take_new else blend
                seen_end[i, e] = seen0 if e == 0 else seen1
            else:
                out[e] = b if beyond > 0 else a
                seen_end[i, e] = False if beyond > gap else old_seen
        walls[i, 0], walls[i, 1] = cx + out[0] * dx, cy + out[0] * dy
        walls[i, 2], walls[i, 3] = cx + out[1] * dx, cy + out[1] * dy
        hits[i] += 1
        last_seen[i] = step
        missed[i] = 0


def _example_see_through() -> tuple:
    walls = np.array([[1.0, -1.0, 1.0, 1.0], [3.0, 3.0, 4.0, 3.0]])
    unseen = np.array([True, True])
    ranges, valid = np.array([2.0, 2.0, 0.5]), np.array([True, True, False])
    return walls, unseen, np.zeros(2, dtype=np.int64), 0.0, 0.0, 0.0, ranges, valid, -0.5, 0.5, 0.1


@kernel(_example_see_through)
def see_through(walls: np.ndarray, unseen: np.ndarray, missed: np.ndarray, px: float, py: float, pa: float,
                ranges: np.ndarray, valid: np.ndarray, a0: float, inc: float, margin: float) -> None:
    """Count, in place in `missed`, the scans the laser passed through each unseen wall.

    Five points q of the wall (fractions 0.2 .. 0.8), in the robot's frame at distance |q|
    and bearing atan2; the beam at that bearing (rint((bearing - a0) / inc)) measured m
    (inf when invalid). A point is seen through when m > |q| + margin, else blocked; the
    wall was passed when the seen-through points outnumber the blocked ones by more than
    half the points (missed + 1). Beams ending on the wall (|m - |q|| <= margin) at more
    than half the points confirm it (missed = 0): an occluder in front says nothing."""
    n_beams = ranges.shape[0]
    c, s_ = math.cos(pa), math.sin(pa)
    for k in range(walls.shape[0]):
        if not unseen[k]:
            continue
        through_n, blocked_n, on_n = 0, 0, 0
        for f in (0.2, 0.35, 0.5, 0.65, 0.8):
            rx = walls[k, 0] + f * (walls[k, 2] - walls[k, 0]) - px
            ry = walls[k, 1] + f * (walls[k, 3] - walls[k, 1]) - py
            x = c * rx + s_ * ry
            y = -s_ * rx + c * ry
            dist = np.hypot(x, y)
            beam = np.rint((np.arctan2(y, x) - a0) / inc)
            if not (beam >= 0 and beam < n_beams):
                continue
            b = int(beam)
            measured = ranges[b] if valid[b] else np.inf
            if measured > dist + margin:
                through_n += 1
            else:
                blocked_n += 1
            if abs(measured - dist) <= margin:
                on_n += 1
        if through_n > blocked_n + 5 // 2:
            missed[k] += 1
        elif on_n > 5 // 2:
            missed[k] = 0
