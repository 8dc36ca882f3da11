"""Objects and people as their own things: small free-standing clusters, tracked over scans.

A cluster of the scan is an *object candidate* when it is small (its points span at most
`max_size`), has at least `min_points` points and the laser saw past both its ends (it
stands free: a person, a box, a chair — not a piece of a wall, which runs on out of view or
into a corner). Candidates are tracked in the zero frame, nearest centroid within
`match_radius` of a track's last one. A track whose centroid moved more than `min_motion`
from where it was first seen is *dynamic* for good: its walls are kept out of the local
map (and the local walls it left where it was first seen are dropped), and its points are
kept out of the pose correction. A track seen in fewer than `confirm_scans` scans is not
merged yet either (a person walking by is gone before that); after that, a track that
stayed put is a *static object* and merged like any wall. Tracks not seen for `forget_scans`
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
    first: tuple[float, float]  # centroid when first seen, zero frame
    last: tuple[float, float]  # centroid when last seen
    seen: int  # scans it was seen in
    last_step: int
    dynamic: bool
    box: tuple[float, float, float, float]  # last bounding box (xmin, ymin, xmax, ymax), zero frame


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


def _example() -> tuple:
    points = np.array([[1.0, 0.0], [1.0, 0.1], [1.1, 0.1], [3.0, 0.0], [3.0, 2.0]])
    clusters = np.array([[0, 3], [3, 5]], dtype=np.int64)
    return points, clusters, np.ones((2, 2), dtype=np.bool_), 3, 0.6, 0.5, 0.2, 0.3


@kernel(_example)
def candidate_boxes(points: np.ndarray, clusters: np.ndarray, end_seen: np.ndarray, min_points: int,
                    max_size: float, px: float, py: float, pa: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The object candidates among the clusters — at least `min_points` points, both ends
    seen past, the diagonal |hi - lo| of their bounding box at most `max_size` — as (cluster
    indices (C,), centroids (C, 2), bounding boxes (C, 4) (xmin, ymin, xmax, ymax)), the
    latter two in the zero frame: q = R(pa) p + (px, py)."""
    k = clusters.shape[0]
    idx = np.empty(k, dtype=np.int64)
    centres, boxes = np.empty((k, 2)), np.empty((k, 4))
    c, s_ = math.cos(pa), math.sin(pa)
    m = 0
    for j in range(k):
        start, end = clusters[j, 0], clusters[j, 1]
        if end - start < min_points or not (end_seen[j, 0] and end_seen[j, 1]):
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
        idx[m] = j
        centres[m, 0], centres[m, 1] = sx / (end - start), sy / (end - start)
        boxes[m, 0], boxes[m, 1], boxes[m, 2], boxes[m, 3] = bx0, by0, bx1, by1
        m += 1
    return idx[:m].copy(), centres[:m].copy(), boxes[:m].copy()


def candidates(scan: ScanPoints, params: ObjectParams) -> np.ndarray:
    """(K,) bool: clusters that are small, free-standing object candidates."""
    out = np.zeros(len(scan.clusters), dtype=bool)
    out[_candidates(scan, (0.0, 0.0, 0.0), params)[0]] = True
    return out


def _candidates(scan: ScanPoints, pose: Pose, params: ObjectParams) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return candidate_boxes(np.ascontiguousarray(scan.points, dtype=float), np.ascontiguousarray(scan.clusters, dtype=np.int64),
                           np.ascontiguousarray(scan.end_seen, dtype=bool), int(params.min_points),
                           float(params.max_size), float(pose[0]), float(pose[1]), float(pose[2]))


def track_objects(state: ObjectsState, scan: ScanPoints, pose: Pose, params: ObjectParams
                  ) -> tuple[Objects, ObjectsState]:
    step = state.step + 1
    k = len(scan.clusters)
    held = np.zeros(k, dtype=bool)
    dynamic = np.zeros(k, dtype=bool)
    tracks = [t for t in state.tracks if step - t.last_step <= params.forget_scans]
    idx, centres, boxes = _candidates(scan, pose, params) if params.enabled and k else (_NONE, _NO_POINTS, _NO_BOXES)
    used = [False] * len(tracks)
    vanished: list[tuple[float, float]] = []
    for c, centre, box in zip(idx.tolist(), map(tuple, centres.tolist()), map(tuple, boxes.tolist()), strict=True):
        best, best_d = -1, params.match_radius
        for i, t in enumerate(tracks):
            d = math.hypot(t.last[0] - centre[0], t.last[1] - centre[1])
            if not used[i] and d < best_d:
                best, best_d = i, d
        if best < 0:
            t = Track(centre, centre, 1, step, False, box)
            tracks.append(t)
            used.append(True)
        else:
            old = tracks[best]
            moved = math.hypot(old.first[0] - centre[0], old.first[1] - centre[1]) > params.min_motion
            if moved and not old.dynamic:
                vanished.append(old.first)
            t = Track(old.first, centre, old.seen + 1, step, old.dynamic or moved, box)
            tracks[best] = t
            used[best] = True
        dynamic[c] = t.dynamic
        held[c] = t.dynamic or t.seen < params.confirm_scans
    live = [t for t in tracks if t.last_step == step]
    dyn = np.array([t.box for t in live if t.dynamic], dtype=float).reshape(-1, 4)
    static = np.array([t.box for t in live if not t.dynamic and t.seen >= params.confirm_scans],
                      dtype=float).reshape(-1, 4)
    out = Objects(held, dynamic, dyn, static, np.array(vanished, dtype=float).reshape(-1, 2))
    return out, ObjectsState(tuple(tracks), step)


_NONE, _NO_POINTS, _NO_BOXES = np.zeros(0, dtype=np.int64), np.zeros((0, 2)), np.zeros((0, 4))


__all__ = ["Objects", "ObjectsState", "candidates", "track_objects"]
