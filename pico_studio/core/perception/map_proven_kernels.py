"""The map-proven candidates' compiled loops (map_proven.py says what they find and why).

Bays. From the door-point candidates (identify_kernels.jamb_candidates with any cap a jamb
and no block face) the convex ends P_i with outward direction o_i = (P_i - F_i) / |P_i - F_i|
(F_i: the wall's far end) pair as identify_kernels.door_pairs's doors, or as a passage's
mouth: two door frame's walls side by side (o_i . o_j > cos(angle)) with the gap across both
(|u . o_i|, |u . o_j| < sin(angle), u = (P_j - P_i) / |P_j - P_i|), a door's width apart,
scored |u . o_i| + |u . o_j|. A gap no other wall crosses (blocked_many) is kept, best scored
first, one per opening (distinct_openings).

Blocks against a wall (`block_sides`). A side S joined at its ends to B and F, e_S . e_B and
e_S . e_F below sin(angle) |e_S| |e_B| (|e_F|); F's far end and B's far end on opposite sides of
S's line (the cross products with S's direction of opposite signs); with n B's unit normal, F's
middle M stands off B's line by n . (M - B0), at least cap_max, of the robot's sign; F's far end
joins S2, square to F, whose far end lies nearer B's line by more than cap_max; and the robot
is not inside (|n . (R - B0)| < |n . (M - B0)| with its projection on F within F).

Lone end caps. A cap from a to b (|b - a| = L <= cap_max, joined to nothing) looks along its
normal n = (-d_y, d_x), d = (b - a) / L, turned towards the robot R ((R - M) . n >= 0, M the
cap's middle); the first wall it meets (ray_hits, the cap itself left out) at t in
[min_width, max_width] is a building's (|k| >= building_min, no object) about square to the
ray (|e_k . n| / |e_k| <= sin(angle)), and no other wall crosses the gap M -> M + t n.

The same floating-point operations in the same order as the numpy they replace, so the
answers are the same to the last bit.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.core.perception.identify_kernels import (
    SAME_OPENING_ANGLE,
    SAME_POINT,
    blocked_many,
    claimed_jambs,
    distinct_openings,
    door_pairs,
    jamb_candidates,
    joins_frame,
    leaves_a_claimed_jamb,
    nearer_end,
    ray_hits,
    same_opening,
    walls_square,
)
from pico_studio.jit import kernel, njit


def _example_bays() -> tuple:
    walls = np.array([[0.0, 0.0, 2.0, 0.0], [2.9, 0.0, 5.0, 0.0], [0.0, 0.0, 0.0, 2.0]])
    connected = np.array([[2, -1], [-1, -1], [0, -1]], dtype=np.int64)
    prop = np.array([[1, 2], [2, 0], [1, 0]], dtype=np.int64)
    return (walls, connected, prop, np.zeros(3, dtype=np.bool_), np.zeros((1, 4)), 1.0, 1.0, 0.35, 0.5, 0, 2, 0.6,
            1.2, 0.3, 0.1, 0.05, 0.02)


@kernel(_example_bays)
def bay_gaps(walls: np.ndarray, connected: np.ndarray, prop: np.ndarray, objects: np.ndarray, doors: np.ndarray,
             rx: float, ry: float,
             cap_max: float, frame_min: float, floating: int, convex: int, min_width: float, max_width: float,
             angle: float, offset: float, offset_short: float, cap_noise: float,
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The bays and passage mouths (K, 4) between convex ends, best aligned first, but those
    that are the same opening as one of `doors` (D, 4) (identify_kernels.same_opening) or leave
    one of their jambs in another direction (identify_kernels.leaves_a_claimed_jamb), and each
    one's two jambs' walls (K,), (K,)."""
    none = np.zeros(0, dtype=np.int64)
    wi_all, we_all, _, long_all, stub_all, sized_all, seen_all, partial, lengths = jamb_candidates(
        walls, connected, prop, objects, cap_max, frame_min, floating, convex, 0.0, rx, ry, 0.0)
    keep = np.empty(wi_all.shape[0], dtype=np.int64)
    n = 0
    for r in range(wi_all.shape[0]):
        if prop[wi_all[r], we_all[r]] == convex and not partial[r]:
            keep[n] = r
            n += 1
    if n < 2:
        return np.zeros((0, 4)), none, none
    keep = keep[:n]
    wi, we = wi_all[keep], we_all[keep]
    long, stub, cap_sized, cap_seen = long_all[keep], stub_all[keep], sized_all[keep], seen_all[keep]
    pts = np.empty((n, 2))
    out_dir = np.empty((n, 2))
    for r in range(n):
        e = we[r]
        pts[r, 0], pts[r, 1] = walls[wi[r], 2 * e], walls[wi[r], 2 * e + 1]
        dx, dy = pts[r, 0] - walls[wi[r], 2 * (1 - e)], pts[r, 1] - walls[wi[r], 2 * (1 - e) + 1]
        norm = max(np.hypot(dx, dy), 1e-12)
        out_dir[r, 0], out_dir[r, 1] = dx / norm, dy / norm
    ia, ja, off_ij, off_ji, is_door, _ = door_pairs(
        pts, out_dir, wi, we, np.ones(n, dtype=np.bool_), long, stub, cap_sized, cap_seen, connected,
        np.zeros(n, dtype=np.bool_), np.zeros(n, dtype=np.bool_), np.zeros(n, dtype=np.bool_), np.zeros(n, dtype=np.bool_),
        np.zeros(n, dtype=np.bool_), np.zeros(n, dtype=np.bool_), lengths[wi], min_width, max_width,
        max_width, angle, offset, offset_short, cap_noise)
    # the door-shaped pairs, then the mouths (pairs of door frame's walls, in row order)
    m_max = ia.shape[0] + n * (n - 1) // 2
    gi, gj = np.empty(m_max, dtype=np.int64), np.empty(m_max, dtype=np.int64)
    off = np.empty(m_max)
    g = 0
    for r in range(ia.shape[0]):
        if is_door[r]:
            gi[g], gj[g], off[g] = ia[r], ja[r], min(off_ij[r], off_ji[r])
            g += 1
    cos_a, sin_a = math.cos(angle), math.sin(angle)
    for i in range(n):
        if not long[i]:
            continue
        for j in range(i + 1, n):
            if not long[j]:
                continue
            dx, dy = pts[j, 0] - pts[i, 0], pts[j, 1] - pts[i, 1]
            dist = np.hypot(dx, dy)
            ux, uy = dx / max(dist, 1e-12), dy / max(dist, 1e-12)
            ui = abs(ux * out_dir[i, 0] + uy * out_dir[i, 1])
            uj = abs(ux * out_dir[j, 0] + uy * out_dir[j, 1])
            if (min_width <= dist <= max_width and out_dir[i, 0] * out_dir[j, 0] + out_dir[i, 1] * out_dir[j, 1] > cos_a
                    and ui < sin_a and uj < sin_a and wi[i] != wi[j] and connected[wi[i], we[i]] != wi[j]):
                gi[g], gj[g], off[g] = i, j, ui + uj
                g += 1
    if g == 0:
        return np.zeros((0, 4)), none, none
    segs = np.empty((g, 4))
    own_a, own_b = np.empty(g, dtype=np.int64), np.empty(g, dtype=np.int64)
    for r in range(g):
        segs[r, 0], segs[r, 1] = pts[gi[r], 0], pts[gi[r], 1]
        segs[r, 2], segs[r, 3] = pts[gj[r], 0], pts[gj[r], 1]
        own_a[r], own_b[r] = wi[gi[r]], wi[gj[r]]
    clear = ~blocked_many(segs, walls, own_a, own_b)
    order = np.argsort(off[:g], kind="mergesort")  # stable: equal scores keep their row order
    kept = distinct_openings(segs, order, clear, SAME_OPENING_ANGLE, SAME_POINT)
    cos_max = math.cos(SAME_OPENING_ANGLE)
    new = np.ones(kept.shape[0], dtype=np.bool_)
    for q in range(kept.shape[0]):
        for d in range(doors.shape[0]):
            if same_opening(segs, kept[q], doors, d, cos_max, SAME_POINT):
                new[q] = False
                break
    # a jamb frames one door: none leaving one of `doors`' jambs in another direction
    jid, claimed, claim = claimed_jambs(pts, out_dir, wi, we, connected, lengths, doors, cap_max, cos_a, SAME_POINT)
    for q in range(kept.shape[0]):
        if new[q] and leaves_a_claimed_jamb(pts, out_dir, gi[kept[q]], gj[kept[q]], jid, claimed, claim, cos_a,
                                            offset_short):
            new[q] = False
    out = kept[new]
    return segs[out], own_a[out], own_b[out]


@njit
def _jamb_wall(gaps: np.ndarray, q: int, j: int, own: int, walls: np.ndarray, connected: np.ndarray,
               which: int) -> tuple[int, int, float, float, float]:
    """The walls at gap q's jamb J (j 0: its first point, 1: its second), an end of wall `own`:
    which 0 is `own`, which 1 the wall joined at that end. Returns (the wall or -1: none, the
    index of its end F farther from J, F - J as dx, dy, |F - J|)."""
    jx, jy = gaps[q, 2 * j], gaps[q, 2 * j + 1]
    w = own
    if which == 1:
        e = nearer_end(walls, own, jx, jy)
        w = connected[own, e]
        if w < 0:
            return -1, 0, 0.0, 0.0, 0.0
    f = 1 - nearer_end(walls, w, jx, jy)
    dx, dy = walls[w, 2 * f] - jx, walls[w, 2 * f + 1] - jy
    return w, f, dx, dy, math.hypot(dx, dy)


@njit
def _door_goes_on(x: float, y: float, dx: float, dy: float, doors: np.ndarray, cos_a: float) -> bool:
    """Does one of `doors` (D, 4) leave F = (x, y) in about the direction (dx, dy)
    (identify_kernels.same_opening): another doorway on along the same line past a piece of wall,
    not the same doorway's other face past its jamb's cap?"""
    ahead = np.array([[x, y, x + dx, y + dy]])
    for d in range(doors.shape[0]):
        if same_opening(ahead, 0, doors, d, cos_a, SAME_POINT):
            return True
    return False


def _example_shapes() -> tuple:
    walls = np.array([[-2.0, 0.0, 0.0, 0.0], [0.9, 0.0, 3.0, 0.0], [0.9, 0.0, 0.9, 1.0]])
    connected = np.array([[-1, -1], [2, -1], [1, -1]], dtype=np.int64)
    gaps = np.array([[0.0, 0.0, 0.9, 0.0]])
    lengths = np.hypot(walls[:, 2] - walls[:, 0], walls[:, 3] - walls[:, 1])
    prop = np.array([[0, 0], [3, 0], [3, 0]], dtype=np.int64)
    return (gaps, walls, connected, prop, lengths, np.array([0], dtype=np.int64), np.array([1], dtype=np.int64), 0.3,
            0.5, 0.1, 3, 0, np.zeros((0, 4)))


@kernel(_example_shapes)
def wall_shaped(gaps: np.ndarray, walls: np.ndarray, connected: np.ndarray, prop: np.ndarray, lengths: np.ndarray,
                own_a: np.ndarray, own_b: np.ndarray, angle: float, frame_min: float, line_offset: float,
                concave: int, floating: int, doors: np.ndarray) -> np.ndarray:
    """(K,) bool: the bay lies in a wall's line or across a passage, as an opening in a building's
    walls does. At each jamb J (the gap's end point, an end of its wall) the walls there (its own,
    and the one joined at that end) run from J towards their far ends F, d = (F - J) / |F - J|;
    with u = (B - A) / |B - A| the gap's direction a wall at least `frame_min` long (or joined at
    F to one that long in a concave corner, `identify_kernels.joins_frame`: a room's wall running
    on to the room's corner; a thick wall's end cap turns into its side at a convex one; or its
    end F floating: it runs on out of view, its length unknown; or one of `doors` (D, 4) going on
    from F the same way: a piece of wall between two doorways) at A is in line when
    d . u < -cos(angle) (at B: d . u > cos(angle)) and the other
    jamb lies within `line_offset` of its line, |d x (B - A)| (one line, not a bed's side
    pointing past a wall's cap), across it when
    |d . u| < sin(angle), on the side sign(u x d). A wall's opening has a wall in line at both jambs (a side room's mouth, a hallway's seen from
    the room); a passage's mouth has walls across it at both, on the same side (a hallway's far
    end). A table's corner beside a partition's end has one of each, or sides running opposite
    ways: no opening of a wall."""
    k = gaps.shape[0]
    out = np.zeros(k, dtype=np.bool_)
    cos_a, sin_a = math.cos(angle), math.sin(angle)
    for q in range(k):
        ax, ay, bx, by = gaps[q, 0], gaps[q, 1], gaps[q, 2], gaps[q, 3]
        ln = max(math.hypot(bx - ax, by - ay), 1e-12)
        ux, uy = (bx - ax) / ln, (by - ay) / ln
        inline = np.zeros(2, dtype=np.bool_)
        along = np.zeros(2, dtype=np.bool_)
        side = np.zeros(2, dtype=np.int64)  # +1 / -1: a wall across, on that side; 0: none (2: both)
        for j in range(2):
            sign = -1.0 if j == 0 else 1.0  # in line: running away from the gap
            for which in range(2):
                w, f, dx, dy, dn = _jamb_wall(gaps, q, j, own_a[q] if j == 0 else own_b[q], walls, connected, which)
                if w < 0:
                    continue
                if dn < frame_min and prop[w, f] != floating and \
                        not (joins_frame(connected, lengths, w, f, frame_min) and prop[w, f] == concave) \
                        and not _door_goes_on(walls[w, 2 * f], walls[w, 2 * f + 1], dx, dy, doors, cos_a):
                    continue  # a door frame's length (or joining one in a room's corner): a wall's end cap or a bed's foot is none
                c = (dx * ux + dy * uy) / dn
                ox, oy = (bx - ax, by - ay) if j == 0 else (ax - bx, ay - by)  # to the other jamb
                if sign * c > cos_a:
                    along[j] = True  # running along the gap: no passage's mouth
                    if abs(dx * oy - dy * ox) / dn <= line_offset:
                        inline[j] = True
                elif abs(c) < sin_a:
                    s = 1 if ux * dy - uy * dx > 0 else -1
                    side[j] = s if side[j] == 0 or side[j] == s else 2
        out[q] = (inline[0] and inline[1]) or (side[0] != 0 and side[0] != 2 and side[0] == side[1]
                                               and not along[0] and not along[1])
    return out


def _example_blocks() -> tuple:
    # a table 1.4 x 0.7 m standing against a wall (y = 0), the robot in front of it
    walls = np.array([[-2.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, -0.7], [0.0, -0.7, 1.4, -0.7], [1.4, -0.7, 1.4, 0.0]])
    connected = np.array([[-1, 1], [0, 2], [1, 3], [2, -1]], dtype=np.int64)
    lengths = np.hypot(walls[:, 2] - walls[:, 0], walls[:, 3] - walls[:, 1])
    return walls, connected, lengths, 0.7, -2.0, 0.35, 0.3


@kernel(_example_blocks)
def block_sides(walls: np.ndarray, connected: np.ndarray, lengths: np.ndarray, rx: float, ry: float, cap_max: float,
                angle: float) -> np.ndarray:
    """(W,) bool: the walls of a block standing against a wall, seen closed (a table, a bed: the
    bay from its corner to a partition's end in line with its side opens no building's walls).
    A side S joined at one end to a wall B about square to it, at the other to the front F; F
    about square to S, leaving S's line on the other side from B (a U of three walls from one
    line is a room's or a niche's shape too), longer than `cap_max` (no wall's end cap: a thick
    wall's end has this shape), its middle at least `cap_max` off B's line on the robot R's side
    (a niche's back lies behind the wall); and F's other end joined to a second side S2, about
    square to F, running back towards B's line; the robot not inside the three (a room's walls
    seen from inside have the same shape). Seen open (F's far end free, or out of view),
    the same corner is a room's wall turning into a passage's side: an escape room's exit."""
    n = walls.shape[0]
    out = np.zeros(n, dtype=np.bool_)
    sin_a = math.sin(angle)
    for s in range(n):
        for e in range(2):
            f, b = connected[s, e], connected[s, 1 - e]
            if f < 0 or b < 0 or f == b or lengths[f] <= cap_max:
                continue
            if not (walls_square(walls, s, f, sin_a) and walls_square(walls, s, b, sin_a)):
                continue
            px, py = walls[s, 2 * e], walls[s, 2 * e + 1]  # the block's corner
            qx, qy = walls[s, 2 * (1 - e)], walls[s, 2 * (1 - e) + 1]  # where S meets B
            fn = nearer_end(walls, f, px, py)
            fx, fy = walls[f, 2 * (1 - fn)], walls[f, 2 * (1 - fn) + 1]  # F's far end
            bf = 1 - nearer_end(walls, b, qx, qy)
            sx, sy = px - qx, py - qy
            to_f = sx * (fy - py) - sy * (fx - px)
            to_b = sx * (walls[b, 2 * bf + 1] - qy) - sy * (walls[b, 2 * bf] - qx)
            if to_f * to_b >= 0:
                continue
            # B's line, its normal n: F stands off it towards the robot
            bx, by = walls[b, 0], walls[b, 1]
            nx, ny = -(walls[b, 3] - by) / max(lengths[b], 1e-12), (walls[b, 2] - bx) / max(lengths[b], 1e-12)
            off_f = nx * ((px + fx) / 2 - bx) + ny * ((py + fy) / 2 - by)
            if abs(off_f) < cap_max or off_f * (nx * (rx - bx) + ny * (ry - by)) <= 0:
                continue
            # closed: F's far end turns into a second side running back towards B's line
            s2 = connected[f, 1 - fn]
            if s2 < 0 or s2 == s or not walls_square(walls, f, s2, sin_a):
                continue
            tn = nearer_end(walls, s2, fx, fy)
            off_s2 = nx * (walls[s2, 2 * (1 - tn)] - bx) + ny * (walls[s2, 2 * (1 - tn) + 1] - by)
            # ...and the robot outside it: from inside, a room's three walls make the same shape
            off_r = nx * (rx - bx) + ny * (ry - by)
            along = ((rx - px) * (fx - px) + (ry - py) * (fy - py)) / max(lengths[f] * lengths[f], 1e-12)
            inside = abs(off_r) < abs(off_f) and 0.0 < along < 1.0
            if abs(off_s2) < abs(off_f) - cap_max and not inside:
                out[s] = True
                out[f] = True
                out[s2] = True
    return out


def _example_sides() -> tuple:
    # a hallway leaving a room's wall (x = 0) at 0..0.9 (y): its upper side 1.2 m long, seen
    walls = np.array([[0.0, -2.0, 0.0, 0.0], [0.0, 0.9, 1.2, 0.9], [0.0, 0.9, 0.0, 3.0]])
    connected = np.array([[-1, -1], [2, -1], [1, -1]], dtype=np.int64)
    gaps = np.array([[0.0, 0.0, 0.0, 0.9]])
    prop = np.array([[0, 2], [2, 0], [2, 0]], dtype=np.int64)
    return gaps, walls, connected, prop, np.array([0], dtype=np.int64), np.array([1], dtype=np.int64), -1.5, 0.3, 0.3, \
        0.8, 0.5, 2, 0


@kernel(_example_sides)
def deep_sides(gaps: np.ndarray, walls: np.ndarray, connected: np.ndarray, prop: np.ndarray, own_a: np.ndarray,
               own_b: np.ndarray, rx: float, ry: float, angle: float, depth: float, run_on: float, convex: int,
               floating: int) -> np.ndarray:
    """(K,) bool: a side of the bay runs on `depth` past its line, away from the robot: a
    passage, not a pocket. At each jamb J the walls there (its own and the one joined at that
    end, `wall_shaped`'s) that run across the gap (|d . u| < sin(angle), d from J to the wall's
    far end F) with F on the far side of the gap's line from the robot R, (F - J) x u and
    (R - A) x u of opposite signs, |(F - J) x u| >= depth, and F no `convex` end (the side runs
    on out of view, or into the room's back wall). A table pocket's sides end at the wall behind
    it, within `depth` (else its rays reach that deep too); a bed's foot, as wide as a hallway
    is long, turns at a seen corner; a hallway seen at a slant, its rays all ending on its far
    side short of `depth`, has that side running on.

    Seen steeply a side room's or a hallway's side shows less than `depth` before the near
    jamb hides it: a side whose F is `floating` (it runs on into the view's edge) needs only
    `run_on` (0 < run_on < depth; 0: off). A pocket's side, as short, ends at its back in a
    corner, concave or joined (restaurant_2024's pocket between two tables against the wall,
    0.7 m deep, seen from in front).

    A side ending at a seen end (`convex`) may be a bed's foot; but both jambs' sides running
    `depth` deep and ending so joined to nothing, the laser seen past both, are a passage running
    out into the open: an escape room's exit, 1 m long, its far mouth seen past."""
    k = gaps.shape[0]
    out = np.zeros(k, dtype=np.bool_)
    sin_a = math.sin(angle)
    for q in range(k):
        ax, ay, bx, by = gaps[q, 0], gaps[q, 1], gaps[q, 2], gaps[q, 3]
        ln = max(math.hypot(bx - ax, by - ay), 1e-12)
        ux, uy = (bx - ax) / ln, (by - ay) / ln
        robot_side = ux * (ry - ay) - uy * (rx - ax)
        free_ends = 0  # jambs whose side runs `depth` deep and ends free: the laser seen past it
        for j in range(2):
            free_here = False
            for which in range(2):
                w, f, dx, dy, dn = _jamb_wall(gaps, q, j, own_a[q] if j == 0 else own_b[q], walls, connected, which)
                if w < 0:
                    continue
                if prop[w, f] == convex:
                    free_here = free_here or (connected[w, f] < 0 and dn >= depth and abs(dx * ux + dy * uy) / dn < sin_a
                                              and (ux * dy - uy * dx) * robot_side < 0)
                    continue
                # as deep as `depth`, any end but a seen corner; down to `run_on`, only an end
                # floating into the view's edge (a pocket's side ends at its back in a corner)
                reach = run_on if prop[w, f] == floating and 0.0 < run_on < depth else depth
                if dn < reach or abs(dx * ux + dy * uy) / dn >= sin_a:
                    continue
                across = ux * dy - uy * dx
                if across * robot_side < 0 and abs(across) >= reach:
                    out[q] = True
            free_ends += free_here
        # both sides running out into the open (a short exit passage between two mouths); one
        # side ending at a seen end may be a bed's foot
        out[q] = out[q] or free_ends == 2
    return out


def _example_caps() -> tuple:
    walls = np.array([[0.0, 1.0, 0.2, 1.0], [-2.0, 0.0, 2.0, 0.0]])
    connected = np.full((2, 2), -1, dtype=np.int64)
    lengths = np.array([0.2, 4.0])
    return walls, connected, np.zeros(2, dtype=np.bool_), lengths, 0.1, 3.0, 0.35, 0.6, 1.2, 1.5, 0.3


@kernel(_example_caps)
def lone_cap_gaps(walls: np.ndarray, connected: np.ndarray, objects: np.ndarray, lengths: np.ndarray, rx: float,
                  ry: float, cap_max: float, min_width: float, max_width: float, building_min: float,
                  angle: float) -> np.ndarray:
    """The possible T-openings (K, 4) from lone end caps, from the cap's middle to the face."""
    n = walls.shape[0]
    caps = np.empty(n, dtype=np.int64)
    c = 0
    for i in range(n):
        if connected[i, 0] < 0 and connected[i, 1] < 0 and lengths[i] <= cap_max and lengths[i] > 1e-6 and not objects[i]:
            caps[c] = i
            c += 1
    if c == 0:
        return np.zeros((0, 4))
    caps = caps[:c]
    mid, normal = np.empty((c, 2)), np.empty((c, 2))
    for r in range(c):
        k = caps[r]
        ax, ay, bx, by = walls[k, 0], walls[k, 1], walls[k, 2], walls[k, 3]
        mid[r, 0], mid[r, 1] = (ax + bx) / 2, (ay + by) / 2
        dx, dy = (bx - ax) / lengths[k], (by - ay) / lengths[k]
        nx, ny = -dy, dx
        if (rx - mid[r, 0]) * nx + (ry - mid[r, 1]) * ny < 0:
            nx, ny = -nx, -ny
        normal[r, 0], normal[r, 1] = nx, ny
    t, hit = ray_hits(mid, normal, walls, caps, np.full(c, -1, dtype=np.int64))
    sin_a = math.sin(angle)
    gaps = np.empty((c, 4))
    own, other = np.empty(c, dtype=np.int64), np.empty(c, dtype=np.int64)
    g = 0
    for r in range(c):
        k = hit[r]
        if k < 0 or not min_width <= t[r] <= max_width or objects[k] or lengths[k] < building_min:
            continue
        ex, ey = walls[k, 2] - walls[k, 0], walls[k, 3] - walls[k, 1]
        if abs(ex * normal[r, 0] + ey * normal[r, 1]) / max(np.hypot(ex, ey), 1e-12) > sin_a:
            continue  # not facing: the wall runs along the gap
        gaps[g, 0], gaps[g, 1] = mid[r, 0], mid[r, 1]
        gaps[g, 2], gaps[g, 3] = mid[r, 0] + t[r] * normal[r, 0], mid[r, 1] + t[r] * normal[r, 1]
        own[g], other[g] = caps[r], k
        g += 1
    blocked = blocked_many(gaps[:g], walls, own[:g], other[:g])
    return gaps[:g][~blocked]


def _example_hidden() -> tuple:
    # a hallway's far end: its right side seen whole to its free end (1, -1.9), its left side
    # (x = 0) seen to -1.4, the rest grazing and unresolved
    walls = np.array([[1.0, 0.0, 1.0, -1.9], [0.0, 0.0, 0.0, -1.4]])
    connected = np.full((2, 2), -1, dtype=np.int64)
    prop = np.array([[1, 2], [1, 0]], dtype=np.int64)
    return walls, connected, prop, np.zeros(2, dtype=np.bool_), 0.2, 3.0, 0.5, 0, 2, 0.6, 1.3, 0.3


@kernel(_example_hidden)
def hidden_mouths(walls: np.ndarray, connected: np.ndarray, prop: np.ndarray, objects: np.ndarray, rx: float, ry: float,
                  frame_min: float, floating: int, convex: int, min_width: float, max_width: float, angle: float
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A passage's far end whose one side's end the laser does not resolve (seen down the
    passage at a few degrees): from P, a door frame's wall's seen free end (`convex`, joined to
    nothing), to Q, P's foot on a wall W2 side by side with it (parallel within `angle`, both
    ends' outward directions alike, at least `frame_min` long, no object), Q past W2's
    `floating` end by at most `max_width` and |P - Q| a door's width, and W2 seen from the robot
    (rx, ry) along its own line, within `angle` of it: grazing, its points too sparse for its
    end (a bed's side ending out of view is seen across). (K, 4) gaps P -> Q and their walls
    (K,), (K,)."""
    n = walls.shape[0]
    cos_a = math.cos(angle)
    segs = np.empty((n * n, 4))
    own_a = np.empty(n * n, dtype=np.int64)
    own_b = np.empty(n * n, dtype=np.int64)
    g = 0
    for i in range(n):
        li = math.hypot(walls[i, 2] - walls[i, 0], walls[i, 3] - walls[i, 1])
        if objects[i] or li < frame_min:
            continue
        for e in range(2):
            if prop[i, e] != convex or connected[i, e] >= 0:
                continue
            px, py = walls[i, 2 * e], walls[i, 2 * e + 1]
            ox, oy = (px - walls[i, 2 * (1 - e)]) / li, (py - walls[i, 2 * (1 - e) + 1]) / li
            for k in range(n):
                lk = math.hypot(walls[k, 2] - walls[k, 0], walls[k, 3] - walls[k, 1])
                if k == i or objects[k] or lk < frame_min:
                    continue
                for f in range(2):
                    if prop[k, f] != floating:
                        continue
                    fx, fy = walls[k, 2 * f], walls[k, 2 * f + 1]
                    vx, vy = (fx - walls[k, 2 * (1 - f)]) / lk, (fy - walls[k, 2 * (1 - f) + 1]) / lk
                    if ox * vx + oy * vy <= cos_a:
                        continue
                    sx, sy = fx - rx, fy - ry  # the robot's view of W2's end, along W2
                    if abs(sx * vx + sy * vy) <= cos_a * math.hypot(sx, sy):
                        continue
                    past = (px - fx) * vx + (py - fy) * vy  # P's foot on W2's line, past its end
                    if past <= 0.0 or past > max_width:
                        continue
                    qx, qy = fx + past * vx, fy + past * vy
                    width = math.hypot(px - qx, py - qy)
                    if width < min_width or width > max_width:
                        continue
                    segs[g, 0], segs[g, 1], segs[g, 2], segs[g, 3] = px, py, qx, qy
                    own_a[g], own_b[g] = i, k
                    g += 1
    return segs[:g].copy(), own_a[:g].copy(), own_b[:g].copy()
