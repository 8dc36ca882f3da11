"""The possible doors only the global map can prove (identify.MAP_PROVEN_KINDS): shapes the
local map alone cannot tell from furniture.

- Bays (`bays`): a gap of a door's shape between two convex corners that the jamb rules refuse,
  and a passage's mouth (`_mouths`). In thin walls a side room's mouth between two 1 m wall
  pieces has exactly the shape of the bay between two tables by a wall.
- Lone end caps (`lone_caps`): a partition's end seen only face on, facing a building wall's
  face a door's width on; a person's foot looks the same.

Once localised the combined map promotes them where the map's walls open
(localisation.combined.combine).
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config.perception_params import IdentifyParams
from pico_studio.core.perception.gap_tests import gaps_blocked, nearest_hits
from pico_studio.core.perception.identify_kernels import (
    SAME_OPENING_ANGLE,
    SAME_POINT,
    distinct_openings,
    door_pairs,
    jamb_candidates,
)
from pico_studio.core.world_model import CONVEX, FLOATING


def bays(walls: np.ndarray, prop: np.ndarray, connected: np.ndarray, objects: np.ndarray,
          robot: tuple[float, float], params: IdentifyParams) -> list[list[float]]:
    """Gaps of a door's shape between two convex corners that the jamb rules refuse: a block's
    corner or face (its cap longer than a wall's thickness, the wall shorter than a building's),
    or the gap backed or never seen through. Between two tables by a wall that is a bay; in a
    thin-walled building it is a room's mouth (a side room between two wall pieces, a hallway's
    inner end) — from the local map alone the two look the same, so it is a possible door ("bay")
    for the map to prove. The door's shape: `door_pairs` with every convex end a jamb (any cap,
    no block face), and no wall across the gap."""
    wi, we, _, long, stub, cap_sized, cap_seen, _ = jamb_candidates(
        np.ascontiguousarray(walls, dtype=float), np.ascontiguousarray(connected, dtype=np.int64),
        np.ascontiguousarray(prop, dtype=np.int64), np.ascontiguousarray(objects, dtype=bool),
        float(params.jamb_cap_max), float(params.door_wall_min_length), FLOATING, CONVEX, 0.0, float(robot[0]),
        float(robot[1]), 0.0)
    convex = prop[wi, we] == CONVEX
    wi, we, long, stub = wi[convex], we[convex], long[convex], stub[convex]
    cap_sized, cap_seen = cap_sized[convex], cap_seen[convex]
    if len(wi) < 2:
        return []
    ends = walls.reshape(-1, 2)
    pts = ends[2 * wi + we]
    out_dir = pts - ends[2 * wi + 1 - we]
    out_dir /= np.maximum(np.hypot(out_dir[:, 0], out_dir[:, 1]), 1e-12)[:, None]
    ia, ja, off_ij, off_ji, is_door, _ = door_pairs(
        np.ascontiguousarray(pts), np.ascontiguousarray(out_dir), wi.astype(np.int64), we.astype(np.int64),
        np.ones(len(wi), dtype=bool), np.ascontiguousarray(long), np.ascontiguousarray(stub),
        np.ascontiguousarray(cap_sized), np.ascontiguousarray(cap_seen), np.ascontiguousarray(connected, dtype=np.int64),
        np.zeros(len(wi), dtype=bool), float(params.door_min_width), float(params.door_max_width),
        float(params.door_angle), float(params.door_offset), float(params.door_offset_short))
    ia, ja, off = ia[is_door], ja[is_door], np.minimum(off_ij[is_door], off_ji[is_door])
    mi, mj, moff = _mouths(pts, out_dir, wi, we, long, connected, params)
    ia, ja, off = np.concatenate([ia, mi]), np.concatenate([ja, mj]), np.concatenate([off, moff])
    if len(ia) == 0:
        return []
    segs = np.concatenate([pts[ia], pts[ja]], axis=1)
    clear = ~gaps_blocked(segs, walls, wi[ia], wi[ja])
    # best aligned first, one gap per opening (as the jamb doors)
    kept = distinct_openings(np.ascontiguousarray(segs), np.argsort(off, kind="stable").astype(np.int64),
                             np.ascontiguousarray(clear), SAME_OPENING_ANGLE, SAME_POINT)
    out: list[list[float]] = segs[kept].tolist()
    return out


def lone_caps(walls: np.ndarray, connected: np.ndarray, objects: np.ndarray, lengths: np.ndarray,
               robot: tuple[float, float], params: IdentifyParams) -> list[np.ndarray]:
    """Possible T-openings from a lone end cap: a wall no longer than a wall's thickness
    (`jamb_cap_max`), joined to nothing (a partition's end seen only face on, its sides edge-on
    or hidden), whose normal towards the robot's side meets a building wall's face (at least
    `end_face_min_length`, about square to it) a door's width on, nothing across the gap. A
    person's foot or a chair's leg looks the same: only the map can prove it."""
    caps = np.flatnonzero((connected < 0).all(axis=1) & (lengths <= params.jamb_cap_max) & (lengths > 1e-6)
                          & ~objects)
    if len(caps) == 0:
        return []
    a, b = walls[caps, 0:2], walls[caps, 2:4]
    mid = (a + b) / 2
    d = (b - a) / lengths[caps][:, None]
    n = np.stack([-d[:, 1], d[:, 0]], axis=1)
    n[((np.asarray(robot, dtype=float) - mid) * n).sum(axis=1) < 0] *= -1
    t, k = nearest_hits(mid, n, walls, (caps, np.full(len(caps), -1)))
    gaps, own, other = [], [], []
    for r in np.flatnonzero((k >= 0) & (t >= params.door_min_width) & (t <= params.door_max_width)).tolist():
        kk = int(k[r])
        if objects[kk] or lengths[kk] < params.end_face_min_length:
            continue
        kd = walls[kk, 2:4] - walls[kk, 0:2]
        if abs(float(kd @ n[r])) / max(float(np.hypot(*kd)), 1e-12) > math.sin(params.door_angle):
            continue
        gaps.append(np.concatenate([mid[r], mid[r] + t[r] * n[r]]))
        own.append(caps[r])
        other.append(kk)
    if not gaps:
        return []
    g = np.array(gaps)
    blocked = gaps_blocked(g, walls, np.array(own), np.array(other))
    return [g[m] for m in np.flatnonzero(~blocked).tolist()]


def _mouths(pts: np.ndarray, out_dir: np.ndarray, wi: np.ndarray, we: np.ndarray, long: np.ndarray,
            connected: np.ndarray, params: IdentifyParams) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A passage's mouth: the convex ends P_i, P_j of two door frame's walls (`long`) running
    side by side the same way (o_i . o_j > cos(door_angle)) with the gap across both (|u . o|
    < sin(door_angle), u = (P_j - P_i) / |P_j - P_i|), a door's width apart — a hallway's end,
    as the truth's passage mouths. (i, j, |u . o_i| + |u . o_j|: how square the mouth is.)"""
    cos_a, sin_a = math.cos(params.door_angle), math.sin(params.door_angle)
    both = np.flatnonzero(long)  # only door frame's walls pair
    a, b = np.triu_indices(len(both), k=1)
    i, j = both[a], both[b]
    d = pts[j] - pts[i]
    dist = np.hypot(d[:, 0], d[:, 1])
    u = d / np.maximum(dist, 1e-12)[:, None]
    ui = np.abs((u * out_dir[i]).sum(axis=1))
    uj = np.abs((u * out_dir[j]).sum(axis=1))
    ok = ((dist >= params.door_min_width) & (dist <= params.door_max_width)
          & ((out_dir[i] * out_dir[j]).sum(axis=1) > cos_a) & (ui < sin_a) & (uj < sin_a)
          & (wi[i] != wi[j]) & (connected[wi[i], we[i]] != wi[j]))
    return i[ok], j[ok], (ui + uj)[ok]
