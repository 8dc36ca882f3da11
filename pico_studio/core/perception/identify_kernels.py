"""Identify's compiled loops: rays against walls, and gaps crossed by walls (identify.py's maths).

Ray hits. A ray o + t r meets wall k (from a_k, e_k = b_k - a_k) where o + t r = a_k + u e_k:

    den = r x e_k,   t = (a_k - o) x e_k / den,   u = (a_k - o) x r / den

(x: the 2-D cross product). It hits when |den| > 1e-12 (not parallel), t > 1e-6 (ahead of
the origin) and 0 <= u <= 1 (on the wall); the ray's answer is the smallest such t (the
first such wall, as numpy's argmin) and its wall, or (inf, -1). Two walls per ray may be
left out (`ex_a`, `ex_b`; -1: none).

Gaps crossed. Wall k (c, d) crosses the middle 80% of a gap (p, q) — from a = p + 0.1 (q - p)
to b = p + 0.9 (q - p) — when each segment's ends lie strictly on both sides of the other's
line: orient(a, b, c) orient(a, b, d) < 0 and orient(c, d, a) orient(c, d, b) < 0, with
orient(p, q, r) = (q - p) x (r - p). The gap's own two walls do not count.

The same floating-point operations in the same order as the numpy they replace, so the
answers are the same to the last bit.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel, njit


@njit
def line_hit(ox: float, oy: float, rx: float, ry: float, walls: np.ndarray, k: int) -> tuple[float, float]:
    """(t, u) where the ray o + t r meets wall k's line a_k + u e_k; (-inf, nan) when parallel
    (|den| <= 1e-12: never a hit)."""
    ax, ay = walls[k, 0], walls[k, 1]
    ex, ey = walls[k, 2] - ax, walls[k, 3] - ay
    den = rx * ey - ry * ex
    if not abs(den) > 1e-12:
        return -np.inf, np.nan
    aox, aoy = ax - ox, ay - oy
    return (aox * ey - aoy * ex) / den, (aox * ry - aoy * rx) / den


@njit
def _beam_towards(qx: float, qy: float, n_beams: int, vx: float, vy: float, va: float, a0: float,
                  inc: float) -> int:
    """The index of the scan's beam towards Q (zero frame; robot at V, heading va): bearing
    b = atan2(-sin(va) dx + cos(va) dy, cos(va) dx + sin(va) dy), (dx, dy) = Q - V, beam
    rint((b - a0) / inc), or -1 out of view."""
    dx, dy = qx - vx, qy - vy
    bearing = math.atan2(-math.sin(va) * dx + math.cos(va) * dy, math.cos(va) * dx + math.sin(va) * dy)
    beam = np.rint((bearing - a0) / inc)
    if not (beam >= 0 and beam < n_beams):
        return -1
    return int(beam)


def _example_rays() -> tuple:
    walls = np.array([[1.0, -1.0, 1.0, 1.0], [2.0, -1.0, 2.0, 1.0]])
    origin = np.zeros((2, 2))
    direction = np.array([[1.0, 0.0], [0.0, 1.0]])
    return origin, direction, walls, np.array([-1, 0], dtype=np.int64), np.array([-1, -1], dtype=np.int64)


@kernel(_example_rays)
def ray_hits(origin: np.ndarray, direction: np.ndarray, walls: np.ndarray, ex_a: np.ndarray,
             ex_b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(nearest hit distance (R,), its wall (R,) int64; inf / -1 for none)."""
    n_rays, n_walls = origin.shape[0], walls.shape[0]
    best = np.full(n_rays, np.inf)
    best_k = np.full(n_rays, -1, dtype=np.int64)
    for i in range(n_rays):
        ox, oy = origin[i, 0], origin[i, 1]
        rx, ry = direction[i, 0], direction[i, 1]
        for k in range(n_walls):
            if k == ex_a[i] or k == ex_b[i]:
                continue
            t, u = line_hit(ox, oy, rx, ry, walls, k)
            if t > 1e-6 and u >= 0 and u <= 1 and t < best[i]:  # strict: the first smallest
                best[i] = t
                best_k[i] = k
    return best, best_k


def _example_blocked() -> tuple:
    segs = np.array([[0.0, 0.0, 2.0, 0.0]])
    walls = np.array([[1.0, -1.0, 1.0, 1.0], [0.0, 0.0, 0.0, 1.0]])
    return segs, walls, np.array([1], dtype=np.int64), np.array([1], dtype=np.int64)


@kernel(_example_blocked)
def blocked_many(segs: np.ndarray, walls: np.ndarray, own_a: np.ndarray, own_b: np.ndarray) -> np.ndarray:
    """(G,) bool: does a wall other than the gap's own two cross the middle 80% of the gap?"""
    g, n_walls = segs.shape[0], walls.shape[0]
    out = np.zeros(g, dtype=np.bool_)
    for m in range(g):
        ax = segs[m, 0] + 0.1 * (segs[m, 2] - segs[m, 0])
        ay = segs[m, 1] + 0.1 * (segs[m, 3] - segs[m, 1])
        bx = segs[m, 0] + 0.9 * (segs[m, 2] - segs[m, 0])
        by = segs[m, 1] + 0.9 * (segs[m, 3] - segs[m, 1])
        for k in range(n_walls):
            if k == own_a[m] or k == own_b[m]:
                continue
            cx, cy, dx, dy = walls[k, 0], walls[k, 1], walls[k, 2], walls[k, 3]
            o1 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
            o2 = (bx - ax) * (dy - ay) - (by - ay) * (dx - ax)
            o3 = (dx - cx) * (ay - cy) - (dy - cy) * (ax - cx)
            o4 = (dx - cx) * (by - cy) - (dy - cy) * (bx - cx)
            if o1 * o2 < 0 and o3 * o4 < 0:
                out[m] = True
                break
    return out


def _example_pairs() -> tuple:
    pts = np.array([[0.0, 0.0], [0.9, 0.0], [0.9, 1.0]])
    out_dir = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0]])
    wi = np.array([0, 1, 2], dtype=np.int64)
    we = np.array([1, 0, 0], dtype=np.int64)
    is_convex = np.array([True, True, False])
    long = np.array([True, True, True])
    stub = np.array([False, False, False])
    cap_sized = np.array([False, False, True])
    cap_seen = np.array([False, False, True])
    connected = np.full((3, 2), -1, dtype=np.int64)
    block = np.zeros(3, dtype=np.bool_)
    building = np.array([True, True, False])
    lone = np.zeros(3, dtype=np.bool_)
    wall_end = np.ones(3, dtype=np.bool_)
    part = np.zeros(3, dtype=np.bool_)
    capped = np.zeros(3, dtype=np.bool_)
    return (pts, out_dir, wi, we, is_convex, long, stub, cap_sized, cap_seen, connected, block, building, wall_end, lone, part,
            capped, np.array([2.0, 2.0, 0.1]), 0.6, 1.2,
            1.5, 0.3, 0.1, 0.05, 0.02)


@njit
def turns_into_a_side(connected: np.ndarray, prop: np.ndarray, lengths: np.ndarray, k: int, e: int,
                       side_min: float, depth: float, convex: int, concave: int) -> bool:
    """Does wall k turn at its end e, a convex corner, into a side at least `side_min` and at
    most `depth` long whose other end is a concave corner (it meets a wall): a block's front
    against a wall, seen at that end?"""
    j = connected[k, e]
    if j < 0 or prop[k, e] != convex or lengths[j] > depth or lengths[j] < side_min:
        return False
    if connected[j, 0] == k:
        return prop[j, 1] == concave
    return connected[j, 1] == k and prop[j, 0] == concave


@njit
def _across(sin_a: float, angle: float, cap_sized: bool, span: float, noise: float) -> float:
    """The sine a wall standing across a gap's line may lean by: sin(angle), for an end cap
    sin(angle + atan(noise / its length)) — its direction measured over a few cm."""
    if not cap_sized:
        return sin_a
    return math.sin(min(angle + math.atan2(noise, max(span, 1e-12)), math.pi / 2))


@kernel(_example_pairs)
def door_pairs(pts: np.ndarray, out_dir: np.ndarray, wi: np.ndarray, we: np.ndarray, is_convex: np.ndarray,
               long: np.ndarray, stub: np.ndarray, cap_sized: np.ndarray, cap_seen: np.ndarray, connected: np.ndarray,
               block: np.ndarray, building: np.ndarray, wall_end: np.ndarray, lone: np.ndarray, part: np.ndarray,
               capped: np.ndarray, span: np.ndarray, min_width: float,
               max_width: float, wide_width: float,
               angle: float, offset: float, offset_short: float, cap_noise: float,
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The pairs (i < j, in row order) of door-point candidates P_i, P_j (wall wi, end we,
    outward direction o) that may be a door or a possible door: (i, j, off_ij, off_ji,
    is_door, is_possible) of those pairs only.

    With pq = P_j - P_i, d = |pq|, u = pq / d: a pair counts when min_width <= d <= max_width
    and the points lie on different, unconnected walls; up to `wide_width` when both walls are
    a building's (`building`: end_face_min_length long, or a door frame's length ending in a
    whole cap or turning at its far end into a wall in a concave corner, as for a T-opening, or
    a shorter stub between a whole cap and a building wall it T-joins; no object) and, for a door, both
    convex with both walls' lines continuing through the gap (a wide doorway in one wall: the
    truth's openings reach that wide; beside a table's front, shorter, or a block's face
    across the line, no such gap is a door); or when one wall is a building's whose end is a
    wall's end (`wall_end`: joined to nothing or to a whole cap, no corner of walls), its line
    continuing through the gap, and the other, no block's face, comes back along it (a
    doorway's short end beside a junction of walls, its far wall seen in part). off_ij = |pq x o_i| (P_j from wall
    i's line), off_ji = |pq x o_j|; u_i = u . o_i, u_j = u . o_j. Wall i's line continues
    through the gap when u_i > cos(angle) and off_ij < offset (a long wall) or < offset_short
    (a stub); wall j's when -u_j > cos(angle) likewise. A door: both convex, and one wall's
    line continues with the other wall coming back along it (-u_j > cos, resp. u_i > cos) or
    standing across it (|u_j| < sin(angle), resp. |u_i|; an end cap, its direction measured over
    a few cm, sin(angle + atan(cap_noise / its length `span`))) as a door frame's wall (`long` or
    `stub`, or `capped`: seen in part, its end joined to a whole cap lying along the gap's line,
    thinner than any object — a thick partition's end meeting a corridor's wall at a doorway, its
    face seen through the doorway only a few dm up past the far jamb's thickness) or an end cap (`cap_sized`: no longer than a wall's thickness) — seen whole
    (`cap_seen`) unless the line it stands across is a long wall's that is no block's face
    (`block`: a table's front seen whole, or one of any length turning at this end into its side
    against a wall, `turns_into_a_side`; a cap seen in part from the side; from a stub, itself a cap, the gap runs through a thick wall's end, and a
    person's side seen in part looks the same): a lone short wall across the line, a box's or
    a person's side, is no jamb; nor is anything standing across a block face's line (a table's
    front pointing at a partition's end), nor a block's face across a stub's line (a thick wall's
    cap pointing into the room at a bed's foot). Nor are two walls in one line a door when either is
    `lone`: a block's face shorter than a door frame's wall, joined to nothing, whose line runs on
    in no other wall past its far end
    (a box standing in line with a partition's side; a piece of wall between two doors runs on
    in the building's walls). Two walls in one line, each continuing through the gap (off < offset),
    are a door too when one is seen in part and the other is a door frame's wall or seen in part
    (`part`: shorter than a door frame's, its far end floating, its end a wall's end, no
    object's): a doorway seen through a nearer one, whose jambs hide all but a few dm of the
    far wall on each side (hospital_2019's rooms in a row); a table's side seen in part in line
    with a partition's short end is neither (the partition's piece is a stub, no frame's wall
    nor seen in part). A possible door: not both convex,
    the two walls collinear (|o_i . o_j| > cos, both offsets < offset) and facing (u_i > 0,
    u_j < 0)."""
    n = pts.shape[0]
    cos_a, sin_a = math.cos(angle), math.sin(angle)
    cap = n * (n - 1) // 2
    oi_, oj_ = np.empty(cap, dtype=np.int64), np.empty(cap, dtype=np.int64)
    off_a, off_b = np.empty(cap), np.empty(cap)
    door, possible = np.empty(cap, dtype=np.bool_), np.empty(cap, dtype=np.bool_)
    m = 0
    for i in range(n):
        for j in range(i + 1, n):
            px, py = pts[j, 0] - pts[i, 0], pts[j, 1] - pts[i, 1]
            dist = np.hypot(px, py)
            wide = dist > max_width
            if not (dist >= min_width and (dist <= max_width or (dist <= wide_width and (building[i] or building[j])))):
                continue
            if wi[i] == wi[j] or connected[wi[i], we[i]] == wi[j]:
                continue
            ux, uy = px / dist, py / dist
            off_ij = abs(px * out_dir[i, 1] - py * out_dir[i, 0])
            off_ji = abs(px * out_dir[j, 1] - py * out_dir[j, 0])
            ui = ux * out_dir[i, 0] + uy * out_dir[i, 1]
            uj = ux * out_dir[j, 0] + uy * out_dir[j, 1]
            line_i = ui > cos_a and ((off_ij < offset and long[i]) or (off_ij < offset_short and stub[i]))
            line_j = -uj > cos_a and ((off_ji < offset and long[j]) or (off_ji < offset_short and stub[j]))
            frame_i = long[i] or stub[i] or capped[i] or (cap_sized[i] and (cap_seen[i] or (long[j] and not block[j])))
            frame_j = long[j] or stub[j] or capped[j] or (cap_sized[j] and (cap_seen[j] or (long[i] and not block[i])))
            in_line = not lone[i] and not lone[j]
            # a stub's line (a thick wall's cap) ends at no block's face across it: a bed's foot
            # facing a doorway a metre in, seen past the cap's inner corner
            # a cap's direction is measured over its few cm: `cap_noise` across its length more
            door_ij = line_i and ((-uj > cos_a and in_line)
                                  or (abs(uj) < _across(sin_a, angle, cap_sized[j], span[j], cap_noise) and frame_j
                                      and not block[i] and not (stub[i] and block[j])))
            door_ji = line_j and ((ui > cos_a and in_line)
                                  or (abs(ui) < _across(sin_a, angle, cap_sized[i], span[i], cap_noise) and frame_i
                                      and not block[j] and not (stub[j] and block[i])))
            both_convex = is_convex[i] and is_convex[j]
            # two walls in one line, each continuing through the gap, one or both seen in part
            # (`part`), the other a door frame's: a doorway seen through another doorway
            parts = (part[i] or part[j]) and (long[i] or part[i]) and (long[j] or part[j]) and ui > cos_a \
                and -uj > cos_a and off_ij < offset and off_ji < offset and in_line
            is_door = both_convex and (door_ij or door_ji or parts)
            if wide:
                is_door = both_convex and ((building[i] and building[j] and line_i and line_j)
                                           or (building[i] and wall_end[i] and line_i and -uj > cos_a and in_line
                                               and not block[j])
                                           or (building[j] and wall_end[j] and line_j and ui > cos_a and in_line
                                               and not block[i]))
                if not is_door:
                    continue
            collinear = (abs(out_dir[i, 0] * out_dir[j, 0] + out_dir[i, 1] * out_dir[j, 1]) > cos_a
                         and off_ij < offset and off_ji < offset)
            is_possible = collinear and ui > 0 and uj < 0 and not both_convex
            if not (is_door or is_possible):
                continue
            oi_[m], oj_[m], off_a[m], off_b[m], door[m], possible[m] = i, j, off_ij, off_ji, is_door, is_possible
            m += 1
    return oi_[:m].copy(), oj_[:m].copy(), off_a[:m].copy(), off_b[:m].copy(), door[:m].copy(), possible[:m].copy()


def _example_backed() -> tuple:
    segs = np.array([[1.0, -0.5, 1.0, 0.5]])
    walls = np.array([[1.0, -1.0, 1.0, -0.5], [1.0, 0.5, 1.0, 1.0], [2.0, -1.0, 2.0, 1.0]])
    own = np.array([0], dtype=np.int64), np.array([1], dtype=np.int64)
    ranges, valid = np.array([2.0, 2.0, 2.0]), np.array([True, True, False])
    return (segs, walls, *own, 0.0, 0.0, True, ranges, valid, 0.0, 0.0, 0.0, -0.1, 0.1,
            np.zeros(1, dtype=np.bool_), np.zeros(3, dtype=np.bool_), 0.1, 0.3, 0.12, 0.5)


@njit
def _on_any(px: float, py: float, walls: np.ndarray, these: np.ndarray, tol: float) -> bool:
    """Does point p lie within `tol` of one of the walls marked in `these`?"""
    for k in range(walls.shape[0]):
        if not these[k]:
            continue
        ax, ay = walls[k, 0], walls[k, 1]
        ex, ey = walls[k, 2] - ax, walls[k, 3] - ay
        t = min(max(((px - ax) * ex + (py - ay) * ey) / max(ex * ex + ey * ey, 1e-12), 0.0), 1.0)
        if math.hypot(px - ax - t * ex, py - ay - t * ey) < tol:
            return True
    return False


@kernel(_example_backed)
def backed(segs: np.ndarray, walls: np.ndarray, own_a: np.ndarray, own_b: np.ndarray, rx: float, ry: float,
           has_view: bool, ranges: np.ndarray, valid: np.ndarray, vx: float, vy: float, va: float, a0: float,
           inc: float, face_end: np.ndarray, things: np.ndarray, occlusion: float, depth: float, jamb_cap_max: float,
           backed_share: float, remembered_deep: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """((G,) bool: is there no seeing through gap g?, (G,) int64: how many of its rays were
    seen to pass it: known, and ending more than `occlusion` beyond the gap's line or never,
    (G,) int64: how many of those ended more than `depth` beyond it or never: free space,
    (G,) bool: is its back seen? of the rays ending beyond its line, at least `backed_share`
    (and one) ended between the jambs (not by a jamb's normal) within `depth`: on a pocket's
    back, not on a passage's side)
    (identify._backed says what and why.)

    Five samples q = p + f (p' - p), f in 0.2 .. 0.8, of each gap (p, p'); the ray from the
    robot R through q has direction r = (q - R) / |q - R|. How far it reaches: the current
    scan's beam at q's bearing (beam = rint((bearing - a0) / inc), wrapped once for a full
    circle; an invalid beam reaches far when it returned nothing or beyond q, else says
    nothing: nan) when that beam exists, else the first wall along the ray (ray_hits' maths,
    the gap's two walls left out; with a scan but out of its view and no wall along it, the ray
    says nothing: the local map not knowing a wall there is no free space; nor, unless
    `remembered_deep`, does one out of view whose remembered wall lies more than `depth` past
    the gap's line: the local map keeps walls, not the free space before them — a bay, a gap
    of a table's shape, is open only where the scan's own beams see through it). A ray stopping
    short of |q - R| - occlusion says nothing.
    Where the others end, in the gap's frame (s along from p, n across): a ray ending within
    `occlusion` of a jamb's normal (|s| or |s - L|; for a T-opening, `face_end`, the far jamb's
    is the face's own line, square to the gap only within door_angle: a ray landing on the face
    run on past the gap) says nothing unless deeper than
    `jamb_cap_max` behind a jamb that is a wall's end; a ray is closed when it ends within
    `depth` of the gap line between the jambs (or deep beside one). A ray ending within
    `occlusion` of a wall marked in `things` (W,) (a small object's: a box standing in a side
    room) says nothing either: what stands in a room is not its back. Backed when some rays say
    something, at least `backed_share` of them are closed, and none reached `depth` beyond."""
    g, n_walls, n_beams = segs.shape[0], walls.shape[0], ranges.shape[0]
    out = np.zeros(g, dtype=np.bool_)
    free = np.zeros(g, dtype=np.int64)
    deep = np.zeros(g, dtype=np.int64)
    back = np.zeros(g, dtype=np.bool_)
    c, sn = math.cos(va), math.sin(va)
    wrap = 2 * math.pi / abs(inc) if has_view else 0.0
    for m in range(g):
        length = np.hypot(segs[m, 2] - segs[m, 0], segs[m, 3] - segs[m, 1])
        den = max(length, 1e-12)
        alx, aly = (segs[m, 2] - segs[m, 0]) / den, (segs[m, 3] - segs[m, 1]) / den
        # a T-opening's far jamb is the face's line, square to the gap only within door_angle
        fk = own_b[m]
        fx, fy = walls[fk, 2] - walls[fk, 0], walls[fk, 3] - walls[fk, 1]
        fl = max(np.hypot(fx, fy), 1e-12)
        fnx, fny = -fy / fl, fx / fl
        inf_n = 0
        closed_n = 0
        behind_n = 0
        back_n = 0
        for f in (0.2, 0.35, 0.5, 0.65, 0.8):
            qx = segs[m, 0] + f * (segs[m, 2] - segs[m, 0])
            qy = segs[m, 1] + f * (segs[m, 3] - segs[m, 1])
            relx, rely = qx - rx, qy - ry
            dist = np.hypot(relx, rely)
            dd = max(dist, 1e-12)
            dx, dy = relx / dd, rely / dd
            # the local map: the first wall along the ray
            reach = np.inf
            for k in range(n_walls):
                if k == own_a[m] or k == own_b[m]:
                    continue
                ax, ay = walls[k, 0], walls[k, 1]
                ex, ey = walls[k, 2] - ax, walls[k, 3] - ay
                dn = dx * ey - dy * ex
                if not abs(dn) > 1e-12:
                    continue
                aox, aoy = ax - rx, ay - ry
                t = (aox * ey - aoy * ex) / dn
                u = (aox * dy - aoy * dx) / dn
                if t > 1e-6 and u >= 0 and u <= 1 and t < reach:
                    reach = t
            known = True
            remembered = False
            if has_view:  # the scan, where it looks through the gap
                sx, sy = qx - vx, qy - vy
                bx = c * sx + sn * sy
                by = -sn * sx + c * sy
                bearing = np.arctan2(by, bx)
                beam = np.rint((bearing - a0) / inc)
                if beam >= n_beams and beam - wrap > -1:
                    beam = np.rint(beam - wrap)
                if beam >= 0 and beam < n_beams:
                    b = int(beam)
                    raw = ranges[b]
                    if valid[b]:
                        reach = raw
                    elif not (np.isfinite(raw) and raw > 0 and raw < dist):
                        reach = np.inf
                    else:
                        reach = np.nan
                    known = not np.isnan(reach)
                elif not np.isfinite(reach):
                    known = False  # out of the laser's view and no wall behind in the local map: unknown
                else:
                    remembered = not remembered_deep  # out of view, a wall the local map keeps
            finite = np.isfinite(reach)
            r_ = reach if finite else 0.0
            if known and finite and _on_any(rx + r_ * dx, ry + r_ * dy, walls, things, occlusion):
                known = False  # on a thing standing there, not on the room's walls
            informative = known and reach >= dist - occlusion
            ex_, ey_ = rx + r_ * dx - segs[m, 0], ry + r_ * dy - segs[m, 1]
            s_ = ex_ * alx + ey_ * aly
            n_ = abs(ex_ * aly - ey_ * alx)
            if remembered and n_ > depth:  # deep behind the gap, but nothing says free up to it
                known = False
                informative = False
            ended = informative and finite
            near_first = abs(s_) < occlusion
            if face_end[m]:
                near_last = abs((rx + r_ * dx - walls[fk, 0]) * fnx + (ry + r_ * dy - walls[fk, 1]) * fny) < occlusion
            else:
                near_last = abs(s_ - length) < occlusion
            side = ended and (near_first or near_last)
            deep_side = side and n_ > jamb_cap_max and (near_first or not face_end[m])
            informative = informative and (not side or deep_side)
            closed = ended and n_ < depth and ((not side and s_ > 0 and s_ < length) or deep_side)
            if informative:
                inf_n += 1
            if closed:
                closed_n += 1
                if not side and reach > dist:
                    back_n += 1
            if ended and reach > dist:
                behind_n += 1
            if known and reach > dist and (not finite or n_ > occlusion):
                free[m] += 1  # seen to pass the gap: it ended `occlusion` beyond its line, or never
                if not finite or n_ > depth:
                    deep[m] += 1  # ...and reached `depth` beyond it: free space behind, not a pocket
        out[m] = inf_n > 0 and closed_n >= backed_share * inf_n and deep[m] == 0
        back[m] = back_n > 0 and back_n >= backed_share * behind_n
    return out, free, deep, back


@njit
def away_normal(gap: np.ndarray, rx: float, ry: float) -> tuple[float, float]:
    """The normal n of a gap (P -> M), |n| = |PM|, pointing away from the robot R."""
    nx, ny = -(gap[3] - gap[1]), gap[2] - gap[0]
    if nx * (rx - gap[0]) + ny * (ry - gap[1]) > 0:
        nx, ny = -nx, -ny
    return nx, ny


@njit
def standing_in_shadow(gap: np.ndarray, walls: np.ndarray, prop: np.ndarray, things: np.ndarray, group: np.ndarray,
                       own: int, face: int, rx: float, ry: float, depth: float, convex: int) -> np.ndarray:
    """(W,) bool: `things`, and every wall with a seen (convex) end E standing in the gap's
    shadow: with the gap (P, Q), u = (Q - P) / |Q - P| and n its normal away from the robot R,
    0 < u . (E - P) < |Q - P| and 0 < n . (E - P) < `depth`; no wall of the jambs' own groups
    (`group`, group_spans' labels: a cabinet in a pocket's corner, joined to its face, is the
    pocket's). The laser saw past that end into the space behind the opening: a box or a
    cabinet standing in the room beyond, not a pocket's back (which runs across the whole
    shadow into its corners)."""
    out = things.copy()
    lx, ly = gap[2] - gap[0], gap[3] - gap[1]
    length = max(math.hypot(lx, ly), 1e-12)
    ux, uy = lx / length, ly / length
    nx, ny = away_normal(gap, rx, ry)
    nx, ny = nx / length, ny / length
    for k in range(walls.shape[0]):
        if out[k] or group[k] == group[own] or group[k] == group[face]:
            continue
        for e in range(2):
            if prop[k, e] != convex:
                continue
            px, py = walls[k, 2 * e] - gap[0], walls[k, 2 * e + 1] - gap[1]
            s, d = px * ux + py * uy, px * nx + py * ny
            if s > 0 and s < length and d > 0 and d < depth:
                out[k] = True
    return out


def _example_beside() -> tuple:
    segs, walls, own_a, own_b, *rest = _example_backed()
    return (segs, walls, own_a, own_b, *rest, np.zeros((3, 2), dtype=np.int64), np.arange(3), 2)


@kernel(_example_beside)
def backed_beside_things(segs: np.ndarray, walls: np.ndarray, own_a: np.ndarray, own_b: np.ndarray, rx: float,
                         ry: float, has_view: bool, ranges: np.ndarray, valid: np.ndarray, vx: float, vy: float,
                         va: float, a0: float, inc: float, face_end: np.ndarray, things: np.ndarray,
                         occlusion: float, depth: float, jamb_cap_max: float, backed_share: float, prop: np.ndarray,
                         group: np.ndarray, convex: int, remembered_deep: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """`backed`, where a ray ending on a thing standing in a gap's shadow says nothing of its
    back (standing_in_shadow: a wall's seen end there): a gap found backed, or its back seen, is
    looked at again with those walls among the `things`."""
    out, free, deep, back = backed(segs, walls, own_a, own_b, rx, ry, has_view, ranges, valid, vx, vy, va, a0, inc,
                                   face_end, things, occlusion, depth, jamb_cap_max, backed_share, remembered_deep)
    for m in range(segs.shape[0]):
        if not (out[m] or back[m]):
            continue
        standing = standing_in_shadow(segs[m], walls, prop, things, group, own_a[m], own_b[m], rx, ry, depth, convex)
        if np.array_equal(standing, things):
            continue
        o1, f1, d1, b1 = backed(segs[m:m + 1], walls, own_a[m:m + 1], own_b[m:m + 1], rx, ry, has_view, ranges,
                                valid, vx, vy, va, a0, inc, face_end[m:m + 1], standing, occlusion, depth,
                                jamb_cap_max, backed_share, remembered_deep)
        out[m], free[m], deep[m], back[m] = o1[0], f1[0], d1[0], b1[0]
    return out, free, deep, back


def _example_spans() -> tuple:
    walls = np.array([[0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 1.0, 1.0], [3.0, 3.0, 4.0, 3.0]])
    connected = np.array([[-1, 1], [0, -1], [-1, -1]], dtype=np.int64)
    return walls, connected


@kernel(_example_spans)
def group_spans(walls: np.ndarray, connected: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(group (W,) int64: a label shared by connected walls, span (W,): the diagonal of the
    bounding box of the wall's group). Groups by union-find over the connections (path
    halving)."""
    n = walls.shape[0]
    root = np.arange(n)
    for i in range(n):
        for e in range(2):
            k = connected[i, e]
            if k < 0:
                continue
            a, b = i, k
            while root[a] != a:
                root[a] = root[root[a]]
                a = root[a]
            while root[b] != b:
                root[b] = root[root[b]]
                b = root[b]
            if a != b:
                root[a] = b
    group = np.empty(n, dtype=np.int64)
    lo_x, lo_y = np.full(n, np.inf), np.full(n, np.inf)
    hi_x, hi_y = np.full(n, -np.inf), np.full(n, -np.inf)
    for i in range(n):
        a = i
        while root[a] != a:
            root[a] = root[root[a]]
            a = root[a]
        group[i] = a
        for e in range(2):
            x, y = walls[i, 2 * e], walls[i, 2 * e + 1]
            lo_x[a], hi_x[a] = min(lo_x[a], x), max(hi_x[a], x)
            lo_y[a], hi_y[a] = min(lo_y[a], y), max(hi_y[a], y)
    span = np.empty(n)
    for i in range(n):
        g = group[i]
        span[i] = np.hypot(hi_x[g] - lo_x[g], hi_y[g] - lo_y[g])
    return group, span


def _example_in_line() -> tuple:
    # a building's wall (0..3, y=0), a 1 m door, a 1.1 m piece, a 1 m door, a wall's piece
    walls = np.array([[0.0, 0.0, 3.0, 0.0], [3.0, 0.0, 3.0, 2.0], [4.0, 0.0, 5.1, 0.0], [6.1, 0.0, 7.0, 0.0]])
    connected = np.array([[-1, 1], [0, -1], [-1, -1], [-1, -1]], dtype=np.int64)
    group, span = group_spans(walls, connected)
    prop = np.array([[0, 3], [3, 0], [2, 2], [2, 0]], dtype=np.int64)
    return (walls, group, span, np.zeros(4, dtype=np.bool_), connected, prop, 2.0, 0.3, 0.05, 1.3, 1.5, 1.0, True, 720,
            3.0, -2.0, 1.57, -1.0, 0.0028, 0, 3)


@njit
def _in_line_beyond(walls: np.ndarray, objects: np.ndarray, i: int, e: int, j: int, cos_a: float, offset: float,
                    max_gap: float, facing: bool = False) -> bool:
    """Wall j continues wall i's line past i's end e, across at most `max_gap`: parallel within
    acos(cos_a), each one's ends within `offset` of the other's line, and j starting (along i,
    from i's end e outwards) at most max_gap on and not reaching back past that end by more
    than `offset`. With `facing`, only the shorter one's end facing across the gap need lie
    within `offset` of the longer one's line: a short piece's own line, drawn on, wanders by its
    angle's error times the distance. A rule that refuses asks it so (what spares it should not
    hang on a 0.2 m piece's angle); one that lends a building's span asks both ends of the
    shorter to lie within `offset` of the longer one's line (the better fitted: a 0.7 m wall seen
    1.6 degrees askew, drawn on 2 m, misses the piece it continues by 0.06 m)."""
    if j == i or objects[j]:
        return False
    ax, ay = walls[i, 0], walls[i, 1]
    li = max(math.hypot(walls[i, 2] - ax, walls[i, 3] - ay), 1e-12)
    ux, uy = (walls[i, 2] - ax) / li, (walls[i, 3] - ay) / li
    cx, cy = walls[j, 0], walls[j, 1]
    lj = max(math.hypot(walls[j, 2] - cx, walls[j, 3] - cy), 1e-12)
    vx, vy = (walls[j, 2] - cx) / lj, (walls[j, 3] - cy) / lj
    if abs(ux * vx + uy * vy) <= cos_a:
        return False
    if facing:
        ex, ey = walls[i, 2 * e], walls[i, 2 * e + 1]
        near = nearer_end(walls, j, ex, ey)
        nx, ny = walls[j, 2 * near], walls[j, 2 * near + 1]
        off = abs((nx - ax) * uy - (ny - ay) * ux) if li >= lj else abs((ex - cx) * vy - (ey - cy) * vx)
        if off > offset:
            return False
    elif li >= lj:
        if abs((cx - ax) * uy - (cy - ay) * ux) > offset or abs((walls[j, 2] - ax) * uy - (walls[j, 3] - ay) * ux) > offset:
            return False
    elif abs((ax - cx) * vy - (ay - cy) * vx) > offset or abs((walls[i, 2] - cx) * vy - (walls[i, 3] - cy) * vx) > offset:
        return False
    s0 = (cx - ax) * ux + (cy - ay) * uy
    s1 = (walls[j, 2] - ax) * ux + (walls[j, 3] - ay) * uy
    if e == 0:  # beyond the start: j lies at s <= 0
        return max(s0, s1) <= offset and max(s0, s1) >= -max_gap
    return min(s0, s1) >= li - offset and min(s0, s1) <= li + max_gap


@njit
def _firm(walls: np.ndarray, connected: np.ndarray, prop: np.ndarray, i: int, e: int, j: int, building_min: float,
          corner_min: float, concave: int) -> bool:
    """Wall j, in line past wall i's end e, is a building's by its own shape: at least
    `building_min` long, or its far end (from i's end e) a concave corner with a wall longer than
    `corner_min` (an object's size: a room's corner, its other wall maybe itself a piece between
    two doors; a table's side against a wall turns into the table's back, short)."""
    lj = math.hypot(walls[j, 2] - walls[j, 0], walls[j, 3] - walls[j, 1])
    if lj >= building_min:
        return True
    px, py = walls[i, 2 * e], walls[i, 2 * e + 1]
    far = 0 if math.hypot(walls[j, 0] - px, walls[j, 1] - py) > math.hypot(walls[j, 2] - px, walls[j, 3] - py) else 1
    k = connected[j, far]
    if k < 0 or prop[j, far] != concave:
        return False
    return math.hypot(walls[k, 2] - walls[k, 0], walls[k, 3] - walls[k, 1]) > corner_min


@kernel(_example_in_line)
def in_line_spans(walls: np.ndarray, group: np.ndarray, span: np.ndarray, objects: np.ndarray, connected: np.ndarray,
                  prop: np.ndarray, min_span: float, angle: float, offset: float, max_gap: float, building_min: float,
                  object_max: float, has_view: bool, n_beams: int, vx: float, vy: float, va: float, a0: float, inc: float,
                  floating: int, concave: int) -> np.ndarray:
    """(W,) each wall's group span, raised to `min_span` where the group is a piece of a
    building's wall between door-wide gaps: the wall between two doors of a corridor or two
    side rooms, its own sides seen edge-on or not at all, spans no more than a table's front
    but lies in one line with the building's walls. A wall i (not an object, its group short
    of `min_span`) is such a piece when at each of its ends e its line runs on past the end in
    another wall j (`_in_line_beyond`: a door's width on at most), and at one end that wall j
    is a building's (its group spans `min_span`, or is such a piece already). A table's face in
    line with a wall's face across a gap has a seen corner at its other end with nothing in
    line beyond it: no piece. Its other end may run on out of view (floating: a side room's
    mouth seen at a slant, its far wall in part; or any end, free or a corner, whose line a door's
    width on, `max_gap` past it, lies outside the scan's field of view, `_beam_towards`: the
    piece of a room's wall between two cubicles' mouths, turning at both ends into the cubicles'
    walls, the room's wall past the far mouth out of view) when the wall it lends from is a building's by
    its own shape (`_firm`: `building_min` long, or turning at a concave corner into a wall
    longer than an object, `object_max`), or is a piece in line past both its own ends (a wall seen in part in line with the
    piece between two side rooms, once that piece is the building's); a table's side against a
    wall, in line with a partition's face by chance, turns into the table's short back. Then its
    whole group is the building's; repeated over the pairs found until nothing changes (at most
    one round per group: the piece between two doors is reached from either side)."""
    n = walls.shape[0]
    out = span.copy()
    building = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        building[i] = span[i] >= min_span and not objects[i]
    cos_a = math.cos(angle)
    # a candidate's line runs on past both its ends, or past one with the other out of view (a
    # test that does not depend on who is a building's: done once), then the walls of other
    # groups it may borrow from, counted first
    candidate = np.zeros(n, dtype=np.bool_)
    loose = np.zeros(n, dtype=np.bool_)  # one end runs on out of view only
    count = 0
    for i in range(n):
        if building[i] or objects[i]:
            continue
        ends_ok = 0
        lenders = 0
        open_end = False
        for e in range(2):
            run_on = False
            for j in range(n):
                if _in_line_beyond(walls, objects, i, e, j, cos_a, offset, max_gap):
                    run_on = True
                    if group[j] != group[i]:
                        lenders += 1
            if not run_on and (prop[i, e] == floating or (has_view and _line_out_of_view(
                    walls, i, e, max_gap, n_beams, vx, vy, va, a0, inc))):
                run_on = open_end = True
            if run_on:
                ends_ok += 1
        if ends_ok == 2 and lenders > 0:
            candidate[i] = True
            loose[i] = open_end
            count += lenders
    pair_i = np.empty(count, dtype=np.int64)
    pair_j = np.empty(count, dtype=np.int64)
    p = 0
    for i in range(n):
        if not candidate[i]:
            continue
        for e in range(2):
            for j in range(n):
                if group[j] != group[i] and _in_line_beyond(walls, objects, i, e, j, cos_a, offset, max_gap) \
                        and (not loose[i] or _firm(walls, connected, prop, i, e, j, building_min, object_max, concave)
                             or (candidate[j] and not loose[j])):
                    pair_i[p], pair_j[p] = i, j
                    p += 1
    # then lend along the pairs until nothing changes (at most one round per group)
    for _ in range(n):
        changed = False
        for q in range(p):
            i, j = pair_i[q], pair_j[q]
            if building[i] or not building[j]:
                continue
            for k in range(n):  # the whole group is the building's
                if group[k] == group[i]:
                    building[k] = True
                    out[k] = max(out[k], min_span)
            changed = True
        if not changed:
            break
    return out


@njit
def _line_out_of_view(walls: np.ndarray, i: int, e: int, reach: float, n_beams: int, vx: float, vy: float, va: float,
                      a0: float, inc: float) -> bool:
    """Is the point `reach` on past wall i's end e, along its line, outside the scan's field of
    view?"""
    ex, ey = walls[i, 2 * e], walls[i, 2 * e + 1]
    dx, dy = ex - walls[i, 2 * (1 - e)], ey - walls[i, 2 * (1 - e) + 1]
    length = math.hypot(dx, dy)
    if length <= 0:
        return False
    return _beam_towards(ex + reach * dx / length, ey + reach * dy / length, n_beams, vx, vy, va, a0, inc) < 0


def _example_inside() -> tuple:
    walls, connected = _example_spans()
    group, _ = group_spans(walls, connected)
    prop = np.array([[0, 3], [3, 0], [0, 0]], dtype=np.int64)
    return walls, connected, prop, group, np.zeros(3, dtype=np.bool_), 0.2, 3


@kernel(_example_inside)
def inside_corners(walls: np.ndarray, connected: np.ndarray, prop: np.ndarray, group: np.ndarray,
                   objects: np.ndarray, min_length: float, concave: int) -> np.ndarray:
    """(W,) bool: the wall's group turns at a concave corner: seen from a room's inside. A
    table, a cabinet or a box seen from outside turns at convex corners only. The corner is
    two walls (not an object's), each at least `min_length` long (a wall no longer than a
    wall's thickness may be an end cap), whose ends meet: each joined to the other there, both
    ends concave. A table standing a few cm off a wall is T-joined to the wall's face: its side
    is joined to the wall, the wall, running on past, to nothing there."""
    n = walls.shape[0]
    mark = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        if objects[i] or math.hypot(walls[i, 2] - walls[i, 0], walls[i, 3] - walls[i, 1]) < min_length:
            continue
        for e in range(2):
            k = connected[i, e]
            if k < 0 or prop[i, e] != concave or objects[k]:
                continue
            mutual = (connected[k, 0] == i and prop[k, 0] == concave) or (connected[k, 1] == i and prop[k, 1] == concave)
            if mutual and math.hypot(walls[k, 2] - walls[k, 0], walls[k, 3] - walls[k, 1]) >= min_length:
                mark[group[i]] = True
    out = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        out[i] = mark[group[i]]
    return out


def _example_groups() -> tuple:
    walls, connected = _example_spans()
    prop = np.array([[1, 2], [2, 1], [0, 0]], dtype=np.int64)
    return walls, connected, prop, 2.0, 0, 3


@kernel(_example_groups)
def object_groups(walls: np.ndarray, connected: np.ndarray, prop: np.ndarray, max_size: float,
                  floating: int, concave: int) -> tuple[np.ndarray, np.ndarray]:
    """(group (W,) int64: a label shared by connected walls, candidate (W,) bool: the wall's
    group spans at most `max_size` (its bounding box's diagonal, `group_spans`), none of its
    ends has the property `floating` and, unless it is a closed loop (every end joined: seen all
    round, its far corners look concave through it), it turns nowhere at a corner `concave` (an
    end so, joined to another wall: the laser looks into a corner, a thing standing against a
    wall or a wall's corner; a free-standing thing seen from outside turns at convex corners
    only))."""
    group, span = group_spans(walls, connected)
    n = walls.shape[0]
    loose = np.zeros(n, dtype=np.bool_)
    open_ = np.zeros(n, dtype=np.bool_)  # a group with an end joined to nothing
    inside = np.zeros(n, dtype=np.bool_)  # a group turning at a concave corner
    for i in range(n):
        for e in range(2):
            if prop[i, e] == floating:
                loose[group[i]] = True
            if connected[i, e] < 0:
                open_[group[i]] = True
            elif prop[i, e] == concave:
                inside[group[i]] = True
    for g in range(n):
        if inside[g] and open_[g]:
            loose[g] = True
    candidate = np.empty(n, dtype=np.bool_)
    for i in range(n):
        candidate[i] = not (span[i] > max_size) and not loose[group[i]]
    return group, candidate


def _example_objects() -> tuple:
    walls, connected, prop, max_size, floating, concave = _example_groups()
    return walls, connected, prop, max_size, 0.1, floating, concave


@kernel(_example_objects)
def small_objects(walls: np.ndarray, connected: np.ndarray, prop: np.ndarray, max_size: float, min_depth: float,
                  floating: int, concave: int) -> np.ndarray:
    """(W,) bool: the wall belongs to a candidate group (`object_groups`: small, seen whole, an
    open chain turning at no concave corner, or a closed loop) at least `min_depth` deep across
    its main direction. The group's wall ends p_k, centred on their mean, have the second
    moments sxx, sxy, syy; the main direction is at theta = atan2(2 sxy, sxx - syy) / 2
    (the principal axis), its normal m = (-sin theta, cos theta), and the depth is the spread
    max - min of p_k . m."""
    group, candidate = object_groups(walls, connected, prop, max_size, floating, concave)
    n = walls.shape[0]
    out = np.zeros(n, dtype=np.bool_)
    done = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        g = group[i]
        if not candidate[i] or done[g]:
            continue
        done[g] = True
        mx, my, c = 0.0, 0.0, 0
        for k in range(n):
            if group[k] == g:
                for e in range(2):
                    mx += walls[k, 2 * e]
                    my += walls[k, 2 * e + 1]
                    c += 1
        mx, my = mx / c, my / c
        sxx, sxy, syy = 0.0, 0.0, 0.0
        for k in range(n):
            if group[k] == g:
                for e in range(2):
                    dx, dy = walls[k, 2 * e] - mx, walls[k, 2 * e + 1] - my
                    sxx += dx * dx
                    sxy += dx * dy
                    syy += dy * dy
        theta = 0.5 * math.atan2(2.0 * sxy, sxx - syy)
        nx, ny = -math.sin(theta), math.cos(theta)
        lo, hi = math.inf, -math.inf
        for k in range(n):
            if group[k] == g:
                for e in range(2):
                    v = (walls[k, 2 * e] - mx) * nx + (walls[k, 2 * e + 1] - my) * ny
                    lo, hi = min(lo, v), max(hi, v)
        deep = hi - lo >= min_depth
        for k in range(n):
            if group[k] == g:
                out[k] = deep
    return out


def _example_candidates() -> tuple:
    walls = np.array([[0.0, 0.0, 2.0, 0.0], [2.0, 0.0, 2.0, 0.2], [3.0, 0.0, 5.0, 0.0]])
    connected = np.array([[-1, 1], [0, -1], [-1, -1]], dtype=np.int64)
    prop = np.array([[0, 2], [2, 2], [2, 0]], dtype=np.int64)
    return walls, connected, prop, np.zeros(3, dtype=np.bool_), 0.35, 0.5, 0, 2, 1.5, 1.0, 1.0, 1.0


@kernel(_example_candidates)
def jamb_candidates(walls: np.ndarray, connected: np.ndarray, prop: np.ndarray, objects: np.ndarray,
                    cap_max: float, frame_min: float, floating: int, convex: int, building_min: float,
                    rx: float, ry: float, object_max: float,
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                               np.ndarray, np.ndarray]:
    """The door-point candidates (identify._doors says what and why): every wall end (i, e)
    that is convex or floating, not on an object, and either joined to nothing or *capped*
    there, or convex on a wall at least `building_min` long turning away from the robot at
    (rx, ry) (a building's thin wall turning: `_turns_away`) into a wall that is no block's face
(`_block_corner`, no longer than `object_max`). Wall k joined at end e is a cap when |k| <= cap_max and it is *whole*: none of k's
    ends is floating but the one joining i (a T-joined k: neither), and the wall joined at its
far end, if any, runs back the same way as i (`_step`: else a box against a wall). Per candidate, in row order
    (i, then e): (wall i, end e, capped, long: |i| >= frame_min, stub: not long and the wall
    joined at i's far end is long, cap_sized: |i| <= cap_max, cap_seen: neither of i's ends
    floating (seen whole), partial: joined to a cap seen in part, lengths (W,) of every wall).
    A convex end of a wall `building_min` long joined to a piece no longer than a cap seen in
    part is a candidate too (`partial`): a door's jamb whose frame corner came out in fragments,
    seen at a slant; as a jamb only in line with another building wall (jamb_doors)."""
    n = walls.shape[0]
    lengths = np.empty(n)
    for i in range(n):
        lengths[i] = np.hypot(walls[i, 2] - walls[i, 0], walls[i, 3] - walls[i, 1])
    wi, we = np.empty(2 * n, dtype=np.int64), np.empty(2 * n, dtype=np.int64)
    capped, long, stub = np.empty(2 * n, dtype=np.bool_), np.empty(2 * n, dtype=np.bool_), np.empty(2 * n, dtype=np.bool_)
    cap_sized, cap_seen = np.empty(2 * n, dtype=np.bool_), np.empty(2 * n, dtype=np.bool_)
    partial = np.zeros(2 * n, dtype=np.bool_)
    m = 0
    for i in range(n):
        for e in range(2):
            if objects[i] or not (prop[i, e] == convex or prop[i, e] == floating):
                continue
            k = connected[i, e]
            whole = False
            if k >= 0 and lengths[k] <= cap_max:
                whole = True
                for b in range(2):
                    if prop[k, b] == floating and connected[k, b] != i:
                        whole = False
                if whole and _step(walls, connected, i, e, k):
                    whole = False
                if not whole:
                    if not (lengths[i] >= building_min and prop[i, e] == convex):
                        continue
                    partial[m] = True
            elif k >= 0 and not (prop[i, e] == convex and lengths[i] >= building_min
                                 and _turns_away(walls, i, e, k, rx, ry) and not _block_corner(connected, prop, lengths, i, k, convex, object_max)):
                # a block's corner (a table against a wall); a building's wall turning is a jamb
                # when it turns away from the robot (R): turning towards it, the corner hides the
                # wall's end from R (convex only as seen from behind: a wall's end by a table)
                continue
            wi[m], we[m], capped[m] = i, e, whole
            long[m] = lengths[i] >= frame_min
            stub[m] = not long[m] and joins_frame(connected, lengths, i, 1 - e, frame_min)
            cap_sized[m] = lengths[i] <= cap_max
            cap_seen[m] = prop[i, 0] != floating and prop[i, 1] != floating
            m += 1
    return (wi[:m].copy(), we[:m].copy(), capped[:m].copy(), long[:m].copy(), stub[:m].copy(), cap_sized[:m].copy(),
            cap_seen[:m].copy(), partial[:m].copy(), lengths)


@njit
def nearer_end(walls: np.ndarray, k: int, px: float, py: float) -> int:
    """The end of wall k (0 or 1) nearer to P (0 on a tie)."""
    return 0 if math.hypot(walls[k, 0] - px, walls[k, 1] - py) <= math.hypot(walls[k, 2] - px, walls[k, 3] - py) else 1


@njit
def square_to(walls: np.ndarray, k: int, ox: float, oy: float, sin_a: float) -> bool:
    """Is wall k about square to the unit direction o: |e_k . o| / |e_k| <= sin_a?"""
    kx, ky = walls[k, 2] - walls[k, 0], walls[k, 3] - walls[k, 1]
    return abs(kx * ox + ky * oy) / max(math.hypot(kx, ky), 1e-12) <= sin_a


@njit
def walls_square(walls: np.ndarray, a: int, b: int, sin_a: float) -> bool:
    """Are walls a and b about square to each other (square_to, o along b)?"""
    bx, by = walls[b, 2] - walls[b, 0], walls[b, 3] - walls[b, 1]
    lb = max(math.hypot(bx, by), 1e-12)
    return square_to(walls, a, bx / lb, by / lb, sin_a)


@njit
def joins_frame(connected: np.ndarray, lengths: np.ndarray, w: int, e: int, frame_min: float) -> bool:
    """Is wall w joined at its end e to a wall at least `frame_min` long? A short stub (or a
    short piece of a room's wall between a door and the room's corner) frames a door so."""
    o = connected[w, e]
    return o >= 0 and lengths[o] >= frame_min


@njit
def _turns_away(walls: np.ndarray, i: int, e: int, k: int, rx: float, ry: float) -> bool:
    """Does wall k, joined at end P (end e of wall i), run to the other side of i's line than
    the robot R? With d = P - (i's far end): (d x (k's far end - P)) (d x (R - P)) < 0."""
    px, py = walls[i, 2 * e], walls[i, 2 * e + 1]
    dx, dy = px - walls[i, 2 * (1 - e)], py - walls[i, 2 * (1 - e) + 1]
    d0 = np.hypot(walls[k, 0] - px, walls[k, 1] - py)
    d1 = np.hypot(walls[k, 2] - px, walls[k, 3] - py)
    fx, fy = (walls[k, 2], walls[k, 3]) if d0 <= d1 else (walls[k, 0], walls[k, 1])
    side_k = dx * (fy - py) - dy * (fx - px)
    side_r = dx * (ry - py) - dy * (rx - px)
    return side_k * side_r < 0


@njit
def _block_corner(connected: np.ndarray, prop: np.ndarray, lengths: np.ndarray, i: int, k: int, convex: int,
                  object_max: float) -> bool:
    """Is wall k, joined to wall i, a block's face: no longer than an object (`object_max`) and
    its other end convex too (a bed's front, i its side)? A room's wall turns into a side wall
    that ends in a concave corner (a thin-walled room's mouth) or runs on out of view; a
    hallway's wall, seen to its end, is longer."""
    if lengths[k] > object_max:
        return False
    if connected[k, 0] == i:
        return prop[k, 1] == convex
    if connected[k, 1] == i:
        return prop[k, 0] == convex
    return False


@njit
def _step(walls: np.ndarray, connected: np.ndarray, i: int, e: int, k: int) -> bool:
    """Does cap k (joined to end e of wall i) join, at its far end, a wall running the other
    way from wall i? A thick wall's end cap joins its two faces, both running back the same
    way; a step turns into a wall running on the other side (a box standing against a wall:
    its front, its short side, the wall)."""
    bk = 0 if connected[k, 0] == i else 1
    if connected[k, bk] != i:
        return False  # k T-joined to i: no far end to look at
    f = connected[k, 1 - bk]
    if f < 0 or f == i:
        return False
    jx, jy = walls[k, 2 * (1 - bk)], walls[k, 2 * (1 - bk) + 1]
    d0 = np.hypot(walls[f, 0] - jx, walls[f, 1] - jy)
    d1 = np.hypot(walls[f, 2] - jx, walls[f, 3] - jy)
    fx, fy = (walls[f, 2] - jx, walls[f, 3] - jy) if d0 <= d1 else (walls[f, 0] - jx, walls[f, 1] - jy)
    ix = walls[i, 2 * (1 - e)] - walls[i, 2 * e]
    iy = walls[i, 2 * (1 - e) + 1] - walls[i, 2 * e + 1]
    return fx * ix + fy * iy < 0


# one opening, not two: two gaps sharing an end point (within SAME_POINT) and leaving it within
# SAME_OPENING_ANGLE of each other (same_opening)
SAME_OPENING_ANGLE = 0.5  # rad
SAME_POINT = 1e-6  # m


def _example_distinct() -> tuple:
    segs = np.array([[0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 1.0, 0.1], [2.0, 0.0, 3.0, 0.0]])
    return segs, np.array([0, 1, 2], dtype=np.int64), np.array([True, True, True]), SAME_OPENING_ANGLE, SAME_POINT


@njit
def same_opening(a: np.ndarray, m: int, b: np.ndarray, k: int, cos_max: float, tol: float) -> bool:
    """Are gaps a[m] and b[k] one opening: sharing an end point (within `tol`) and leaving it
    with cos of the angle between them above `cos_max`?"""
    for ea in range(2):
        for eb in range(2):
            pax, pay = a[m, 2 * ea], a[m, 2 * ea + 1]
            pbx, pby = b[k, 2 * eb], b[k, 2 * eb + 1]
            if max(abs(pax - pbx), abs(pay - pby)) < tol:
                ux, uy = a[m, 2 * (1 - ea)] - pax, a[m, 2 * (1 - ea) + 1] - pay
                vx, vy = b[k, 2 * (1 - eb)] - pbx, b[k, 2 * (1 - eb) + 1] - pby
                cos = (ux * vx + uy * vy) / max(math.hypot(ux, uy) * math.hypot(vx, vy), 1e-12)
                if cos > cos_max:
                    return True
    return False


@kernel(_example_distinct)
def distinct_openings(segs: np.ndarray, order: np.ndarray, usable: np.ndarray, max_angle: float,
                      tol: float) -> np.ndarray:
    """The `usable` gaps in `order`, each kept unless it is the same opening as one kept before
    (`same_opening`). The kept rows, in order (K,) int64."""
    cos_max = math.cos(max_angle)
    kept = np.empty(order.shape[0], dtype=np.int64)
    n = 0
    for r in range(order.shape[0]):
        m = order[r]
        if not usable[m]:
            continue
        same = False
        for q in range(n):
            if same_opening(segs, m, segs, kept[q], cos_max, tol):
                same = True
                break
        if not same:
            kept[n] = m
            n += 1
    return kept[:n].copy()


@njit
def jamb_ids(wi: np.ndarray, we: np.ndarray, connected: np.ndarray, lengths: np.ndarray, cap_max: float) -> np.ndarray:
    """(C,) one label per jamb among the candidates (wall wi, end we): a wall's end and the far
    corner of the end cap joined to it (no longer than `cap_max`: a thick wall's end) share one."""
    c = wi.shape[0]
    jid = np.arange(c)
    for r in range(c):
        i, e = wi[r], we[r]
        k = connected[i, e]
        if k < 0 or lengths[k] > cap_max or connected[k, 0] == connected[k, 1]:
            continue
        far_end = 1 if connected[k, 0] == i else 0 if connected[k, 1] == i else -1
        if far_end < 0:
            continue
        for r2 in range(c):
            if wi[r2] == k and we[r2] == far_end:
                low = min(jid[r], jid[r2])
                jid[r], jid[r2] = low, low
    return jid


@njit
def claimed_jambs(pts: np.ndarray, out_dir: np.ndarray, wi: np.ndarray, we: np.ndarray, connected: np.ndarray,
                  lengths: np.ndarray, doors: np.ndarray, cap_max: float, cos_a: float,
                  tol: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(jid (C,) jamb_ids, claimed (C,) per label, claim (C, 2) the claiming door's outward
    direction): a jamb is a door's when one of `doors` (D, 4) has an end at a candidate's point
    P (within `tol`) and leaves it along the candidate's wall (u . o > cos(angle); the wall no end
    cap of another, whose direction runs across the wall it caps). The first such door's."""
    c = pts.shape[0]
    jid = jamb_ids(wi, we, connected, lengths, cap_max)
    claimed = np.zeros(c, dtype=np.bool_)
    claim = np.zeros((c, 2))
    for d in range(doors.shape[0]):
        dist = max(math.hypot(doors[d, 2] - doors[d, 0], doors[d, 3] - doors[d, 1]), 1e-12)
        for e in range(2):
            px, py = doors[d, 2 * e], doors[d, 2 * e + 1]
            ux, uy = (doors[d, 2 * (1 - e)] - px) / dist, (doors[d, 2 * (1 - e) + 1] - py) / dist
            for r in range(c):
                cap = lengths[wi[r]] <= cap_max and connected[wi[r], 1 - we[r]] >= 0
                if cap or claimed[jid[r]] or max(abs(pts[r, 0] - px), abs(pts[r, 1] - py)) >= tol:
                    continue
                if ux * out_dir[r, 0] + uy * out_dir[r, 1] > cos_a:
                    claimed[jid[r]] = True
                    claim[jid[r], 0], claim[jid[r], 1] = ux, uy
    return jid, claimed, claim


@njit
def leaves_a_claimed_jamb(pts: np.ndarray, out_dir: np.ndarray, i: int, j: int, jid: np.ndarray,
                          claimed: np.ndarray, claim: np.ndarray, cos_a: float, offset_short: float) -> bool:
    """A jamb frames one door. Does the gap P_i -> P_j leave a jamb another door continues in its
    wall's line (claimed_jambs) in another direction (its outward direction, u at P_i, -u at P_j,
    more than `angle` off that door's) — a partition's end between two pieces of the partition
    framing a doorway is no side of a gap to a table's corner across the room (suite:171, 9 of
    50 poses) — and not on one grid with it: each point off the other's wall line by
    `offset_short` or more (|pq x o|; two doorways meeting at one corner, hospital_2021's rooms)?"""
    px, py = pts[j, 0] - pts[i, 0], pts[j, 1] - pts[i, 1]
    dist = max(math.hypot(px, py), 1e-12)
    ux, uy = px / dist, py / dist
    off_i, off_j = abs(px * out_dir[i, 1] - py * out_dir[i, 0]), abs(px * out_dir[j, 1] - py * out_dir[j, 0])
    if min(off_i, off_j) < offset_short:
        return False
    gi, gj = jid[i], jid[j]
    return ((claimed[gi] and ux * claim[gi, 0] + uy * claim[gi, 1] <= cos_a)
            or (claimed[gj] and -(ux * claim[gj, 0] + uy * claim[gj, 1]) <= cos_a))


def _example_extended() -> tuple:
    walls = np.array([[0.0, -1.0, 2.0, -1.0], [3.0, 2.0, 3.0, 4.0]])
    origin = np.array([[2.3, 0.0]])
    direction = np.array([[0.0, -1.0]])
    return origin, direction, walls, np.array([[False, True], [False, False]]), np.array([True, True]), 0.5


@kernel(_example_extended)
def extended_hits(origin: np.ndarray, direction: np.ndarray, walls: np.ndarray, floating: np.ndarray,
                  eligible: np.ndarray, reach: float) -> tuple[np.ndarray, np.ndarray]:
    """Where rays o + t r meet an `eligible` wall's line just past one of its floating ends (the
    wall seen in part, running on out of view there): ray_hits' maths with u (along the wall,
    0 .. 1 between its ends) beyond the floating end by at most `reach` / |e| — u in
    (1, 1 + reach / |e|] past end 1, [-reach / |e|, 0) before end 0. (nearest t (R,), wall
    (R,) int64; inf / -1 for none.)"""
    n_rays, n_walls = origin.shape[0], walls.shape[0]
    best = np.full(n_rays, np.inf)
    best_k = np.full(n_rays, -1, dtype=np.int64)
    for i in range(n_rays):
        ox, oy = origin[i, 0], origin[i, 1]
        rx, ry = direction[i, 0], direction[i, 1]
        for k in range(n_walls):
            if not eligible[k] or not (floating[k, 0] or floating[k, 1]):
                continue
            t, u = line_hit(ox, oy, rx, ry, walls, k)
            extra = reach / max(np.hypot(walls[k, 2] - walls[k, 0], walls[k, 3] - walls[k, 1]), 1e-12)
            past = (floating[k, 1] and u > 1 and u <= 1 + extra) or (floating[k, 0] and u < 0 and u >= -extra)
            if t > 1e-6 and past and t < best[i]:
                best[i] = t
                best_k[i] = k
    return best, best_k
