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

from dataclasses import dataclass

import numpy as np

from pico_studio.config.perception_params import ObjectParams
from pico_studio.core.geometry import transform_points
from pico_studio.core.perception.scan import ScanPoints

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


def candidates(scan: ScanPoints, params: ObjectParams) -> np.ndarray:
    """(K,) bool: clusters that are small, free-standing object candidates."""
    k = len(scan.clusters)
    if k == 0:
        return np.zeros(0, dtype=bool)
    start, end = scan.clusters[:, 0], scan.clusters[:, 1]
    n = end - start
    lo = np.minimum.reduceat(scan.points, start, axis=0)
    hi = np.maximum.reduceat(scan.points, start, axis=0)
    size = np.hypot(*(hi - lo).T)
    return (n >= params.min_points) & (size <= params.max_size) & scan.end_seen.all(axis=1)


def track_objects(state: ObjectsState, scan: ScanPoints, pose: Pose, params: ObjectParams
                  ) -> tuple[Objects, ObjectsState]:
    step = state.step + 1
    cand = candidates(scan, params) if params.enabled else np.zeros(len(scan.clusters), dtype=bool)
    held = np.zeros(len(cand), dtype=bool)
    dynamic = np.zeros(len(cand), dtype=bool)
    tracks = [t for t in state.tracks if step - t.last_step <= params.forget_scans]
    used = [False] * len(tracks)
    vanished: list[tuple[float, float]] = []
    for c in np.flatnonzero(cand).tolist():
        s, e = scan.clusters[c]
        pts = transform_points(scan.points[s:e], pose)
        centre = (float(pts[:, 0].mean()), float(pts[:, 1].mean()))
        box = (float(pts[:, 0].min()), float(pts[:, 1].min()), float(pts[:, 0].max()), float(pts[:, 1].max()))
        best, best_d = -1, params.match_radius
        for i, t in enumerate(tracks):
            d = float(np.hypot(t.last[0] - centre[0], t.last[1] - centre[1]))
            if not used[i] and d < best_d:
                best, best_d = i, d
        if best < 0:
            tracks.append(Track(centre, centre, 1, step, False, box))
            used.append(True)
            t = tracks[-1]
        else:
            old = tracks[best]
            moved = float(np.hypot(old.first[0] - centre[0], old.first[1] - centre[1])) > params.min_motion
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


__all__ = ["Objects", "ObjectsState", "candidates", "track_objects"]
