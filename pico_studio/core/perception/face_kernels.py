"""The T-openings' compiled loops: a wall's end facing another wall's face (identify._doors says
what counts and why).

From a jamb candidate P (a wall's convex end, outward direction o) the ray P + t o meets a
wall k first (identify_kernels.ray_hits). A face seen in part is reached past its floating
end too (identify_kernels.extended_hits, within `reach`), unless the current scan's beam
towards that point goes on beyond it (`beam_at`). The gap P -> M = P + t o is a T-opening
candidate when

* k is not P's own wall nor the wall P joins, no object, no block's face (both ends convex
  and shorter than a building's wall, or the front of a block against a wall:
  `against_a_wall`), and a building's wall (|k| >= building_min) unless P's wall is;
* min_width <= t <= max_width, and M is no nearer than `cap_max` to a free convex end of k
  (a corner there, not a face) unless k is a building's wall on the robot's side of the gap's
  line, only that end past it (`_room_wall_past_the_line`); from a corner whose other wall runs
  on beyond the line, facing a face running on into the robot's side (`_corridor_mouth`), a
  possible door only; up to `wide_width` the gap is a door only from a building
  wall's end facing a building wall, seen deep and free beside the end (t_openings,
  `_side_seen`), or seen so in `evidence_scans` scans before (`tally`), its side hidden behind
  the wall itself now (a beam ending on the side, or the gap closed, bans the place), else a
  possible door; from a wall whose far end is no concave corner, a face turning into another
  wall in a concave corner within `depth` past the line, no ray reaching that deep, is a
  pocket's side: a possible door only (`_shallow_back`); rays through the gap ending within
  `depth` behind it back it (no door), unless P's wall is a room's (at least `room_wall` long,
  its far end a concave corner: no piece of furniture's side);
* k is about square to the ray: |e_k . o| / |e_k| <= sin(angle).

Where k fails the last two at a free corner, or is a piece no longer than `cap_max` askew to
the ray (a stub or a trim against a wall, a corner seen in fragments), the face may be a
building's wall just behind it, within `cap_max` further along the ray, met on it or up to
`occlusion` past one of its ends (the corner's fragments eat its last few cm; `_face_behind`),
meeting the same tests.

The current scan's beam towards a point Q (zero frame; robot at V, heading va): bearing
b = atan2(-sin(va) dx + cos(va) dy, cos(va) dx + sin(va) dy), (dx, dy) = Q - V, beam
rint((b - a0) / inc); it says 1 when it reaches more than `occlusion` beyond Q, -1 when it
ends more than that before Q, 0 otherwise or out of view.

The same floating-point operations in the same order as the Python they replace.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.core.perception.identify_kernels import (
    _beam_towards,
    away_normal,
    backed_beside_things,
    blocked_many,
    extended_hits,
    group_spans,
    line_hit,
    nearer_end,
    ray_hits,
    square_to,
    standing_in_shadow,
    turns_into_a_side,
)
from pico_studio.jit import kernel, njit


@njit
def beam_at(qx: float, qy: float, has_view: bool, ranges: np.ndarray, valid: np.ndarray, vx: float, vy: float,
            va: float, a0: float, inc: float, occlusion: float) -> int:
    """1: the scan's beam towards Q reaches more than `occlusion` beyond it; -1: it ends more
    than that before Q; 0: neither, or Q out of view."""
    if not has_view:
        return 0
    b = _beam_towards(qx, qy, ranges.shape[0], vx, vy, va, a0, inc)
    if b < 0 or not valid[b]:
        return 0
    r, dist = ranges[b], math.hypot(qx - vx, qy - vy)
    if r > dist + occlusion:
        return 1
    if r < dist - occlusion:
        return -1
    return 0


@njit
def _turns_into_a_glimpse(connected: np.ndarray, prop: np.ndarray, lengths: np.ndarray, k: int, e: int,
                          depth: float, convex: int, floating: int) -> bool:
    """Does wall k turn at its end e, a convex corner, into a side seen in part (its other end
    floating), seen at most `depth` long?"""
    j = connected[k, e]
    if j < 0 or prop[k, e] != convex or lengths[j] > depth:
        return False
    other = 1 if connected[j, 0] == k else 0
    return prop[j, other] == floating


@njit
def against_a_wall(connected: np.ndarray, prop: np.ndarray, lengths: np.ndarray, cap: float, short: float,
                   depth: float, convex: int, concave: int) -> np.ndarray:
    """(W,) bool: a wall longer than `cap`, shorter than `short`, turning at a convex corner into
    a wall at most `depth` long whose other end is a concave corner: a block's front against a
    wall (identify._doors)."""
    n = connected.shape[0]
    out = np.zeros(n, dtype=np.bool_)
    for k in range(n):
        if lengths[k] > cap and lengths[k] < short:
            out[k] = turns_into_a_side(connected, prop, lengths, k, 0, 0.0, depth, convex, concave) \
                or turns_into_a_side(connected, prop, lengths, k, 1, 0.0, depth, convex, concave)
    return out


@njit
def _side_seen(gap: np.ndarray, rx: float, ry: float, has_view: bool, ranges: np.ndarray, valid: np.ndarray,
               vx: float, vy: float, va: float, a0: float, inc: float, occlusion: float) -> int:
    """Is the side beyond a T-opening's jamb P (the gap P -> M) seen free: do the scan's beams
    towards P + f n, f = 1/2 and 1, n the gap's normal away from the robot R, |n| = |PM|, reach
    more than `occlusion` past those points, or return nothing? 1: both free; -1: a beam ends
    on one of them, within `occlusion` (a wall's corner there, its other wall running from P
    away from R); 0: neither (out of view, or ending before them: from a viewpoint behind the
    wall itself they end on it, hidden)."""
    if not has_view:
        return 0
    px, py = gap[0], gap[1]
    nx, ny = away_normal(gap, rx, ry)
    free = True
    for f in (0.5, 1.0):
        qx, qy = px + f * nx, py + f * ny
        b = _beam_towards(qx, qy, ranges.shape[0], vx, vy, va, a0, inc)
        if b < 0:
            return 0
        r, dist = ranges[b], math.hypot(qx - vx, qy - vy)
        if valid[b]:
            if abs(r - dist) <= occlusion:
                return -1
            if not r > dist + occlusion:
                free = False
        elif math.isfinite(r) and r > 0 and r < dist:  # (an invalid beam returned nothing, or beyond)
            free = False
    return 1 if free else 0


@njit
def _at_a_corner(walls: np.ndarray, prop: np.ndarray, connected: np.ndarray, k: int, mx: float, my: float,
                 cap_max: float, convex: int) -> bool:
    """Does M lie within `cap_max` of one of wall k's free convex ends?"""
    for b in range(2):
        if prop[k, b] == convex and connected[k, b] < 0 and \
                math.hypot(mx - walls[k, 2 * b], my - walls[k, 2 * b + 1]) < cap_max:
            return True
    return False


@njit
def _room_wall_past_the_line(walls: np.ndarray, prop: np.ndarray, connected: np.ndarray, k: int, mx: float,
                             my: float, px: float, py: float, ox: float, oy: float, vx: float, vy: float,
                             cap_max: float, convex: int) -> bool:
    """Is the free convex end of wall k within `cap_max` of M the only part of k beyond the gap's
    line P + t o (away from the viewpoint V), the rest of k on V's side: the room's own wall
    ending just past the doorway's line (a thick wall turning there), its face met near the corner?"""
    side_v = ox * (vy - py) - oy * (vx - px)
    for b in range(2):
        cx, cy = walls[k, 2 * b], walls[k, 2 * b + 1]
        if prop[k, b] != convex or connected[k, b] >= 0 or math.hypot(mx - cx, my - cy) >= cap_max:
            continue
        qx, qy = walls[k, 2 - 2 * b], walls[k, 3 - 2 * b]
        side_c = ox * (cy - py) - oy * (cx - px)
        side_q = ox * (qy - py) - oy * (qx - px)
        if side_c * side_v < 0 and side_q * side_v > 0:
            return True
    return False


@njit
def _corridor_mouth(gap: np.ndarray, walls: np.ndarray, connected: np.ndarray, lengths: np.ndarray, k: int,
                    face: int, rx: float, ry: float, cap_max: float) -> bool:
    """Does wall k turn at the gap's jamb P into a wall longer than `cap_max` whose far end lies
    more than `cap_max` beyond the gap's line (away from the robot R), while the face runs on
    more than `cap_max` on R's side of it: P a corner, that wall a corridor's side, the face
    its other side running straight on as the room's wall (no wall's end at P: a thick wall's
    cap is no longer; a face ending at the line, a corner there too, makes a passage's mouth)?"""
    j = connected[k, nearer_end(walls, k, gap[0], gap[1])]
    if j < 0 or lengths[j] <= cap_max:
        return False
    nx, ny = away_normal(gap, rx, ry)
    width = math.hypot(nx, ny)
    if width <= 1e-12:
        return False
    nx, ny = nx / width, ny / width  # depths past the gap's line, away from R, are along n

    def beyond(x: float, y: float) -> float:
        return nx * (x - gap[0]) + ny * (y - gap[1])

    e = nearer_end(walls, j, gap[0], gap[1])
    if beyond(walls[j, 2 - 2 * e], walls[j, 3 - 2 * e]) <= cap_max:
        return False
    return -min(beyond(walls[face, 0], walls[face, 1]), beyond(walls[face, 2], walls[face, 3])) > cap_max


@njit
def _along_a_wall(gap: np.ndarray, walls: np.ndarray, own: int, face: int, tol: float) -> bool:
    """Does a wall other than the gap's own two lie on the gap's line (both its ends within
    `tol` of it) over more than `tol` of the gap's middle 80%? (blocked_many counts only walls
    crossing the gap: one lying along it closes it as well; a fragment of the face's corner
    reaching a few cm into it does not.)"""
    dx, dy = gap[2] - gap[0], gap[3] - gap[1]
    length = math.hypot(dx, dy)
    if length <= 1e-12:
        return False
    ux, uy = dx / length, dy / length
    for k in range(walls.shape[0]):
        if k == own or k == face:
            continue
        s0 = (walls[k, 0] - gap[0]) * ux + (walls[k, 1] - gap[1]) * uy
        s1 = (walls[k, 2] - gap[0]) * ux + (walls[k, 3] - gap[1]) * uy
        n0 = abs((walls[k, 0] - gap[0]) * uy - (walls[k, 1] - gap[1]) * ux)
        n1 = abs((walls[k, 2] - gap[0]) * uy - (walls[k, 3] - gap[1]) * ux)
        if n0 <= tol and n1 <= tol and min(max(s0, s1), 0.9 * length) - max(min(s0, s1), 0.1 * length) > tol:
            return True
    return False


@njit
def _face_behind(px: float, py: float, ox: float, oy: float, walls: np.ndarray, lengths: np.ndarray,
                 objects: np.ndarray, block_face: np.ndarray, t0: float, depth: float, building_min: float,
                 own: int, joined: int, past: float) -> tuple[int, float]:
    """The first building wall (at least `building_min`, no object, no block's face, neither the
    ray's own wall nor the wall it joins) the ray P + t o meets at t0 < t <= t0 + depth, on it or
    up to `past` beyond one of its ends (the fragments of a corner of walls, the piece met first
    among them, eat a few cm of the face's end): (its index, t), or (-1, inf)."""
    best_k, best_t = -1, math.inf
    for j in range(walls.shape[0]):
        if j == own or j == joined or objects[j] or block_face[j] or lengths[j] < building_min:
            continue
        t, u = line_hit(px, py, ox, oy, walls, j)
        slack = past / lengths[j]
        if t > t0 and t <= t0 + depth and u >= -slack and u <= 1 + slack and t < best_t:
            best_k, best_t = j, t
    return best_k, best_t


@njit
def _met_in_part(rows: np.ndarray, pts: np.ndarray, out_dir: np.ndarray, walls: np.ndarray, floats: np.ndarray,
                 eligible: np.ndarray, span: float, hit_t: np.ndarray, hit_k: np.ndarray, has_view: bool,
                 ranges: np.ndarray, valid: np.ndarray, vx: float, vy: float, va: float, a0: float, inc: float,
                 occlusion: float) -> None:
    """The ends `rows` whose ray meets an `eligible` wall's line at most `span` past one of its
    floating ends (the wall seen in part, extended_hits) meet it there, unless the scan looks
    past that point (beam_at: the wall ends short of it): `hit_t`, `hit_k` set in place."""
    ext_t, ext_k = extended_hits(pts[rows], out_dir[rows], walls, floats, eligible, span)
    for q in range(rows.shape[0]):
        r = rows[q]
        if ext_k[q] >= 0:
            px, py = pts[r, 0] + ext_t[q] * out_dir[r, 0], pts[r, 1] + ext_t[q] * out_dir[r, 1]
            if beam_at(px, py, has_view, ranges, valid, vx, vy, va, a0, inc, occlusion) <= 0:
                hit_t[r], hit_k[r] = ext_t[q], ext_k[q]


def _example_faces() -> tuple:
    walls = np.array([[0.0, 0.0, 0.0, 2.0], [0.0, 2.0, 0.2, 2.0], [1.0, -1.0, 1.0, 4.0]])
    connected = np.array([[-1, 1], [0, -1], [-1, -1]], dtype=np.int64)
    prop = np.array([[0, 2], [2, 2], [0, 0]], dtype=np.int64)
    lengths = np.array([2.0, 0.2, 5.0])
    pts, out_dir, far = np.array([[0.2, 2.0]]), np.array([[1.0, 0.0]]), np.array([[0.0, 2.0]])
    one, no = np.array([True]), np.array([False])
    ranges, valid = np.array([2.0, 2.0, 2.0]), np.array([True, True, True])
    return (pts, out_dir, far, np.array([1], dtype=np.int64), np.array([1], dtype=np.int64), one, no, no, no,
            walls, connected, prop, np.zeros(3, dtype=np.bool_), lengths, True, ranges, valid, 0.0, 0.0, 0.0, -0.1,
            0.1, 0.6, 1.2, 1.5, 0.12, 1.5, 1.0, 0.3, 0.5, 0.1, 0.2, 0, 2, 3)


@kernel(_example_faces)
def face_gaps(pts: np.ndarray, out_dir: np.ndarray, far: np.ndarray, wi: np.ndarray, we: np.ndarray,
              building: np.ndarray, cornered: np.ndarray, weak: np.ndarray, glimpse: np.ndarray, walls: np.ndarray,
              connected: np.ndarray, prop: np.ndarray, objects: np.ndarray, lengths: np.ndarray, has_view: bool,
              ranges: np.ndarray, valid: np.ndarray, vx: float, vy: float, va: float, a0: float, inc: float,
              min_width: float, max_width: float, wide_width: float, cap_max: float, building_min: float,
              object_max: float, angle: float, reach: float, occlusion: float, continuation: float, floating: int, convex: int,
              concave: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                     np.ndarray]:
    """The T-opening candidates from the ends `pts` (F, 2) (outward `out_dir`, far end `far`, wall
    `wi`, end `we`; which rule each end passed: `building`, `cornered`, `weak`, `glimpse`):
    (gaps (G, 4) from the end to the face, own wall (G,), face wall (G,), weak (G,), glimpse
    (G,), beyond (G,) int64: for a weak end, the scan's beam at the wall's far end continued
    by `continuation` (beam_at), else 0; and missed (F,): the end's ray met no wall within
    `max_width`, not even past a floating end)."""
    f, n_walls = pts.shape[0], walls.shape[0]
    hit_t, hit_k = ray_hits(pts, out_dir, walls, np.full(f, -1, dtype=np.int64), np.full(f, -1, dtype=np.int64))
    # a face seen in part: met past its floating end, unless the scan looks past that point
    miss = np.empty(f, dtype=np.int64)
    nm = 0
    for r in range(f):
        if hit_k[r] < 0 or hit_t[r] > wide_width:
            miss[nm] = r
            nm += 1
    floats = np.empty((n_walls, 2), dtype=np.bool_)
    eligible = np.empty(n_walls, dtype=np.bool_)
    still = np.empty(nm, dtype=np.int64)
    ns = 0
    if nm > 0:
        for k in range(n_walls):
            floats[k, 0], floats[k, 1] = prop[k, 0] == floating, prop[k, 1] == floating
        if reach > 0:
            for k in range(n_walls):
                eligible[k] = lengths[k] >= building_min and not objects[k]
            _met_in_part(miss[:nm], pts, out_dir, walls, floats, eligible, reach, hit_t, hit_k, has_view, ranges,
                         valid, vx, vy, va, a0, inc, occlusion)
        # ...or, from a building wall's end, a face seen only through the gap: a piece of any
        # length floating at both ends, the jamb's end hiding it on one side and the view's edge
        # on the other (a wall beyond a doorway seen obliquely, the room's side of it out of
        # view; or through a gap beside the jamb, that gap's far corner hiding the rest), met
        # on its line past its floating end, unless the scan looks past that point (a partition's
        # face beside a block's corner, ending short of the line, is seen to end there): here
        # within `occlusion`, below (once the lone jambs are known) up to `reach`
        for q in range(nm):
            if building[miss[q]] and hit_k[miss[q]] < 0:
                still[ns] = miss[q]
                ns += 1
        if ns > 0:
            for k in range(n_walls):
                eligible[k] = floats[k, 0] and floats[k, 1] and not objects[k]
            _met_in_part(still[:ns], pts, out_dir, walls, floats, eligible, occlusion, hit_t, hit_k, has_view,
                         ranges, valid, vx, vy, va, a0, inc, occlusion)
    missed = np.empty(f, dtype=np.bool_)
    for r in range(f):
        # a face beyond max_width leaves the end a lone jamb too: the map proves that one (from the
        # end along its wall) where the wide gap's far side is no jamb of its opening
        missed[r] = hit_k[r] < 0 or hit_t[r] > max_width
    if ns > 0 and reach > occlusion:
        # ...and so does a face seen through the gap met only farther than `occlusion` past its
        # floating end: the T-opening to it may be hidden or refused, and the end stays the map's
        # to prove (t_openings drops the lone jamb where that door is found)
        for q in range(ns):
            if hit_k[still[q]] >= 0:
                still[q] = -1
        rest = still[:ns][still[:ns] >= 0]
        if rest.shape[0] > 0:
            _met_in_part(rest, pts, out_dir, walls, floats, eligible, reach, hit_t, hit_k, has_view, ranges, valid,
                         vx, vy, va, a0, inc, occlusion)
    # the face is a building's: no block's face, nor a block's front against a wall
    block_face = against_a_wall(connected, prop, lengths, cap_max, building_min, object_max, convex, concave)
    for k in range(n_walls):
        if prop[k, 0] == convex and prop[k, 1] == convex and lengths[k] < building_min:
            block_face[k] = True
    gaps = np.empty((f, 4))
    own, face = np.empty(f, dtype=np.int64), np.empty(f, dtype=np.int64)
    is_weak, is_glimpse = np.empty(f, dtype=np.bool_), np.empty(f, dtype=np.bool_)
    beyond = np.zeros(f, dtype=np.int64)
    sin_a = math.sin(angle)
    g = 0
    for r in range(f):
        k, t = hit_k[r], hit_t[r]
        if k < 0 or k == wi[r] or objects[k] or block_face[k] or connected[wi[r], we[r]] == k:
            continue
        if (cornered[r] or weak[r] or glimpse[r]) and lengths[k] < building_min:
            continue
        if not (min_width <= t and t <= wide_width):  # wider than max_width: a possible door at most
            continue
        mx, my = pts[r, 0] + t * out_dir[r, 0], pts[r, 1] + t * out_dir[r, 1]
        corner = _at_a_corner(walls, prop, connected, k, mx, my, cap_max, convex)
        if corner and has_view and lengths[k] >= building_min and \
                _room_wall_past_the_line(walls, prop, connected, k, mx, my, pts[r, 0], pts[r, 1], out_dir[r, 0],
                                         out_dir[r, 1], vx, vy, cap_max, convex):
            # the room's own wall (a building's) ending just past the doorway's line, turning
            # there: its face met near that corner, a T-opening; a table's corner poking into
            # the line is the other way round (its side runs on beyond the line)
            corner = False
        if corner or not square_to(walls, k, out_dir[r, 0], out_dir[r, 1], sin_a):
            # a piece's free corner where the ray meets it (a table's end), or a piece no longer
            # than a wall's thickness askew to it (a stub or a trim against a wall, a corner seen
            # in fragments): the face is a building wall's just behind it, within a wall's
            # thickness, or none (what stands in the gap itself is blocked_many's to find);
            # any other wall askew runs along the gap
            if not (corner or lengths[k] <= cap_max):
                continue
            k, t = _face_behind(pts[r, 0], pts[r, 1], out_dir[r, 0], out_dir[r, 1], walls, lengths, objects,
                                block_face, t, cap_max, building_min, wi[r], connected[wi[r], we[r]], occlusion)
            if k < 0 or t > wide_width:
                continue
            mx, my = pts[r, 0] + t * out_dir[r, 0], pts[r, 1] + t * out_dir[r, 1]
            if _at_a_corner(walls, prop, connected, k, mx, my, cap_max, convex) or \
                    not square_to(walls, k, out_dir[r, 0], out_dir[r, 1], sin_a):
                continue
        gaps[g, 0], gaps[g, 1], gaps[g, 2], gaps[g, 3] = pts[r, 0], pts[r, 1], mx, my
        own[g], face[g], is_weak[g], is_glimpse[g] = wi[r], k, weak[r], glimpse[r]
        if weak[r]:
            # a short wall's far end that the scan looks past, in line with the wall, ends there
            beyond[g] = beam_at(far[r, 0] - continuation * out_dir[r, 0], far[r, 1] - continuation * out_dir[r, 1],
                                has_view, ranges, valid, vx, vy, va, a0, inc, occlusion)
        g += 1
    return (gaps[:g].copy(), own[:g].copy(), face[:g].copy(), is_weak[:g].copy(), is_glimpse[:g].copy(),
            beyond[:g].copy(), missed)


BANNED = -1e6  # a contradicted T-opening's count: never promoted


@njit
def tally(evidence: np.ndarray, gaps: np.ndarray, support: np.ndarray, against: np.ndarray, min_width: float,
          angle: float, keep: int, reopen: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Count scans for the T-openings on a short wall: `evidence` (E, 5) rows (middle x, y, unit
    gap direction x, y, supporting scans), `gaps` (G, 4) this scan's candidates, `support` (G,)
    free rays seen through the gap, `against` (G,) blocked or backed now. A gap is the first
    record whose middle lies within min_width / 2 of its middle, about parallel (|u_r . u| >
    cos(angle)); a supporting scan adds one (the record follows the latest view), a
    contradicting one bans the place (BANNED) for good. With `reopen` (a building wall's
    T-openings, remembered only where seen closed) a supporting scan counts nothing: it reopens
    a banned place (count 0) and makes no record where none was, so the short walls' counts are
    not crowded out. Returns the records (at most `keep`, the largest |count| first, stable) and
    each gap's count."""
    e, g = evidence.shape[0], gaps.shape[0]
    rows = np.empty((e + g, 5))
    rows[:e] = evidence
    n = e
    counts = np.zeros(g, dtype=np.int64)
    cos_a = math.cos(angle)
    for m in range(g):
        mx, my = (gaps[m, 0] + gaps[m, 2]) / 2, (gaps[m, 1] + gaps[m, 3]) / 2
        ln = max(math.hypot(gaps[m, 2] - gaps[m, 0], gaps[m, 3] - gaps[m, 1]), 1e-12)
        ux, uy = (gaps[m, 2] - gaps[m, 0]) / ln, (gaps[m, 3] - gaps[m, 1]) / ln
        hit = -1
        for r in range(n):
            if math.hypot(rows[r, 0] - mx, rows[r, 1] - my) <= min_width / 2 and \
                    abs(rows[r, 2] * ux + rows[r, 3] * uy) > cos_a:
                hit = r
                break
        if against[m]:
            if hit < 0:
                hit = n
                n += 1
            rows[hit, 0], rows[hit, 1], rows[hit, 2], rows[hit, 3], rows[hit, 4] = mx, my, ux, uy, BANNED
            counts[m] = int(BANNED)
            continue
        if not support[m]:
            counts[m] = int(rows[hit, 4]) if hit >= 0 else 0
            continue
        if reopen:
            if hit >= 0 and rows[hit, 4] < 0:
                rows[hit, 4] = 0.0
            counts[m] = int(rows[hit, 4]) if hit >= 0 else 0
            continue
        if hit < 0:
            hit = n
            n += 1
            rows[hit, 4] = 0.0
        rows[hit, 0], rows[hit, 1], rows[hit, 2], rows[hit, 3], rows[hit, 4] = mx, my, ux, uy, rows[hit, 4] + 1.0
        counts[m] = int(rows[hit, 4])
    out = rows[:n]
    if n > keep:
        out = out[np.argsort(-np.abs(out[:, 4]), kind="mergesort")[:keep]]
    return out.copy(), counts


@njit
def _hidden(gap: np.ndarray, has_view: bool, ranges: np.ndarray, valid: np.ndarray, vx: float, vy: float,
            va: float, a0: float, inc: float, occlusion: float) -> bool:
    """Do the scan's beams towards two of the gap's points at a quarter, half and three quarters
    end more than `occlusion` before them (something stands in front)?"""
    n = 0
    for f in (0.25, 0.5, 0.75):
        qx, qy = gap[0] + f * (gap[2] - gap[0]), gap[1] + f * (gap[3] - gap[1])
        if beam_at(qx, qy, has_view, ranges, valid, vx, vy, va, a0, inc, occlusion) < 0:
            n += 1
    return n >= 2


@njit
def _face_ends_past(gap: np.ndarray, face: np.ndarray, rx: float, ry: float) -> tuple[float, float]:
    """How far each end E of the face (x0, y0, x1, y1) lies past the gap's line away from the
    robot R: n . (E - P) / |n|, n = away_normal."""
    nx, ny = away_normal(gap, rx, ry)
    den = max(math.hypot(nx, ny), 1e-12)
    return ((nx * (face[0] - gap[0]) + ny * (face[1] - gap[1])) / den,
            (nx * (face[2] - gap[0]) + ny * (face[3] - gap[1])) / den)


@njit
def _runs_on(gap: np.ndarray, face: np.ndarray, far_props: np.ndarray, rx: float, ry: float, run_on: float,
             floating: int) -> bool:
    """Is the face (x0, y0, x1, y1) a T-opening's gap (P -> M) meets seen running on at least
    `run_on` past the gap's line, away from the robot R, its end there floating (out of view,
    no corner: not a pocket's side ending at its back)? (_face_ends_past)"""
    s0, s1 = _face_ends_past(gap, face, rx, ry)
    return (s0 >= run_on and far_props[0] == floating) or (s1 >= run_on and far_props[1] == floating)


@njit
def _face_seen_past(gap: np.ndarray, face: np.ndarray, rx: float, ry: float, run_on: float, has_view: bool,
                    ranges: np.ndarray, valid: np.ndarray, vx: float, vy: float, va: float, a0: float, inc: float,
                    occlusion: float) -> bool:
    """Does the scan see the face (x0, y0, x1, y1) of a T-opening's gap (P -> M) `run_on` past the
    gap's line, away from the robot R: the beam towards the point F of the face's line that deep
    ends within `occlusion` of that line, at least `run_on` - `occlusion` past the gap's line?"""
    if not has_view:
        return True
    nx, ny = away_normal(gap, rx, ry)
    den = math.hypot(nx, ny)
    fx, fy = face[2] - face[0], face[3] - face[1]
    fl = math.hypot(fx, fy)
    if den <= 1e-12 or fl <= 1e-12:
        return False
    nx, ny = nx / den, ny / den
    ux, uy = fx / fl, fy / fl
    along = ux * nx + uy * ny  # the face's direction against the normal: how deep a step along it goes
    if abs(along) <= 1e-6:
        return False
    t = run_on / along  # from M along the face to F
    qx, qy = gap[2] + t * ux, gap[3] + t * uy
    b = _beam_towards(qx, qy, ranges.shape[0], vx, vy, va, a0, inc)
    if b < 0 or not valid[b]:
        return False
    dx, dy = qx - vx, qy - vy
    dist = math.hypot(dx, dy)
    if dist <= 1e-12:
        return False
    ex, ey = vx + ranges[b] * dx / dist, vy + ranges[b] * dy / dist
    off = abs((ex - face[0]) * uy - (ey - face[1]) * ux)
    deep = (ex - gap[0]) * nx + (ey - gap[1]) * ny
    return off <= occlusion and deep >= run_on - occlusion


@njit
def _shallow_back(gap: np.ndarray, face: np.ndarray, far_props: np.ndarray, rx: float, ry: float, depth: float,
                  occlusion: float, concave: int) -> bool:
    """Does the face (x0, y0, x1, y1) a T-opening's gap (P -> M) meets turn, in a concave corner
    more than `occlusion` and less than `depth` past the gap's line away from the robot R, into
    another wall: the pocket's back beside a table standing against a wall? (_face_ends_past)"""
    s0, s1 = _face_ends_past(gap, face, rx, ry)
    return (occlusion < s0 < depth and far_props[0] == concave) or (occlusion < s1 < depth and far_props[1] == concave)


@njit
def _something_stands_there(gap: np.ndarray, walls: np.ndarray, prop: np.ndarray, objects: np.ndarray,
                            group: np.ndarray, own: int, face: int, rx: float, ry: float, depth: float,
                            convex: int) -> bool:
    """Does a wall (no small object's: a chair in a pocket is one) with a seen end stand in the
    gap's shadow (identify_kernels.standing_in_shadow)? The laser saw past it into the space
    behind the opening: a cabinet standing in the room beyond, no pocket."""
    standing = standing_in_shadow(gap, walls, prop, objects, group, own, face, rx, ry, depth, convex)
    for k in range(walls.shape[0]):
        if standing[k] and not objects[k]:
            return True
    return False


@njit
def _same_place(a: np.ndarray, b: np.ndarray, min_width: float, angle: float) -> bool:
    """Two gaps about parallel whose middles lie within min_width / 2: one opening."""
    max_, may = (a[0] + a[2]) / 2, (a[1] + a[3]) / 2
    mbx, mby = (b[0] + b[2]) / 2, (b[1] + b[3]) / 2
    if math.hypot(max_ - mbx, may - mby) > min_width / 2:
        return False
    ux, uy, vx, vy = a[2] - a[0], a[3] - a[1], b[2] - b[0], b[3] - b[1]
    cos = abs(ux * vx + uy * vy) / max(math.hypot(ux, uy) * math.hypot(vx, vy), 1e-12)
    return cos > math.cos(angle)


def _example_openings() -> tuple:
    (pts, out_dir, far, wi, we, _, _, _, _, walls, connected, prop, objects, lengths, has_view, ranges, valid, vx, vy,
     va, a0, inc, *_) = _example_faces()
    one = np.array([True])
    return (pts, out_dir, far, wi, we, one, one, one, walls, connected, prop, objects, lengths, np.zeros((0, 4)),
            np.zeros((0, 5)), 0.0, 0.0, has_view, ranges, valid, vx, vy, va, a0, inc, 0.6, 1.2, 1.5, 0.12, 1.5, 1.0, 0.3, 0.5,
            0.1, 0.2, 0.3, 0.5, 1, 3, 16, 0.5, 2.2, 0, 2, 3)


@kernel(_example_openings)
def t_openings(pts: np.ndarray, out_dir: np.ndarray, far: np.ndarray, wi: np.ndarray, we: np.ndarray,
               is_convex: np.ndarray, long: np.ndarray, capped: np.ndarray, walls: np.ndarray, connected: np.ndarray,
               prop: np.ndarray, objects: np.ndarray, lengths: np.ndarray, doors: np.ndarray, evidence: np.ndarray,
               rx: float, ry: float, has_view: bool, ranges: np.ndarray, valid: np.ndarray, vx: float, vy: float, va: float, a0: float,
               inc: float, min_width: float, max_width: float, wide_width: float, cap_max: float, building_min: float,
               object_max: float, angle: float, reach: float, occlusion: float, continuation: float, depth: float,
               backed_share: float, min_free_rays: int, evidence_scans: int, evidence_max: int, run_on: float,
               room_wall: float, floating: int, convex: int, concave: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The T-openings from the jamb candidates (identify._doors says which ends count and why):
    (doors (N, 4) new ones, not the same place as one of `doors` nor one found before; possible
    (P, 4): weak ends still counting scans, then glimpses; evidence: the records after this
    scan, `evidence` itself when no weak end was tested; lone jambs (J, 4): a building wall's
    end whose ray meets no wall within `max_width` (a long one's too when its far end makes it a
    block's front), from the end `max_width` on along it — a jamb whose other side is out of
    view, for the map to prove)."""
    c = wi.shape[0]
    building = np.empty(c, dtype=np.bool_)
    cornered, weak, glimpse = np.empty(c, dtype=np.bool_), np.empty(c, dtype=np.bool_), np.empty(c, dtype=np.bool_)
    face = np.empty(c, dtype=np.int64)
    # a building wall's end taken for a block's front's: no T-opening's jamb, but still a lone
    # jamb when nothing faces it (a corridor's wall 2.8 m long whose far end turns into a doorway's
    # side seen in part; the scan's points in its line past a gap make it a door, line_jambs)
    blocked_end = np.zeros(c, dtype=np.bool_)
    f = 0
    for r in range(c):
        i, far_end = wi[r], prop[wi[r], 1 - we[r]]
        building[r] = lengths[i] >= building_min or (long[r] and capped[r])
        # a block's front against a wall as long as a building's wall (a table 1.4-1.6 m long:
        # its far end turns into a side longer than an end cap, a partition's cap being none) is
        # only ever a possible door's jamb, for the map to prove (a glimpse); an exit hallway's
        # side turning into the short piece of room wall beside it has the same shape; so is one
        # whose far end turns at a convex corner into a side seen in part (its first few cm, the
        # rest hidden or out of view: the table's back, the pocket's, unseen)
        block = building[r] and (
            turns_into_a_side(connected, prop, lengths, i, 1 - we[r], cap_max, object_max, convex, concave)
            or _turns_into_a_glimpse(connected, prop, lengths, i, 1 - we[r], object_max, convex, floating))
        blocked_end[r] = block
        building[r] = building[r] and not block
        cornered[r] = long[r] and far_end == concave and not building[r] and not block
        weak[r] = (long[r] or capped[r]) and not building[r] and not block and far_end == floating and evidence_scans > 0
        glimpse[r] = block or (not building[r] and not cornered[r] and not weak[r] and far_end == floating)
        if is_convex[r] and (building[r] or cornered[r] or weak[r] or glimpse[r]):
            face[f] = r
            f += 1
    empty = np.zeros((0, 4))
    if f == 0:
        return empty, empty, evidence, empty
    face = face[:f]
    g, oa, ob, wk, gl_, beyond, missed = face_gaps(
        pts[face], out_dir[face], far[face], wi[face], we[face], building[face], cornered[face], weak[face],
        glimpse[face], walls, connected, prop, objects, lengths, has_view, ranges, valid, vx, vy, va, a0, inc,
        min_width, max_width, wide_width, cap_max, building_min, object_max, angle, reach, occlusion, continuation,
        floating, convex, concave)
    lone = np.empty((f, 4))
    j = 0
    for q in range(f):
        r = face[q]
        if (building[r] or blocked_end[r]) and missed[q]:
            lone[j, 0], lone[j, 1] = pts[r, 0], pts[r, 1]
            lone[j, 2], lone[j, 3] = pts[r, 0] + max_width * out_dir[r, 0], pts[r, 1] + max_width * out_dir[r, 1]
            j += 1
    lone = lone[:j].copy()
    n = g.shape[0]
    if n == 0:
        return empty, empty, evidence, lone
    # no wall across the gap (blocked_many)...
    bad = blocked_many(g, walls, oa, ob)
    group, _ = group_spans(walls, connected)  # connected walls' labels (a thing standing apart is no jamb's)
    for m in range(n):  # ...or closed by a wall lying on its line (a wall piece beside an exit)
        bad[m] = bad[m] or _along_a_wall(g[m], walls, oa[m], ob[m], occlusion)
    # seen edge-on a T-opening's rays end by its face and say nothing; its jamb and face were
    # tested already, so no free ray is asked for; a ray ending on an object, or on a wall whose
    # seen end stands in the gap's shadow (a box, a cabinet standing in the room behind, the
    # laser seeing past it), says nothing of a back either
    backed_g, free_g, deep_g, back_g = backed_beside_things(g, walls, oa, ob, rx, ry, has_view, ranges, valid, vx, vy,
                                                            va, a0, inc, np.ones(n, dtype=np.bool_), objects,
                                                            occlusion, depth, cap_max, backed_share, prop, group,
                                                            convex)
    for m in range(n):
        # ...but a room's wall (at least `room_wall` long, its far end a concave corner: longer
        # than a bed's side or a table's) opens whatever stands behind its end: a cabinet 0.8 m
        # inside the room backs the doorway as a table's side backs a pocket
        if backed_g[m] and lengths[oa[m]] >= room_wall and \
                prop[oa[m], 1 - nearer_end(walls, oa[m], g[m, 0], g[m, 1])] == concave:
            backed_g[m] = False
    bad |= backed_g
    for m in range(n):
        # a corridor's mouth beside a room's wall running straight on: only ever a possible
        # door, for the map to prove
        if not bad[m] and _corridor_mouth(g[m], walls, connected, lengths, oa[m], ob[m], rx, ry, cap_max):
            gl_[m], wk[m] = True, False
    possible = np.empty((n, 4))
    p = 0
    # wider than a door (a wall's end facing a face up to `wide_width` on): among furniture as
    # often a passage as a doorway, and a room's corner 1.3-1.5 m from a corridor's wall (its
    # other wall unseen edge-on) is one too. A door only from a building wall's end facing a
    # building wall's face, seen through deep, the side beyond the end seen free (a wall's free
    # end, not a corner); else only ever a possible door, for the map to prove (no evidence
    # counted)
    strong = ~wk & ~gl_  # a building wall's end or a door frame's in a room's corner: a door from one scan
    deep = deep_g >= max(min_free_rays, 1)  # seen through deep
    wide = np.zeros(n, dtype=np.bool_)
    side = np.zeros(n, dtype=np.int64)
    for m in range(n):
        if math.hypot(g[m, 2] - g[m, 0], g[m, 3] - g[m, 1]) > max_width:
            strong[m] = False
            if not wk[m] and not gl_[m] and lengths[ob[m]] >= building_min:
                wide[m] = True
                side[m] = _side_seen(g[m], rx, ry, has_view, ranges, valid, vx, vy, va, a0, inc, occlusion)
            else:
                if not bad[m] and not _hidden(g[m], has_view, ranges, valid, vx, vy, va, a0, inc, occlusion):
                    possible[p] = g[m]
                    p += 1
                bad[m], wk[m], gl_[m] = True, False, False
    wide_rows = np.flatnonzero(wide)
    if wide_rows.shape[0] > 0:
        # ...seen so in `evidence_scans` scans it is remembered, as a short wall's T-opening is:
        # seen again from beside its wall (the side hidden behind the wall itself, its rays maybe
        # landing on the face) it stays a door; a beam ending on the side (a room's corner, its
        # other wall there) or the gap closed bans the place
        free = ~bad[wide_rows] & deep[wide_rows] & (side[wide_rows] > 0)
        evidence, count = tally(evidence, g[wide_rows], free, bad[wide_rows] | (side[wide_rows] < 0), min_width,
                                angle, evidence_max)
        for q in range(wide_rows.shape[0]):
            m = wide_rows[q]
            if free[q] or (not bad[m] and evidence_scans > 0 and count[q] >= evidence_scans):
                continue
            if not bad[m] and not _hidden(g[m], has_view, ranges, valid, vx, vy, va, a0, inc, occlusion):
                possible[p] = g[m]
                p += 1
            bad[m] = True
    weak_rows = np.flatnonzero(wk)
    if weak_rows.shape[0] > 0:
        # a scan supports the opening when a ray through the gap reached free space, or when
        # rays passed it and its face is seen running on `run_on` past its line into the view's
        # edge: seen steeply, the rays through a T-opening land on its own face a few dm on,
        # and a pocket's side ends at the pocket's back in a corner. Seen by this scan: the
        # local map remembering the face run on is no evidence (from farther along the gap's
        # line the jamb's own wall hides it, and a pocket's back may be what it hides)
        sure = ~bad & deep
        for m in range(n):
            if not sure[m] and not bad[m] and run_on > 0 and free_g[m] >= max(min_free_rays, 1):
                sure[m] = _runs_on(g[m], walls[ob[m]], prop[ob[m]], rx, ry, run_on, floating) and \
                    _face_seen_past(g[m], walls[ob[m]], rx, ry, run_on, has_view, ranges, valid, vx, vy, va, a0, inc,
                                    occlusion)
        against = bad[weak_rows] | (beyond[weak_rows] > 0)
        support = sure[weak_rows] & (beyond[weak_rows] <= 0) & ~against
        evidence, count = tally(evidence, g[weak_rows], support, against, min_width, angle, evidence_max)
        for q in range(weak_rows.shape[0]):
            m = weak_rows[q]
            if count[q] < evidence_scans:  # not proven yet (nor banned): for the map to confirm
                if count[q] >= 0 and not bad[m]:
                    possible[p] = g[m]
                    p += 1
                bad[m] = True
    strong_rows = np.flatnonzero(strong)
    if strong_rows.shape[0] > 0:
        # ...but a pocket seen closed once (its back within `depth`: a table's side by a wall)
        # stays closed when seen again edge-on, rays saying nothing: only ever a possible door,
        # for the map to prove, until rays are seen through it deep
        through = ~bad[strong_rows] & deep[strong_rows]
        closed = backed_g[strong_rows] & back_g[strong_rows]  # on a back between the jambs, not a passage's side
        # the same gap: its middle within `occlusion` / 2 (a gap from the same end to another
        # face, a wall seen before the nearer one came into the local map, is another place)
        evidence, count = tally(evidence, g[strong_rows], through, closed, occlusion, angle, evidence_max, True)
        for q in range(strong_rows.shape[0]):
            m = strong_rows[q]
            if count[q] < 0 and not bad[m]:
                possible[p] = g[m]
                p += 1
                bad[m] = True
    for m in range(n):
        # seen steeply a pocket's rays all land on its side wall's face and say nothing; from a
        # wall whose far end is no concave corner (a table 1.5-1.6 m long against a wall: its
        # front a building's length, its far end free or turning into its side), that face
        # turning into the wall behind the table within `depth` of the line is its back: only
        # ever a possible door, for the map to prove (a room's wall ending in the room's corner
        # keeps its door beside a cabinet standing against the doorway's side wall)
        k = oa[m]
        far_end = 1 - nearer_end(walls, k, g[m, 0], g[m, 1])
        if not bad[m] and deep_g[m] < max(min_free_rays, 1) and prop[k, far_end] != concave \
                and _shallow_back(g[m], walls[ob[m]], prop[ob[m]], rx, ry, depth, occlusion, concave) \
                and not _something_stands_there(g[m], walls, prop, objects, group, oa[m], ob[m], rx, ry, depth, convex):
            gl_[m] = True
        if gl_[m] and not bad[m]:
            possible[p] = g[m]
            p += 1
        bad[m] = bad[m] or gl_[m]
    found = np.empty((n, 4))
    d = 0
    for m in range(n):
        if bad[m] or _hidden(g[m], has_view, ranges, valid, vx, vy, va, a0, inc, occlusion):
            continue
        same = False
        for k in range(doors.shape[0]):
            if _same_place(g[m], doors[k], min_width, angle):
                same = True
                break
        for k in range(d):
            if not same and _same_place(g[m], found[k], min_width, angle):
                same = True
        if not same:
            found[d] = g[m]
            d += 1
    # a lone jamb whose end's T-opening was found is that door (its face met past a glimpse's end)
    keep = np.ones(lone.shape[0], dtype=np.bool_)
    for j in range(lone.shape[0]):
        for k in range(d):
            if lone[j, 0] == found[k, 0] and lone[j, 1] == found[k, 1]:
                keep[j] = False
    return found[:d].copy(), possible[:p].copy(), evidence, lone[keep]
