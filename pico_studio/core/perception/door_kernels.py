"""Identify's door pipeline between jambs, compiled (identify._doors says what counts and why).

Jamb doors. The door-point candidates (identify_kernels.jamb_candidates) are wall ends P_i
with outward direction o_i = (P_i - F_i) / |P_i - F_i| (F_i: the wall's far end). Their pairs
a door's width apart (identify_kernels.door_pairs) are tested as gaps P_i -> P_j: crossed by
another wall (blocked_many), else looked through (identify_kernels.backed: backed, and how
many rays were seen to pass). A door is a door-shaped pair, neither blocked nor backed, with
at least `min_free_rays` rays seen through, best aligned first (the smaller of the two
offsets |pq x o|), one per opening (distinct_openings) and one per jamb (a jamb one of them
continues in its wall's line frames no other leaving it in another direction:
identify_kernels.leaves_a_claimed_jamb). A possible door is a possible pair not blocked nor
backed.

Loose walls. From a floating end the ray P + t o meets a wall k first (ray_hits) at t in
[min_width, facing]; k is not P's own wall, the wall P joins, nor an object: a possible door
P -> P + t o.

A possible door whose middle lies within `dist` of a door's middle is that door (`away_from`).

The same floating-point operations in the same order as the numpy they replace.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.core.perception.identify_kernels import (
    SAME_OPENING_ANGLE,
    SAME_POINT,
    _in_line_beyond,
    backed,
    blocked_many,
    claimed_jambs,
    distinct_openings,
    door_pairs,
    jamb_candidates,
    leaves_a_claimed_jamb,
    ray_hits,
    turns_into_a_side,
)
from pico_studio.jit import kernel, njit


def _example_jambs() -> tuple:
    walls = np.array([[0.0, 0.0, 2.0, 0.0], [2.9, 0.0, 5.0, 0.0], [0.0, 3.0, 5.0, 3.0]])
    connected = np.full((3, 2), -1, dtype=np.int64)
    prop = np.array([[0, 2], [2, 0], [0, 0]], dtype=np.int64)
    ranges, valid = np.array([4.0, 4.0, 4.0]), np.array([True, True, True])
    return (walls, connected, prop, np.zeros(3, dtype=np.bool_), 2.45, -1.0, True, ranges, valid, 2.45, -1.0, 1.57,
            -0.3, 0.3, 0.12, 1.0, 1.5, 1.5, 0.25, 0.6, 1.2, 1.5, 0.3, 0.1, 0.05, 1, 0.1, 0.3, 0.5, 0.02, 0, 2, 3)


@kernel(_example_jambs)
def jamb_doors(walls: np.ndarray, connected: np.ndarray, prop: np.ndarray, objects: np.ndarray, rx: float, ry: float,
               has_view: bool, ranges: np.ndarray, valid: np.ndarray, vx: float, vy: float, va: float, a0: float,
               inc: float, cap_max: float, frame_min: float, building_min: float, object_max: float, thickness: float,
               min_width: float,
               max_width: float, wide_width: float, angle: float, offset: float, offset_short: float, min_free_rays: int,
               occlusion: float, depth: float, backed_share: float, cap_noise: float, floating: int, convex: int,
               concave: int,
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                          np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(wi, we, capped, long, partial (C,): the candidates, pts, out_dir, far (C, 2): their ends, outward
    directions and far ends, is_convex (C,), lengths (W,), doors (D, 4), possible (P, 4),
    possible_convex (P,): one of its ends convex). `thickness`: a whole cap thinner than this
    (`object_min_depth`: no object is so thin) is a wall's end, framing a door seen in part."""
    wi, we, capped, long, stub, cap_sized, cap_seen, partial, lengths = jamb_candidates(
        walls, connected, prop, objects, cap_max, frame_min, floating, convex, building_min, rx, ry, object_max)
    c = wi.shape[0]
    pts, far, out_dir = np.empty((c, 2)), np.empty((c, 2)), np.empty((c, 2))
    is_convex, block, building = np.empty(c, dtype=np.bool_), np.empty(c, dtype=np.bool_), np.empty(c, dtype=np.bool_)
    for r in range(c):
        i, e = wi[r], we[r]
        pts[r, 0], pts[r, 1] = walls[i, 2 * e], walls[i, 2 * e + 1]
        far[r, 0], far[r, 1] = walls[i, 2 * (1 - e)], walls[i, 2 * (1 - e) + 1]
        dx, dy = pts[r, 0] - far[r, 0], pts[r, 1] - far[r, 1]
        norm = max(np.hypot(dx, dy), 1e-12)
        out_dir[r, 0], out_dir[r, 1] = dx / norm, dy / norm
        is_convex[r] = prop[i, e] == convex
        # a block's face: seen whole, both ends convex, longer than a cap, shorter than a building's
        block[r] = prop[i, 0] == convex and prop[i, 1] == convex and lengths[i] > cap_max and lengths[i] < building_min
        # ...or, however long, a block's front against a wall seen at this end: it turns here, a
        # convex corner, into a side longer than a cap and no longer than an object that meets a
        # wall (a table 1.9 m long by a wall, its corner 0.95 m from a room wall's end: no jamb)
        block[r] = block[r] or turns_into_a_side(connected, prop, lengths, i, e, cap_max, object_max, convex, concave)
        # a building's wall (as for a T-opening): long, or a door frame's length ending in a whole
        # cap (a thick wall's end) or whose far end turns into another wall in a concave corner
        # ...or a stub between a whole cap and a building wall it T-joins in a concave corner (a
        # wall's short end between a doorway and a junction of walls)
        k = connected[i, 1 - e]
        junction = stub[r] and capped[r] and prop[i, 1 - e] == concave and k >= 0 and lengths[k] >= building_min
        building[r] = (lengths[i] >= building_min or (long[r] and (capped[r] or prop[i, 1 - e] == concave))
                       or junction) and not objects[i]
    # a wall's end: joined to nothing, or to a whole cap (a thick wall's end); a building wall
    # turning at a convex corner is a jamb too, but 1.3-1.5 m from a short wall in its line it
    # is as often a room's corner beside a corridor's wall (door_pairs' wide doorways)
    # ...and a wall shorter than a door frame's seen in part (`part`): its far end floating (the
    # view stopped there, behind a nearer doorway's jamb), its end a wall's end, no object's
    wall_end, part = np.empty(c, dtype=np.bool_), np.empty(c, dtype=np.bool_)
    for r in range(c):
        i, e = wi[r], we[r]
        wall_end[r] = connected[i, e] < 0 or capped[r]
        part[r] = wall_end[r] and not long[r] and not stub[r] and not objects[i] and prop[i, 1 - e] == floating
    # a lone block face: shorter than a door frame's wall, joined to nothing, its line running on
    # in no other wall past its far end (a box's or a person's face; a piece of wall between two
    # doors runs on in the building's walls)
    lone = np.zeros(c, dtype=np.bool_)
    cos_a = math.cos(angle)
    for r in range(c):
        i, e = wi[r], we[r]
        if block[r] and not long[r] and connected[i, 0] < 0 and connected[i, 1] < 0:
            lone[r] = True
            for k in range(walls.shape[0]):
                if _in_line_beyond(walls, objects, i, 1 - e, k, cos_a, offset_short, max_width, True):
                    lone[r] = False
                    break
    # a wall seen in part whose end carries a whole cap thinner than any object: a thick wall's end
    thin_capped = np.zeros(c, dtype=np.bool_)
    for r in range(c):
        k = connected[wi[r], we[r]]
        thin_capped[r] = capped[r] and k >= 0 and lengths[k] < thickness
    ia, ja, off_ij, off_ji, is_door, is_possible = door_pairs(
        pts, out_dir, wi, we, is_convex, long, stub, cap_sized, cap_seen, connected, block, building, wall_end, lone, part,
        thin_capped, lengths[wi], min_width, max_width, wide_width, angle, offset, offset_short, cap_noise)
    # an end joined to a cap seen in part is a jamb only between two building walls in one line
    cos_a = math.cos(angle)
    for r in range(ia.shape[0]):
        i, j = ia[r], ja[r]
        if (partial[i] or partial[j]) and not (
                building[i] and building[j] and abs(out_dir[i, 0] * out_dir[j, 0] + out_dir[i, 1] * out_dir[j, 1]) > cos_a
                and off_ij[r] < offset and off_ji[r] < offset):
            is_door[r] = False
    g = ia.shape[0]
    segs = np.empty((g, 4))
    own_a, own_b = np.empty(g, dtype=np.int64), np.empty(g, dtype=np.int64)
    for r in range(g):
        segs[r, 0], segs[r, 1], segs[r, 2], segs[r, 3] = pts[ia[r], 0], pts[ia[r], 1], pts[ja[r], 0], pts[ja[r], 1]
        own_a[r], own_b[r] = wi[ia[r]], wi[ja[r]]
    blocked = blocked_many(segs, walls, own_a, own_b)
    some = np.flatnonzero(~blocked)
    backed_some, free_some, _, _ = backed(segs[some], walls, own_a[some], own_b[some], rx, ry, has_view, ranges, valid,
                                          vx, vy, va, a0, inc, np.zeros(some.shape[0], dtype=np.bool_),
                                          np.zeros(walls.shape[0], dtype=np.bool_), occlusion, depth, cap_max,
                                          backed_share)
    unseen = np.ones(g, dtype=np.bool_)
    for q in range(some.shape[0]):
        blocked[some[q]] = backed_some[q]
        unseen[some[q]] = free_some[q] < min_free_rays
    # best aligned first; a later door from the same point in about the same direction is the
    # same opening seen from another corner of the jamb (e.g. both corners of an end cap)
    cand = np.flatnonzero(is_door & ~blocked & ~unseen)
    cand = cand[one_door_per_jamb(pts, out_dir, wi, we, connected, lengths, segs, ia, ja, cand, cap_max,
                                  math.cos(angle), offset_short)]
    score = np.empty(cand.shape[0])
    for q in range(cand.shape[0]):
        score[q] = min(off_ij[cand[q]], off_ji[cand[q]])
    order = cand[np.argsort(score, kind="mergesort")]
    doors = segs[distinct_openings(segs, order, np.ones(g, dtype=np.bool_), SAME_OPENING_ANGLE, SAME_POINT)]
    maybe = np.flatnonzero(is_possible & ~blocked)
    possible_convex = np.empty(maybe.shape[0], dtype=np.bool_)
    for q in range(maybe.shape[0]):
        possible_convex[q] = is_convex[ia[maybe[q]]] or is_convex[ja[maybe[q]]]
    return wi, we, capped, long, partial, pts, out_dir, far, is_convex, lengths, doors, segs[maybe], possible_convex


@njit
def one_door_per_jamb(pts: np.ndarray, out_dir: np.ndarray, wi: np.ndarray, we: np.ndarray, connected: np.ndarray,
                      lengths: np.ndarray, segs: np.ndarray, ia: np.ndarray, ja: np.ndarray, cand: np.ndarray,
                      cap_max: float, cos_a: float, offset_short: float) -> np.ndarray:
    """(K,) rows of `cand` kept: none leaving a jamb another of them continues in its wall's
    line (identify_kernels.leaves_a_claimed_jamb)."""
    jid, claimed, claim = claimed_jambs(pts, out_dir, wi, we, connected, lengths, segs[cand], cap_max, cos_a,
                                        SAME_POINT)
    keep = np.empty(cand.shape[0], dtype=np.int64)
    n = 0
    for q in range(cand.shape[0]):
        if not leaves_a_claimed_jamb(pts, out_dir, ia[cand[q]], ja[cand[q]], jid, claimed, claim, cos_a, offset_short):
            keep[n] = q
            n += 1
    return keep[:n].copy()


def _example_loose() -> tuple:
    walls = np.array([[0.0, 0.0, 2.0, 0.0], [3.0, -1.0, 3.0, 1.0]])
    return (np.array([[2.0, 0.0]]), np.array([[1.0, 0.0]]), np.array([0], dtype=np.int64),
            np.array([1], dtype=np.int64), walls, np.full((2, 2), -1, dtype=np.int64), np.zeros(2, dtype=np.bool_),
            0.6, 1.5)


@kernel(_example_loose)
def loose_gaps(pts: np.ndarray, out_dir: np.ndarray, wi: np.ndarray, we: np.ndarray, walls: np.ndarray,
               connected: np.ndarray, objects: np.ndarray, min_width: float, facing: float) -> np.ndarray:
    """The possible doors (L, 4) from loose ends `pts` (outward `out_dir`, wall `wi`, end `we`)
    to the wall each faces."""
    n = pts.shape[0]
    t, k = ray_hits(pts, out_dir, walls, np.full(n, -1, dtype=np.int64), np.full(n, -1, dtype=np.int64))
    out = np.empty((n, 4))
    g = 0
    for r in range(n):
        if k[r] < 0 or k[r] == wi[r] or not (min_width <= t[r] and t[r] <= facing):
            continue
        if connected[wi[r], we[r]] == k[r] or objects[k[r]]:
            continue
        out[g, 0], out[g, 1] = pts[r, 0], pts[r, 1]
        out[g, 2], out[g, 3] = pts[r, 0] + t[r] * out_dir[r, 0], pts[r, 1] + t[r] * out_dir[r, 1]
        g += 1
    return out[:g].copy()


def _example_away() -> tuple:
    return np.array([[0.0, 0.0, 1.0, 0.0], [5.0, 0.0, 6.0, 0.0]]), np.array([[0.0, 0.1, 1.0, 0.1]]), 0.3


@kernel(_example_away)
def away_from(possible: np.ndarray, doors: np.ndarray, dist: float) -> np.ndarray:
    """(P,) bool: the possible door's middle lies farther than `dist` from every door's middle."""
    keep = np.ones(possible.shape[0], dtype=np.bool_)
    for p in range(possible.shape[0]):
        mpx, mpy = (possible[p, 0] + possible[p, 2]) / 2, (possible[p, 1] + possible[p, 3]) / 2
        near = math.inf
        for d in range(doors.shape[0]):
            mdx, mdy = (doors[d, 0] + doors[d, 2]) / 2, (doors[d, 1] + doors[d, 3]) / 2
            near = min(near, np.hypot(mpx - mdx, mpy - mdy))
        keep[p] = near > dist
    return keep
