"""Merge (seed 001): fold the current map into the local map, kept in the zero frame.

Keeping the local map in the zero frame is the same as "transforming the previous local map
to the current pose" (seed 001) done once: the current map is brought to the zero frame
with the pose instead, and every comparison is made there. One step:

1. **Associate** each new wall with the most similar local wall: directions within `angle`,
   the new end points within `distance` of the local wall's line, the extents along the line
   overlapping or leaving a gap below `gap` (seed 001's cases: parallel, small angle, split
   into pieces, a short one next to a long one).
2. **Fuse**: the line is the weighted mean of old and new (the old one weighs its number of
   sightings, at most `max_weight`, the new one 1). An end the new scan saw for real (the
   laser looked past it, or it is a corner of the scan) pulls the old end with the same
   weights; a floating new end only extends the wall.
3. New walls nobody matched are added, tentative.
4. **Merge** local walls that became similar to each other (a wall seen in two pieces).
5. **Connect** end points of two walls at least `connect_min_angle` apart whose ends lie
   within `connect_radius` of the lines' crossing: the corner is the crossing, pulled
   towards the previous corner by the end's weight (its number of consecutive connected
   scans, at most `max_weight`), so one noisy scan cannot move a well-seen corner far. An end
   near the inside of another wall (a T, e.g. a cabinet against a wall) connects too.
6. **Drop**: walls shorter than `min_length`; walls the laser passed through `miss_limit` scans in a row (a door opened, an
   object moved); tentative walls not seen again within `tentative_life` scans; walls not
   seen for `forget_scans` scans (when set); walls beyond `keep_radius`; beyond `max_walls`, the least seen. What is shown are walls seen at least
   `confirm_hits` times and connected to another wall — or seen `unconnected_hits` times —
   so the map holds connected walls and does not flicker when one scan misses a wall.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pico_studio.config.perception_params import MergeParams
from pico_studio.core.geometry import transform_segments
from pico_studio.core.perception.merge_kernels import (
    connect_candidates,
    connect_walk,
    fuse,
    near_pairs,
    see_through,
)
from pico_studio.core.perception.scan import ScanPoints
from pico_studio.core.perception.segment import END_FLOATING, END_SEEN, Segments

Pose = tuple[float, float, float]


@dataclass(frozen=True)
class LocalMapState:
    walls: np.ndarray  # (W, 4) zero frame
    hits: np.ndarray  # (W,) scans the wall was seen in
    last_seen: np.ndarray  # (W,) step of the last sighting
    missed: np.ndarray  # (W,) consecutive scans the laser passed through it
    seen_end: np.ndarray  # (W, 2) bool: the wall's true end was seen there
    end_weight: np.ndarray  # (W, 2) consecutive scans the end was connected
    connected: np.ndarray  # (W, 2) int: the wall connected at that end, -1 none
    step: int = 0

    @staticmethod
    def empty() -> LocalMapState:
        return LocalMapState(
            np.zeros((0, 4)), np.zeros(0), np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64),
            np.zeros((0, 2), dtype=bool), np.zeros((0, 2)), np.zeros((0, 2), dtype=np.int64), 0,
        )

    def shown(self, params: MergeParams) -> np.ndarray:
        """(W,) bool: walls confirmed enough to be in the local map's output."""
        linked = (self.connected >= 0).any(axis=1)
        return (self.hits >= params.confirm_hits) & (linked | (self.hits >= params.unconnected_hits))


class _Work:
    """Mutable copies of the state's arrays for one step."""

    def __init__(self, s: LocalMapState):
        self.walls = s.walls.copy()
        self.hits = s.hits.copy()
        self.last_seen = s.last_seen.copy()
        self.missed = s.missed.copy()
        self.seen_end = s.seen_end.copy()
        self.end_weight = s.end_weight.copy()
        self.step = s.step + 1

    def keep(self, mask: np.ndarray) -> None:
        for name in ("walls", "hits", "last_seen", "missed", "seen_end", "end_weight"):
            setattr(self, name, getattr(self, name)[mask])

    def add(self, seg: np.ndarray, seen: np.ndarray) -> None:
        k = len(seg)
        self.walls = np.vstack([self.walls, seg])
        self.hits = np.concatenate([self.hits, np.ones(k)])
        self.last_seen = np.concatenate([self.last_seen, np.full(k, self.step)])
        self.missed = np.concatenate([self.missed, np.zeros(k, dtype=np.int64)])
        self.seen_end = np.vstack([self.seen_end, seen])
        self.end_weight = np.vstack([self.end_weight, np.zeros((k, 2))])


def merge(
    state: LocalMapState, segs: Segments, pose: Pose, scan: ScanPoints, params: MergeParams
) -> LocalMapState:
    w = _Work(state)
    new = transform_segments(segs.segments, pose)
    new_real = segs.end_kind != END_FLOATING  # a corner of the scan or a seen free end
    new_seen = segs.end_kind == END_SEEN
    if len(new):
        target = _associate(w.walls, new, params) if len(w.walls) else np.full(len(new), -1)
        todo = np.flatnonzero(target >= 0)
        while len(todo):  # a wall seen in two pieces fuses them one after the other
            _, first = np.unique(target[todo], return_index=True)
            now = todo[first]
            _fuse(w, target[now], new[now], new_real[now], new_seen[now], params)
            rest = np.ones(len(todo), dtype=bool)
            rest[first] = False
            todo = todo[rest]
        fresh = target < 0
        w.add(new[fresh], new_seen[fresh])
    _merge_local(w, params)
    _see_through(w, pose, scan, params)
    connected = _connect(w, params)
    linked = (connected >= 0).any(axis=1)
    age = w.step - w.last_seen
    tentative = w.hits < params.unconnected_hits
    keep = (w.missed < params.miss_limit) & ~(tentative & ~linked & (age > params.tentative_life))
    keep &= ~(tentative & linked & (age > 4 * params.tentative_life))
    keep &= _within(w.walls, pose, params.keep_radius)
    if params.forget_scans > 0:
        keep &= age <= params.forget_scans
    keep &= np.hypot(w.walls[:, 2] - w.walls[:, 0], w.walls[:, 3] - w.walls[:, 1]) >= params.min_length
    if keep.sum() > params.max_walls:
        order = np.argsort(-(w.hits + 0.5 * linked))
        cap = np.zeros(len(keep), dtype=bool)
        cap[order[: params.max_walls]] = True
        keep &= cap
    if not keep.all():
        remap = np.cumsum(keep) - 1
        connected = np.where(connected >= 0, np.where(keep[np.maximum(connected, 0)], remap[np.maximum(connected, 0)], -1), -1)
        connected = connected[keep]
        w.keep(keep)
    return LocalMapState(w.walls, w.hits, w.last_seen, w.missed, w.seen_end, w.end_weight, connected, w.step)


# ----- 1. association ------------------------------------------------------------------------


def _dir(seg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    d = seg[..., 2:4] - seg[..., 0:2]
    length = np.hypot(d[..., 0], d[..., 1])
    return d / np.maximum(length, 1e-12)[..., None], length


def _similar(a: np.ndarray, b: np.ndarray, params: MergeParams) -> tuple[np.ndarray, np.ndarray]:
    """(A, B) bool similar and (A, B) cost (mean perpendicular distance) of walls a vs walls b."""
    da, la = _dir(a)
    db, _ = _dir(b)
    cos = np.abs(da @ db.T)
    ang_ok = cos > math.cos(params.angle)
    # b's end points in a's frame (t along a from a's first end, n across)
    rel0 = b[None, :, 0:2] - a[:, None, 0:2]
    rel1 = b[None, :, 2:4] - a[:, None, 0:2]
    t0 = (rel0 * da[:, None, :]).sum(-1)
    t1 = (rel1 * da[:, None, :]).sum(-1)
    n0 = np.abs(rel0[..., 0] * da[:, None, 1] - rel0[..., 1] * da[:, None, 0])
    n1 = np.abs(rel1[..., 0] * da[:, None, 1] - rel1[..., 1] * da[:, None, 0])
    near = np.maximum(n0, n1) < params.distance
    lo, hi = np.minimum(t0, t1), np.maximum(t0, t1)
    gap = np.maximum(lo - la[:, None], -hi)
    ok = ang_ok & near & (gap < params.gap)
    return ok, (n0 + n1) / 2


def _associate(walls: np.ndarray, new: np.ndarray, params: MergeParams) -> np.ndarray:
    ok, cost = _similar(walls, new, params)
    cost = np.where(ok, cost, np.inf)
    best = np.argmin(cost, axis=0)
    return np.where(np.isfinite(cost[best, np.arange(len(new))]), best, -1)


# ----- 2. fusion -----------------------------------------------------------------------------


def _fuse(w: _Work, i: np.ndarray, seg: np.ndarray, real: np.ndarray, seen: np.ndarray, params: MergeParams) -> None:
    """Fuse new walls seg (ka, 4) into local walls i (ka,) (distinct), all at once; the
    weighted line and the ends' rules with their maths: merge_kernels.fuse."""
    for name in ("walls", "hits", "last_seen", "missed", "seen_end"):  # fused in place
        setattr(w, name, np.ascontiguousarray(getattr(w, name)))
    fuse(w.walls, w.hits, w.last_seen, w.missed, w.seen_end, np.ascontiguousarray(i, dtype=np.int64),
         np.ascontiguousarray(seg, dtype=float), np.ascontiguousarray(real, dtype=bool),
         np.ascontiguousarray(seen, dtype=bool), int(w.step), float(params.max_weight), float(params.gap))


# ----- 4. merging local walls ----------------------------------------------------------------


def _merge_local(w: _Work, params: MergeParams) -> None:
    for _ in range(8):
        n = len(w.walls)
        if n < 2:
            return
        ia, ka = _near_pairs(w.walls, max(params.gap, params.distance))
        half = ia < ka
        ia, ka = ia[half], ka[half]
        ok = _similar_both(w.walls[ia], w.walls[ka], params)
        if not ok.any():
            return
        gone = np.zeros(n, dtype=bool)
        for i, k in zip(ia[ok].tolist(), ka[ok].tolist(), strict=True):
            if gone[i] or gone[k]:
                continue
            keep, drop = (i, k) if w.hits[i] >= w.hits[k] else (k, i)
            _absorb(w, keep, drop, params)
            gone[drop] = True
        w.keep(~gone)


def _similar_both(a: np.ndarray, b: np.ndarray, params: MergeParams) -> np.ndarray:
    """(P,) bool: walls a[p] and b[p] are similar both ways (the test of `_similar`, row by
    row, in each direction; directions and lengths computed once)."""
    da, la = _dir(a)
    db, lb = _dir(b)
    ang_ok = np.abs((da * db).sum(1)) > math.cos(params.angle)
    if not ang_ok.any():
        return ang_ok
    return ang_ok & _rows_near(a, da, la, b, params) & _rows_near(b, db, lb, a, params)


def _rows_near(a: np.ndarray, da: np.ndarray, la: np.ndarray, b: np.ndarray, params: MergeParams) -> np.ndarray:
    """(P,) bool: b[p]'s ends lie near a[p]'s line, overlapping it or within `gap` of it."""
    rel0 = b[:, 0:2] - a[:, 0:2]
    rel1 = b[:, 2:4] - a[:, 0:2]
    t0 = (rel0 * da).sum(1)
    t1 = (rel1 * da).sum(1)
    n0 = np.abs(rel0[:, 0] * da[:, 1] - rel0[:, 1] * da[:, 0])
    n1 = np.abs(rel1[:, 0] * da[:, 1] - rel1[:, 1] * da[:, 0])
    gap = np.maximum(np.minimum(t0, t1) - la, -np.maximum(t0, t1))
    return (np.maximum(n0, n1) < params.distance) & (gap < params.gap)


def _absorb(w: _Work, i: int, k: int, params: MergeParams) -> None:
    """Wall i takes wall k in: weighted line, union of extents (outermost ends win)."""
    a, b = w.walls[i], w.walls[k].copy()
    da, _ = _dir(a)
    db, _ = _dir(b)
    seen_k = w.seen_end[k].copy()
    if da @ db < 0:
        b = np.concatenate([b[2:4], b[0:2]])
        db = -db
        seen_k = seen_k[::-1]
    wa, wb = min(w.hits[i], params.max_weight), min(w.hits[k], params.max_weight)
    ang = math.atan2(da[1], da[0]) + math.atan2(da[0] * db[1] - da[1] * db[0], da @ db) * wb / (wa + wb)
    d = np.array([math.cos(ang), math.sin(ang)])
    nrm = np.array([-d[1], d[0]])
    rho = (wa * (nrm @ (a[0:2] + a[2:4]) / 2) + wb * (nrm @ (b[0:2] + b[2:4]) / 2)) / (wa + wb)
    origin = rho * nrm
    ta = [(a[0:2] - origin) @ d, (a[2:4] - origin) @ d]
    tb = [(b[0:2] - origin) @ d, (b[2:4] - origin) @ d]
    lo = (ta[0], w.seen_end[i, 0]) if ta[0] <= tb[0] else (tb[0], seen_k[0])
    hi = (ta[1], w.seen_end[i, 1]) if ta[1] >= tb[1] else (tb[1], seen_k[1])
    w.walls[i] = np.concatenate([origin + lo[0] * d, origin + hi[0] * d])
    w.seen_end[i] = (lo[1], hi[1])
    w.hits[i] = w.hits[i] + w.hits[k]
    w.last_seen[i] = max(w.last_seen[i], w.last_seen[k])
    w.missed[i] = min(w.missed[i], w.missed[k])


# ----- 5. connecting ends into corners ---------------------------------------------------------


def _near_pairs(walls: np.ndarray, r: float) -> tuple[np.ndarray, ...]:
    """Ordered pairs (i, k), i != k, whose bounding boxes grown by r overlap: the only pairs
    that can connect or merge, found without an all-pairs geometry pass (merge_kernels)."""
    return near_pairs(np.ascontiguousarray(walls, dtype=float), float(r))


def _connect(w: _Work, params: MergeParams) -> np.ndarray:
    """Connect wall ends into corners and T's; the maths: merge_kernels (connect_candidates
    finds the pairs, connect_walk takes them one after the other)."""
    n = len(w.walls)
    connected = np.full((n, 2), -1, dtype=np.int64)
    old_weight = w.end_weight.copy()
    w.end_weight = np.zeros_like(w.end_weight)
    if n < 2:
        return connected
    r = params.connect_radius
    ia, ka = _near_pairs(w.walls, r)
    if len(ia) == 0:
        return connected
    walls = np.array(w.walls, dtype=float)  # moved in place by the walk
    d, ei, ek, s, dist_i, cost, end_end, t_join = connect_candidates(
        walls, ia, ka, np.ascontiguousarray(w.hits, dtype=float), float(r),
        math.sin(params.connect_min_angle), float(params.confirm_hits))
    # tentative walls connect last (their cost carries r): a sliver seen once must not steal
    # a corner from walls seen many times
    pairs = np.flatnonzero(end_end & (ia < ka))
    tees = np.flatnonzero(t_join)
    pairs = pairs[np.argsort(cost[pairs])]
    tees = tees[np.argsort(dist_i[tees])]
    if not len(pairs) and not len(tees):
        return connected
    # a handful of corners per scan, one after the other (each may take an end another wanted)
    seen = np.array(w.seen_end, dtype=bool)
    conn, ew = connect_walk(walls, d, np.ascontiguousarray(old_weight, dtype=float), seen, ia, ka, ei, ek, s,
                            pairs.astype(np.int64), tees.astype(np.int64), float(params.max_weight))
    w.walls = walls
    w.end_weight = ew
    w.seen_end = seen
    return conn


# ----- 6. dropping -----------------------------------------------------------------------------


def _see_through(w: _Work, pose: Pose, scan: ScanPoints, params: MergeParams) -> None:
    """Count, for walls not seen this scan, whether the laser passed through them."""
    n = len(w.walls)
    if n == 0 or len(scan.ranges) < 2:
        return
    unseen = w.last_seen != w.step
    if not unseen.any():
        return
    a0 = float(scan.angles[0])
    inc = (float(scan.angles[-1]) - a0) / (len(scan.angles) - 1)
    if inc == 0 or not math.isfinite(inc):
        return
    # the points, beams and counts with their maths: merge_kernels.see_through
    w.missed = np.ascontiguousarray(w.missed, dtype=np.int64)
    see_through(np.ascontiguousarray(w.walls, dtype=float), np.ascontiguousarray(unseen), w.missed,
                float(pose[0]), float(pose[1]), float(pose[2]), np.ascontiguousarray(scan.ranges, dtype=float),
                np.ascontiguousarray(scan.valid, dtype=bool), a0, inc, float(params.see_through))


def drop_near(state: LocalMapState, places: np.ndarray, radius: float) -> LocalMapState:
    """The state without walls lying entirely within `radius` of one of `places` (V, 2): what
    an object left where it stood before it turned out to move."""
    if len(places) == 0 or len(state.walls) == 0:
        return state
    ends = state.walls.reshape(-1, 2, 2)
    d = np.hypot(*(ends[:, :, None, :] - places[None, None, :, :]).transpose(3, 0, 1, 2))  # (W, 2, V)
    gone = (d <= radius).all(axis=1).any(axis=1)
    if not gone.any():
        return state
    keep = ~gone
    remap = np.cumsum(keep) - 1
    c = state.connected
    connected = np.where(c >= 0, np.where(keep[np.maximum(c, 0)], remap[np.maximum(c, 0)], -1), -1)[keep]
    return LocalMapState(state.walls[keep], state.hits[keep], state.last_seen[keep], state.missed[keep],
                         state.seen_end[keep], state.end_weight[keep], connected, state.step)


def _within(walls: np.ndarray, pose: Pose, radius: float) -> np.ndarray:
    if len(walls) == 0:
        return np.zeros(0, dtype=bool)
    p = np.array(pose[:2])
    a, b = walls[:, 0:2], walls[:, 2:4]
    ab = b - a
    t = np.clip(((p - a) * ab).sum(1) / np.maximum((ab**2).sum(1), 1e-12), 0, 1)
    return np.hypot(*(a + t[:, None] * ab - p).T) <= radius


__all__ = ["END_SEEN", "LocalMapState", "drop_near", "merge"]
