"""Objects and people as their own things: small free-standing clusters, tracked over scans.

A cluster of the scan is an *object candidate* when it is small (its points span at most
`max_size`), has at least `min_points` points and the laser saw past both its ends (it
stands free: a person, a box, a chair — not a piece of a wall, which runs on out of view or
into a corner). With `partly_hidden`, a cluster seen past at one end only is a candidate too
(a box coming out from behind a table, walking along its own face: restaurant_2024's box),
followed by that end — its centroid moves as more of it comes into view, the end it was seen
past only when it does. Candidates are tracked in the zero frame: a track followed by its
centroid meets the nearest candidate centroid within `match_radius` of its last one, a track
followed by an end the nearest seen end; when a partly hidden track is seen whole, its start
shifts by the same offset (end to centroid), so its motion runs on; seen partly hidden again
it starts afresh. A track whose reference moved more than `min_motion` from its start is
*dynamic* for good: its walls are kept out of the local map (and the local walls it left
where it began are dropped, but those seen in more scans than the track is old and not seen
through now: they stood there before it came — a wall's end cap tracked while its seen end slid along
as the view changed leaves its wall), and its points are kept out of the pose correction. A
dynamic track seen partly hidden that then stays put (its reference within `min_motion`) for
`settle_scans` scans is a static object again, measured afresh from there, and merged: a wall
piece seen past its end whose end cap's far corner came into view (its seen end jumped 0.15-0.3 m
in one scan) is a wall again, and a doorway beside it gets its jamb back; a thing seen whole
stays dynamic (a person who paused, merged, would smear the map when walking on). A new
candidate whose box overlaps a settled track's (within `min_motion`) that no candidate met is
that thing seen by another of its ends (a box paused by the robot, seen from its other side):
the same track, so when it walks on what it left since it settled goes too. A whole
track seen in fewer than `confirm_scans` scans is not merged yet either (a person walking by
is gone before that); after that, a track that stayed put is a *static object* and merged
like any wall. A partly hidden one is merged at once unless it moves (a thick wall's end cap
with its face running on out of view looks the same). Tracks not seen for `forget_scans`
scans are forgotten.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pico_studio.config.perception_params import ObjectParams
from pico_studio.core.perception.scan import ScanPoints
from pico_studio.jit import kernel

Pose = tuple[float, float, float]


@dataclass(frozen=True)
class Track:
    first: tuple[float, float]  # reference point when first seen (or since its kind changed), zero frame
    last: tuple[float, float]  # reference point when last seen
    seen: int  # scans it was seen in
    last_step: int
    dynamic: bool
    box: tuple[float, float, float, float]  # last bounding box (xmin, ymin, xmax, ymax), zero frame
    whole: bool = True  # last seen past at both ends (reference: the centroid), else at one (that end)
    origin: tuple[float, float] | None = None  # the reference when the track began (None: `first`)
    born: int = 0  # the step it began
    still: tuple[float, float] | None = None  # where it stands: the reference since `still_since` within min_motion
    still_since: int = 0
    settled: bool = False  # static again after it moved (settle_scans): the same thing may move on


@dataclass(frozen=True)
class ObjectsState:
    tracks: tuple[Track, ...] = ()
    step: int = 0


@dataclass(frozen=True)
class Objects:
    held: np.ndarray  # (K,) bool per scan cluster: keep its walls out of the merge
    dynamic: np.ndarray  # (K,) bool per scan cluster: a dynamic obstacle
    dynamic_boxes: np.ndarray  # (D, 4) zero frame
    static_boxes: np.ndarray  # (O, 4) zero frame
    vanished_at: np.ndarray  # (V, 2) zero frame: where tracks that just turned dynamic were first seen
    vanished_age: np.ndarray  # (V,) int: scans since each of those tracks began


def _example() -> tuple:
    points = np.array([[1.0, 0.0], [1.0, 0.1], [1.1, 0.1], [3.0, 0.0], [3.0, 2.0]])
    clusters = np.array([[0, 3], [3, 5]], dtype=np.int64)
    return points, clusters, np.ones((2, 2), dtype=np.bool_), 3, 0.6, 0.5, 0.2, 0.3, True


@kernel(_example)
def candidate_boxes(points: np.ndarray, clusters: np.ndarray, end_seen: np.ndarray, min_points: int,
                    max_size: float, px: float, py: float, pa: float, partly_hidden: bool
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The object candidates among the clusters — at least `min_points` points, both ends
    seen past (or one, when `partly_hidden`), the diagonal |hi - lo| of their bounding box at
    most `max_size` — as (cluster indices (C,), centroids (C, 2), bounding boxes (C, 4) (xmin,
    ymin, xmax, ymax), end points (C, 4): the first and the last point), all in the zero
    frame: q = R(pa) p + (px, py)."""
    k = clusters.shape[0]
    idx = np.empty(k, dtype=np.int64)
    centres, boxes, ends = np.empty((k, 2)), np.empty((k, 4)), np.empty((k, 4))
    c, s_ = math.cos(pa), math.sin(pa)
    m = 0
    for j in range(k):
        start, end = clusters[j, 0], clusters[j, 1]
        both = end_seen[j, 0] and end_seen[j, 1]
        if end - start < min_points or not (both or (partly_hidden and (end_seen[j, 0] or end_seen[j, 1]))):
            continue
        lx, ly, hx, hy = np.inf, np.inf, -np.inf, -np.inf
        for i in range(start, end):
            lx, ly = min(lx, points[i, 0]), min(ly, points[i, 1])
            hx, hy = max(hx, points[i, 0]), max(hy, points[i, 1])
        if not np.hypot(hx - lx, hy - ly) <= max_size:
            continue
        sx = sy = 0.0
        bx0, by0, bx1, by1 = np.inf, np.inf, -np.inf, -np.inf
        for i in range(start, end):
            x = points[i, 0] * c + points[i, 1] * -s_ + px
            y = points[i, 0] * s_ + points[i, 1] * c + py
            sx, sy = sx + x, sy + y
            bx0, by0, bx1, by1 = min(bx0, x), min(by0, y), max(bx1, x), max(by1, y)
            if i == start:
                ends[m, 0], ends[m, 1] = x, y
            if i == end - 1:
                ends[m, 2], ends[m, 3] = x, y
        idx[m] = j
        centres[m, 0], centres[m, 1] = sx / (end - start), sy / (end - start)
        boxes[m, 0], boxes[m, 1], boxes[m, 2], boxes[m, 3] = bx0, by0, bx1, by1
        m += 1
    return idx[:m].copy(), centres[:m].copy(), boxes[:m].copy(), ends[:m].copy()


def candidates(scan: ScanPoints, params: ObjectParams) -> np.ndarray:
    """(K,) bool: clusters that are small, free-standing object candidates."""
    out = np.zeros(len(scan.clusters), dtype=bool)
    out[_candidates(scan, (0.0, 0.0, 0.0), params)[0]] = True
    return out


def _candidates(scan: ScanPoints, pose: Pose, params: ObjectParams
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:  # (idx, centroids, boxes, ends)
    return candidate_boxes(np.ascontiguousarray(scan.points, dtype=float), np.ascontiguousarray(scan.clusters, dtype=np.int64),
                           np.ascontiguousarray(scan.end_seen, dtype=bool), int(params.min_points),
                           float(params.max_size), float(pose[0]), float(pose[1]), float(pose[2]),
                           bool(params.partly_hidden))


def track_objects(state: ObjectsState, scan: ScanPoints, pose: Pose, params: ObjectParams
                  ) -> tuple[Objects, ObjectsState]:
    step = state.step + 1
    k = len(scan.clusters)
    held = np.zeros(k, dtype=bool)
    dynamic = np.zeros(k, dtype=bool)
    tracks = [t for t in state.tracks if step - t.last_step <= params.forget_scans]
    idx, centres, boxes, ends = (_candidates(scan, pose, params) if params.enabled and k
                                 else (_NONE, _NO_POINTS, _NO_BOXES, _NO_BOXES))
    end_seen = scan.end_seen[idx]
    used = [False] * len(tracks)
    vanished: list[tuple[float, float]] = []
    ages: list[int] = []
    for c, centre, box, two, seen in zip(idx.tolist(), map(tuple, centres.tolist()), map(tuple, boxes.tolist()),
                                         ends.tolist(), end_seen.tolist(), strict=True):
        whole = seen[0] and seen[1]
        seen_ends = [(two[2 * e], two[2 * e + 1]) for e in (0, 1) if seen[e]]
        best, best_d, best_ref = -1, params.match_radius, centre
        for i, t in enumerate(tracks):
            # a track followed by an end meets the candidate's nearest seen end, else its centroid
            for q in (seen_ends if not t.whole else [centre]):
                d = math.hypot(t.last[0] - q[0], t.last[1] - q[1])
                if not used[i] and d < best_d:
                    best, best_d, best_ref = i, d, q
        ref = centre if whole else seen_ends[0]
        same = _settled_at(tracks, used, box, params.min_motion) if best < 0 else -1
        if same >= 0:
            # a thing that settled, seen now by another of its ends (a box paused by the robot,
            # seen from its other side): the same track, measured afresh from this end, so
            # when it moves on what it left since it settled goes with it
            old = tracks[same]
            t = Track(ref, ref, old.seen + 1, step, False, box, whole, old.origin, old.born, ref, step, True)
            tracks[same] = t
            used[same] = True
        elif best < 0:
            t = Track(ref, ref, 1, step, False, box, whole, ref, step)
            tracks.append(t)
            used.append(True)
        else:
            old = tracks[best]
            # (a whole track's centroid against a partly hidden one's says nothing: no motion)
            moved = (not (old.whole and not whole)
                     and math.hypot(old.first[0] - best_ref[0], old.first[1] - best_ref[1]) > params.min_motion)
            if moved and not old.dynamic:  # what it left where it began goes
                vanished.append(old.origin or old.first)
                ages.append(step - old.born)
            first = old.first
            if not old.whole and whole:  # followed by its centroid from now: the start shifted alike
                first = (first[0] + centre[0] - best_ref[0], first[1] + centre[1] - best_ref[1])
            elif old.whole and not whole:  # a partly hidden centroid says little: measured afresh
                first = ref
            still, since = old.still, old.still_since
            if still is None or old.whole != whole or \
                    math.hypot(ref[0] - still[0], ref[1] - still[1]) > params.min_motion:
                still, since = ref, step
            t = Track(first, ref, old.seen + 1, step, old.dynamic or moved, box, whole, old.origin, old.born,
                      still, since, old.settled and not moved)
            if t.dynamic and not whole and params.settle_scans > 0 and step - since >= params.settle_scans:
                # stayed put, seen partly hidden: static again, measured afresh from here (a wall
                # piece whose seen end jumped as its end cap came into view; a box stopped half hidden)
                t = Track(ref, ref, max(old.seen + 1, params.confirm_scans), step, False, box, whole, ref, step,
                          ref, step, True)
            tracks[best] = t
            used[best] = True
        dynamic[c] = t.dynamic
        # a partly hidden candidate is merged at once (a wall's end cap with its face running on
        # out of view looks the same) unless it moves; a whole one once it stayed put a while
        held[c] = t.dynamic or (whole and t.seen < params.confirm_scans)
    live = [t for t in tracks if t.last_step == step]
    dyn = np.array([t.box for t in live if t.dynamic], dtype=float).reshape(-1, 4)
    static = np.array([t.box for t in live if not t.dynamic and t.seen >= params.confirm_scans],
                      dtype=float).reshape(-1, 4)
    out = Objects(held, dynamic, dyn, static, np.array(vanished, dtype=float).reshape(-1, 2),
                  np.array(ages, dtype=np.int64))
    return out, ObjectsState(tuple(tracks), step)


def _settled_at(tracks: list[Track], used: list[bool], box: tuple[float, float, float, float],
                margin: float) -> int:
    """The settled track not matched this scan whose box overlaps `box` within `margin`, or -1."""
    for i, t in enumerate(tracks):
        if t.settled and not t.dynamic and not used[i] and t.box[0] - margin <= box[2] and box[0] <= t.box[2] + margin \
                and t.box[1] - margin <= box[3] and box[1] <= t.box[3] + margin:
            return i
    return -1


_NONE, _NO_POINTS, _NO_BOXES = np.zeros(0, dtype=np.int64), np.zeros((0, 2)), np.zeros((0, 4))


__all__ = ["Objects", "ObjectsState", "candidates", "track_objects"]
