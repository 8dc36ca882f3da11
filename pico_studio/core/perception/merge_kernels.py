"""Merge's compiled passes (merge.py calls them in this order; the maths beside each).

One step folds the current map (K new walls, zero frame) into the local map (W walls with
their hits, last sighting, misses, seen ends, end weights):

1. `fold_in` — associate each new wall with its most similar local wall (`associate`), fuse
   the matched ones in (`fuse`, in scan order: a wall seen in two pieces takes them one
   after the other), append the rest as tentative walls.
2. `merge_similar` — local walls similar both ways, or a shorter one lying along a longer one
   (`lies_along`: within `angle` of its direction, both ends within `distance` of its line and
   at most `distance` past its ends), are absorbed into the one seen more (`absorb`), up to 8
   rounds.
3. `see_through` — unseen walls the laser passed through count a miss; `trim_through` cuts
   back wall ends the laser passed through up to where it met the wall.
4. `connect` — ends into corners and T's (`near_pairs`, `connect_candidates`, `connect_walk`).
5. `drop_mask`, then `compact` — what stays; the connections renumbered.

Similar (`similar`). Wall b is similar to wall a (from p_a, unit direction d_a, length l_a)
when |d_a . d_b| > cos(angle), b's ends lie within `distance` of a's line
(n = |(q - p_a) x d_a|) and b's extent along it, t = (q - p_a) . d_a, overlaps [0, l_a] or
leaves a gap max(min t - l_a, -max t) below `gap`. Its cost: the mean of the two n.

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

Connecting. Corners in order of cost, then T's in order of i's distance (stable sorts: ties
keep pair order), each taking ends still free: the corner is the crossing x = p_i + s d_i
pulled towards the previous corner (the mean of the two ends) by the end weight
w = min(max(w_i, w_k), max_weight): (w prev + x) / (w + 1); a T pulls i's end towards x
alike. Ends read p_i from the walls as they move, so a moved end moves later crossings (the
order matters, as in the Python).
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel, njit

# the local map's per-wall arrays, in the order every pass takes and returns them:
# walls (W, 4) float, hits (W,) float, last_seen (W,) int64, missed (W,) int64,
# seen_end (W, 2) bool, end_weight (W, 2) float


def _example_map() -> tuple:
    walls = np.array([[0.0, 0.0, 1.0, 0.0], [1.0, 0.05, 1.0, 1.0], [3.0, 3.0, 4.0, 3.0]])
    return (walls, np.array([3.0, 1.0, 2.0]), np.zeros(3, dtype=np.int64), np.zeros(3, dtype=np.int64),
            np.zeros((3, 2), dtype=np.bool_), np.zeros((3, 2)))


@njit
def direction(walls: np.ndarray, i: int) -> tuple[float, float, float]:
    """(d_x, d_y, length) of wall i: d = (end - start) / max(length, 1e-12)."""
    dx, dy = walls[i, 2] - walls[i, 0], walls[i, 3] - walls[i, 1]
    length = np.hypot(dx, dy)
    den = max(length, 1e-12)
    return dx / den, dy / den, length


@njit
def similar(a: np.ndarray, i: int, b: np.ndarray, j: int, cos_angle: float, distance: float,
            gap: float) -> tuple[bool, float]:
    """Is wall b[j] similar to wall a[i] (see the module docstring), and its cost."""
    dax, day, la = direction(a, i)
    dbx, dby, _ = direction(b, j)
    ang_ok = abs(dax * dbx + day * dby) > cos_angle
    r0x, r0y = b[j, 0] - a[i, 0], b[j, 1] - a[i, 1]
    r1x, r1y = b[j, 2] - a[i, 0], b[j, 3] - a[i, 1]
    t0, t1 = r0x * dax + r0y * day, r1x * dax + r1y * day
    n0, n1 = abs(r0x * day - r0y * dax), abs(r1x * day - r1y * dax)
    near = max(n0, n1) < distance
    ext = max(min(t0, t1) - la, -max(t0, t1))
    return ang_ok and near and ext < gap, (n0 + n1) / 2


@njit
def lies_along(walls: np.ndarray, i: int, k: int, cos_angle: float, distance: float) -> bool:
    """Is the shorter wall k a piece of wall i: within `cos_angle` of its direction, both ends
    within `distance` of its line and at most `distance` past its ends (a corner's fragment left beside the
    wall it belongs to: seen from both ways, the long wall's far end strays off the short one's
    line by more than `distance`)."""
    dax, day, la = direction(walls, i)
    dbx, dby, lb = direction(walls, k)
    if lb > la or abs(dax * dbx + day * dby) <= cos_angle:
        return False
    for e in range(2):
        rx, ry = walls[k, 2 * e] - walls[i, 0], walls[k, 2 * e + 1] - walls[i, 1]
        t = rx * dax + ry * day
        if abs(rx * day - ry * dax) >= distance or t < -distance or t > la + distance:
            return False
    return True


def _example_associate() -> tuple:
    walls = _example_map()[0]
    return walls, np.array([[0.1, 0.02, 0.9, 0.01]]), 0.98, 0.08, 0.15


@kernel(_example_associate)
def associate(walls: np.ndarray, new: np.ndarray, cos_angle: float, distance: float, gap: float) -> np.ndarray:
    """(K,) int64: the local wall each new wall is most similar to (least cost, the first
    on ties), -1 none."""
    target = np.full(new.shape[0], -1, dtype=np.int64)
    for j in range(new.shape[0]):
        best = np.inf
        for i in range(walls.shape[0]):
            ok, cost = similar(walls, i, new, j, cos_angle, distance, gap)
            if ok and cost < best:
                best, target[j] = cost, i
    return target


def _example_fold_in() -> tuple:
    new = np.array([[0.1, 0.02, 0.9, 0.01], [5.0, 5.0, 6.0, 5.0]])
    real = np.array([[True, False], [True, True]])
    return (*_example_map(), new, real, real.copy(), 1, 0.98, 0.08, 0.15, 10.0)


@kernel(_example_fold_in)
def fold_in(walls: np.ndarray, hits: np.ndarray, last_seen: np.ndarray, missed: np.ndarray,
            seen_end: np.ndarray, end_weight: np.ndarray, new: np.ndarray, real: np.ndarray, seen: np.ndarray,
            step: int, cos_angle: float, distance: float, gap: float, max_weight: float) -> tuple:
    """Steps 1-3: the map's arrays (copies, W + fresh rows) with the new walls associated,
    fused in (`fuse`, new wall by new wall in scan order) and the unmatched ones appended
    (seen once, now; their seen ends are the scan's)."""
    target = associate(walls, new, cos_angle, distance, gap)
    w, k = walls.shape[0], new.shape[0]
    fresh = 0
    for j in range(k):
        fresh += target[j] < 0
    n = w + fresh
    walls2, hits2 = np.empty((n, 4)), np.empty(n)
    last2, missed2 = np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64)
    seen2, weight2 = np.empty((n, 2), dtype=np.bool_), np.zeros((n, 2))
    walls2[:w] = walls
    hits2[:w] = hits
    last2[:w] = last_seen
    missed2[:w] = missed
    seen2[:w] = seen_end
    weight2[:w] = end_weight
    matched = np.flatnonzero(target >= 0)
    fuse(walls2, hits2, last2, missed2, seen2, target[matched], new[matched], real[matched], seen[matched],
         step, max_weight, gap)
    m = w
    for j in range(k):
        if target[j] < 0:
            walls2[m] = new[j]
            hits2[m], last2[m], missed2[m] = 1.0, step, 0
            seen2[m] = seen[j]
            m += 1
    return walls2, hits2, last2, missed2, seen2, weight2


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
    """Fuse new walls seg (K, 4) into local walls idx (K,), one after the other, in place.

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


def _example_merge_similar() -> tuple:
    walls, hits, last, missed, seen, weight = _example_map()
    walls = np.vstack([walls, [[0.9, 0.01, 1.8, 0.02]]])
    return (walls, np.append(hits, 1.0), np.append(last, 0), np.append(missed, 0), np.vstack([seen, [[True, False]]]),
            np.vstack([weight, [[0.0, 0.0]]]), np.zeros((walls.shape[0], 2)), 0.98, 0.08, 0.15, 10.0)


@kernel(_example_merge_similar)
def merge_similar(walls: np.ndarray, hits: np.ndarray, last_seen: np.ndarray, missed: np.ndarray,
                  seen_end: np.ndarray, end_weight: np.ndarray, viewpoint: np.ndarray, cos_angle: float,
                  distance: float, gap: float, max_weight: float) -> tuple:
    """Step 4: local walls similar to each other both ways (a wall seen in two pieces), or one
    lying along the other (`lies_along`), merge:
    pairs i < k with bounding boxes within max(gap, distance), in row order, each wall once
    a round; the one seen more (i on ties) absorbs the other, the viewpoint (W, 2) of the one
    seen last with it. Up to 8 rounds, until none."""
    r = max(gap, distance)
    for _ in range(8):
        n = walls.shape[0]
        if n < 2:
            break
        ia, ka = near_pairs(walls, r)
        pairs = []
        for m in range(ia.shape[0]):
            i, k = ia[m], ka[m]
            if i < k and ((similar(walls, i, walls, k, cos_angle, distance, gap)[0]
                           and similar(walls, k, walls, i, cos_angle, distance, gap)[0])
                          or lies_along(walls, i, k, cos_angle, distance) or lies_along(walls, k, i, cos_angle, distance)):
                pairs.append((i, k))
        if len(pairs) == 0:
            break
        gone = np.zeros(n, dtype=np.bool_)
        for i, k in pairs:  # tested on the round's walls, absorbed one after the other
            if gone[i] or gone[k]:
                continue
            keep, drop = (i, k) if hits[i] >= hits[k] else (k, i)
            if last_seen[drop] > last_seen[keep]:
                viewpoint[keep] = viewpoint[drop]
            absorb(walls, hits, last_seen, missed, seen_end, keep, drop, max_weight)
            gone[drop] = True
        walls, hits, last_seen, missed, seen_end, end_weight, _ = compact(
            ~gone, walls, hits, last_seen, missed, seen_end, end_weight, np.full((n, 2), -1, dtype=np.int64))
        viewpoint = viewpoint[~gone]
    return walls, hits, last_seen, missed, seen_end, end_weight, viewpoint


@njit
def absorb(walls: np.ndarray, hits: np.ndarray, last_seen: np.ndarray, missed: np.ndarray, seen_end: np.ndarray,
           i: int, k: int, max_weight: float) -> None:
    """Wall i takes wall k in, in place. With k oriented like i (flipped when d_i . d_k < 0)
    and weights w = min(hits, max_weight): the direction turns from i's by
    atan2(d_i x d_k, d_i . d_k) w_k / (w_i + w_k), the offset rho along the normal n is the
    weighted mean of n . mid; on that line the outermost ends win (with their seen flags).
    Hits add up, the last sighting is the later, the misses the fewer."""
    bx0, by0, bx1, by1 = walls[k, 0], walls[k, 1], walls[k, 2], walls[k, 3]
    dax, day, _ = direction(walls, i)
    dbx, dby, _ = direction(walls, k)
    seen_k0, seen_k1 = seen_end[k, 0], seen_end[k, 1]
    if dax * dbx + day * dby < 0:
        bx0, by0, bx1, by1 = bx1, by1, bx0, by0
        dbx, dby = -dbx, -dby
        seen_k0, seen_k1 = seen_k1, seen_k0
    wa, wb = min(hits[i], max_weight), min(hits[k], max_weight)
    ang = math.atan2(day, dax) + math.atan2(dax * dby - day * dbx, dax * dbx + day * dby) * wb / (wa + wb)
    dx, dy = math.cos(ang), math.sin(ang)
    nx, ny = -dy, dx
    ax0, ay0, ax1, ay1 = walls[i, 0], walls[i, 1], walls[i, 2], walls[i, 3]
    rho = (wa * ((nx * (ax0 + ax1) + ny * (ay0 + ay1)) / 2) + wb * ((nx * (bx0 + bx1) + ny * (by0 + by1)) / 2)) / (wa + wb)
    ox, oy = rho * nx, rho * ny
    ta0, ta1 = (ax0 - ox) * dx + (ay0 - oy) * dy, (ax1 - ox) * dx + (ay1 - oy) * dy
    tb0, tb1 = (bx0 - ox) * dx + (by0 - oy) * dy, (bx1 - ox) * dx + (by1 - oy) * dy
    lo, lo_seen = (ta0, seen_end[i, 0]) if ta0 <= tb0 else (tb0, seen_k0)
    hi, hi_seen = (ta1, seen_end[i, 1]) if ta1 >= tb1 else (tb1, seen_k1)
    walls[i, 0], walls[i, 1] = ox + lo * dx, oy + lo * dy
    walls[i, 2], walls[i, 3] = ox + hi * dx, oy + hi * dy
    seen_end[i, 0], seen_end[i, 1] = lo_seen, hi_seen
    hits[i] = hits[i] + hits[k]
    last_seen[i] = max(last_seen[i], last_seen[k])
    missed[i] = min(missed[i], missed[k])


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


@njit
def _reading(x: float, y: float, ranges: np.ndarray, valid: np.ndarray, a0: float, inc: float) -> float:
    """What the scan's beam at the bearing of (x, y) (robot frame) measured: rint((atan2(y, x)
    - a0) / inc); inf when it returned nothing, nan when no beam looks there."""
    beam = np.rint((np.arctan2(y, x) - a0) / inc)
    if not (beam >= 0 and beam < ranges.shape[0]):
        return np.nan
    b = int(beam)
    return ranges[b] if valid[b] else np.inf


def _example_see_through() -> tuple:
    walls = np.array([[1.0, -1.0, 1.0, 1.0], [3.0, 3.0, 4.0, 3.0]])
    ranges, valid = np.array([2.0, 2.0, 0.5]), np.array([True, True, False])
    return walls, np.zeros(2, dtype=np.int64), 1, np.zeros(2, dtype=np.int64), 0.0, 0.0, 0.0, ranges, valid, -0.5, 0.5, 0.1


@kernel(_example_see_through)
def see_through(walls: np.ndarray, last_seen: np.ndarray, step: int, missed: np.ndarray, px: float, py: float, pa: float,
                ranges: np.ndarray, valid: np.ndarray, a0: float, inc: float, margin: float) -> None:
    """Step 3: count, in place in `missed`, the scans the laser passed through each wall not
    seen this scan (last_seen != step).

    Five points q of the wall (fractions 0.2 .. 0.8), in the robot's frame at distance |q|
    and bearing atan2; the beam at that bearing (rint((bearing - a0) / inc)) measured m
    (inf when invalid). A point is seen through when m > |q| + margin, else blocked; the
    wall was passed when the seen-through points outnumber the blocked ones by more than
    half the points (missed + 1). Beams ending on the wall (|m - |q|| <= margin) at more
    than half the points confirm it (missed = 0): an occluder in front says nothing."""
    c, s_ = math.cos(pa), math.sin(pa)
    for k in range(walls.shape[0]):
        if last_seen[k] == step:  # seen this scan
            continue
        through_n, blocked_n, on_n = 0, 0, 0
        for f in (0.2, 0.35, 0.5, 0.65, 0.8):
            rx = walls[k, 0] + f * (walls[k, 2] - walls[k, 0]) - px
            ry = walls[k, 1] + f * (walls[k, 3] - walls[k, 1]) - py
            x = c * rx + s_ * ry
            y = -s_ * rx + c * ry
            dist = np.hypot(x, y)
            measured = _reading(x, y, ranges, valid, a0, inc)
            if math.isnan(measured):
                continue
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


@njit
def _through_to(ex: float, ey: float, ux: float, uy: float, length: float, px: float, py: float, c: float, s_: float,
                ranges: np.ndarray, valid: np.ndarray, a0: float, inc: float, margin: float, step_len: float) -> float:
    """How far from the end (ex, ey), walking along the unit direction (ux, uy), the wall is cut
    back (`trim_through`'s walk): the first point on the wall after at least three seen through,
    else 0."""
    through_n = 0
    t = 0.0
    while t < length - step_len:
        qx, qy = ex + t * ux - px, ey + t * uy - py
        x, y = c * qx + s_ * qy, -s_ * qx + c * qy
        dist = math.hypot(x, y)
        if dist <= 1e-9:
            return 0.0
        cos_b = abs(qx * ux + qy * uy) / dist  # beam and wall: cos of the angle between
        sin_b = math.sqrt(max(0.0, 1.0 - cos_b * cos_b))
        if (dist * (inc / 2.0) + step_len / 2.0) * cos_b > (margin / 2.0) * sin_b:
            return 0.0  # a slant its beams can not judge
        measured = _reading(x, y, ranges, valid, a0, inc)
        if math.isnan(measured):
            return 0.0
        if measured > dist + margin:
            through_n += 1
        elif abs(measured - dist) <= margin:
            return t if through_n >= 3 else 0.0
        else:
            return 0.0
        t += step_len
    return 0.0


def _example_trim() -> tuple:
    # a wall y = 1 from x = -1 to 1; the laser (beams 0.05 rad apart) passes its left 0.6 m
    walls = np.array([[-1.0, 1.0, 1.0, 1.0]])
    a0, inc = 0.5, 0.05
    angles = a0 + inc * np.arange(45)
    ranges = 1.0 / np.sin(angles)
    ranges[np.cos(angles) / np.sin(angles) < -0.4] = 5.0
    return walls, 0.0, 0.0, 0.0, ranges, np.ones(45, dtype=np.bool_), a0, inc, 0.15, 0.05


@kernel(_example_trim)
def trim_through(walls: np.ndarray, px: float, py: float, pa: float, ranges: np.ndarray,
                 valid: np.ndarray, a0: float, inc: float, margin: float, step_len: float) -> int:
    """Step 3b: cut back, in place, wall ends the laser passed through: a smear merged on to a
    wall's end (a box walking past a wall's cap, a person beside a table). From each end, points
    q every `step_len` along the wall are read as `see_through` reads its five (the beam at q's
    bearing measured m; through when m > |q| + margin, on the wall when |m - |q|| <= margin);
    when at least three points from the end are seen through and the next is on the wall, the
    end moves there. A point the beam can not judge stops the walk: out of view, behind
    something (m < |q| - margin), or where the beam could meet the wall more than margin / 2
    from q, its bearing rounded to a beam (at most inc / 2 off) and the wall placed within half
    a step: (|q| inc / 2 + step_len / 2) / tan b > margin / 2, b the angle between beam and
    wall (seen at a slant, a wall a cm off passes for seen through: about 18 degrees at least).
    Walls shorter than three steps are left to `see_through`. The walls cut."""
    c, s_ = math.cos(pa), math.sin(pa)
    cut = 0
    for k in range(walls.shape[0]):
        dx, dy = walls[k, 2] - walls[k, 0], walls[k, 3] - walls[k, 1]
        length = math.hypot(dx, dy)
        if length < 3.0 * step_len:
            continue
        ux, uy = dx / length, dy / length
        # the ends' new positions along the wall, from end 0
        t0 = _through_to(walls[k, 0], walls[k, 1], ux, uy, length, px, py, c, s_, ranges, valid, a0, inc, margin,
                         step_len)
        t1 = length - _through_to(walls[k, 2], walls[k, 3], -ux, -uy, length, px, py, c, s_, ranges, valid, a0, inc,
                                  margin, step_len)
        if (t0 > 0.0 or t1 < length) and t1 - t0 >= step_len:
            x0, y0 = walls[k, 0], walls[k, 1]
            walls[k, 0], walls[k, 1] = x0 + t0 * ux, y0 + t0 * uy
            walls[k, 2], walls[k, 3] = x0 + t1 * ux, y0 + t1 * uy
            cut += 1
    return cut


def _example_connect() -> tuple:
    walls, hits, _, _, seen, weight = _example_map()
    return walls.copy(), hits, weight, seen.copy(), 0.12, 0.48, 1.0, 10.0


@kernel(_example_connect)
def connect(walls: np.ndarray, hits: np.ndarray, end_weight: np.ndarray, seen_end: np.ndarray, r: float,
            sin_min: float, confirm_hits: float, cap: float) -> tuple[np.ndarray, np.ndarray]:
    """Step 5: connect wall ends into corners and T's (the module docstring), moving `walls`
    and clearing `seen_end` in place: (connected (W, 2) int64, -1 none; end weights (W, 2))."""
    n = walls.shape[0]
    ia, ka = near_pairs(walls, r)
    if ia.shape[0] == 0:
        return np.full((n, 2), -1, dtype=np.int64), np.zeros((n, 2))
    d, ei, ek, s, dist_i, cost, end_end, t_join = connect_candidates(walls, ia, ka, hits, r, sin_min, confirm_hits)
    # tentative walls connect last (their cost carries r): a sliver seen once must not steal
    # a corner from walls seen many times
    pairs = np.flatnonzero(end_end & (ia < ka))
    tees = np.flatnonzero(t_join)
    pairs = pairs[np.argsort(cost[pairs], kind="mergesort")]
    tees = tees[np.argsort(dist_i[tees], kind="mergesort")]
    # a handful of corners per scan, one after the other (each may take an end another wanted)
    return connect_walk(walls, d, end_weight, seen_end, ia, ka, ei, ek, s, pairs, tees, cap)


def _example_drop() -> tuple:
    walls, hits, last, missed, _, _ = _example_map()
    conn = np.array([[-1, 1], [0, -1], [-1, -1]], dtype=np.int64)
    return walls, hits, last, missed, conn, 0.0, 0.0, 1, 2, 5, 6, -1, 12.0, 0.06


@kernel(_example_drop)
def drop_mask(walls: np.ndarray, hits: np.ndarray, last_seen: np.ndarray, missed: np.ndarray,
              connected: np.ndarray, px: float, py: float, step: int, unconnected_hits: float,
              tentative_life: int, miss_limit: int, forget_scans: int, keep_radius: float,
              min_length: float) -> np.ndarray:
    """Step 6 (W,) bool, the walls kept: passed through fewer than `miss_limit` scans in a
    row; a tentative wall (fewer than `unconnected_hits` hits) seen within `tentative_life`
    scans, or 4x that when connected; seen within `forget_scans` scans (when >= 0); some point
    a + t (b - a), t = clip((p - a).(b - a) / |b - a|^2, 0, 1), within `keep_radius` of the
    robot p; at least `min_length` long."""
    n = walls.shape[0]
    keep = np.empty(n, dtype=np.bool_)
    for i in range(n):
        linked = connected[i, 0] >= 0 or connected[i, 1] >= 0
        age = step - last_seen[i]
        tentative = hits[i] < unconnected_hits
        ok = missed[i] < miss_limit and not (tentative and not linked and age > tentative_life)
        ok = ok and not (tentative and linked and age > 4 * tentative_life)
        ax, ay, bx, by = walls[i, 0], walls[i, 1], walls[i, 2], walls[i, 3]
        abx, aby = bx - ax, by - ay
        t = ((px - ax) * abx + (py - ay) * aby) / max(abx * abx + aby * aby, 1e-12)
        t = min(max(t, 0.0), 1.0)
        ok = ok and np.hypot(ax + t * abx - px, ay + t * aby - py) <= keep_radius
        if forget_scans >= 0:
            ok = ok and age <= forget_scans
        keep[i] = ok and np.hypot(abx, aby) >= min_length
    return keep


def _example_compact() -> tuple:
    conn = np.array([[-1, 1], [0, -1], [-1, -1]], dtype=np.int64)
    return (np.array([True, False, True]), *_example_map(), conn)


@kernel(_example_compact)
def compact(keep: np.ndarray, walls: np.ndarray, hits: np.ndarray, last_seen: np.ndarray, missed: np.ndarray,
            seen_end: np.ndarray, end_weight: np.ndarray, connected: np.ndarray) -> tuple:
    """The rows `keep` of every array; connections to dropped walls become -1, the others
    take their wall's new number."""
    n = keep.shape[0]
    remap = np.full(n, -1, dtype=np.int64)
    m = 0
    for i in range(n):
        if keep[i]:
            remap[i] = m
            m += 1
    conn = np.empty((m, 2), dtype=np.int64)
    for i in range(n):
        if keep[i]:
            for e in range(2):
                c = connected[i, e]
                conn[remap[i], e] = remap[c] if c >= 0 else -1
    return walls[keep], hits[keep], last_seen[keep], missed[keep], seen_end[keep], end_weight[keep], conn


def _example_shown() -> tuple:
    conn = np.array([[-1, 1], [0, -1], [-1, -1]], dtype=np.int64)
    return np.array([3.0, 1.0, 2.0]), conn, 1.0, 2.0


@kernel(_example_shown)
def shown_walls(hits: np.ndarray, connected: np.ndarray, confirm_hits: float,
                unconnected_hits: float) -> tuple[np.ndarray, np.ndarray]:
    """The walls shown — seen at least `confirm_hits` times and connected, or seen
    `unconnected_hits` times — as (indices (S,), their connections renumbered among the
    shown (S, 2), -1 none or not shown)."""
    n = hits.shape[0]
    remap = np.full(n, -1, dtype=np.int64)
    m = 0
    for i in range(n):
        linked = connected[i, 0] >= 0 or connected[i, 1] >= 0
        if hits[i] >= confirm_hits and (linked or hits[i] >= unconnected_hits):
            remap[i] = m
            m += 1
    idx = np.empty(m, dtype=np.int64)
    conn = np.empty((m, 2), dtype=np.int64)
    for i in range(n):
        if remap[i] >= 0:
            idx[remap[i]] = i
            for e in range(2):
                c = connected[i, e]
                conn[remap[i], e] = remap[c] if c >= 0 else -1
    return idx, conn
