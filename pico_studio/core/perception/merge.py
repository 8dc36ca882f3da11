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
4. **Merge** local walls that became similar to each other (a wall seen in two pieces), and a
   short wall lying along a longer one, within `angle` and `distance` of its line and between
   its ends (a corner's fragment left beside the wall it belongs to).
5. **Connect** end points of two walls at least `connect_min_angle` apart whose ends lie
   within `connect_radius` of the lines' crossing: the corner is the crossing, pulled
   towards the previous corner by the end's weight (its number of consecutive connected
   scans, at most `max_weight`), so one noisy scan cannot move a well-seen corner far. An end
   near the inside of another wall (a T, e.g. a cabinet against a wall) connects too.
6. **Drop**: walls shorter than `min_length`; walls the laser passed through `miss_limit` scans in a row (a door opened, an
   object moved) — and a wall's end it passed through, up to where it met the wall, is cut
   back (`trim_step`: a smear merged on to a wall's end); tentative walls not seen again within `tentative_life` scans; walls not
   seen for `forget_scans` scans (when set); walls beyond `keep_radius`; beyond `max_walls`, the least seen. What is shown are walls seen at least
   `confirm_hits` times and connected to another wall — or seen `unconnected_hits` times —
   so the map holds connected walls and does not flicker when one scan misses a wall.

Each step is one compiled pass over the map's arrays, with its maths: merge_kernels.py.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pico_studio.config.perception_params import MergeParams
from pico_studio.core.geometry import transform_segments
from pico_studio.core.perception.merge_kernels import (
    compact,
    connect,
    drop_mask,
    fold_in,
    merge_similar,
    see_through,
    shown_walls,
    trim_through,
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
    # (step, stamp) of the steps within the last `forget_seconds` (when set): a wall last seen
    # before the window's first step was not seen for that long
    window: tuple[tuple[int, float], ...] = ()
    # (W, 2) zero frame: where the robot stood when it last saw each wall, the pose's position for
    # the walls seen in this step (None: unknown, as if from where it stands now) — a corner in a
    # room the robot has left is judged as seen from there
    viewpoint: np.ndarray | None = None

    @staticmethod
    def empty() -> LocalMapState:
        return LocalMapState(
            np.zeros((0, 4)), np.zeros(0), np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64),
            np.zeros((0, 2), dtype=bool), np.zeros((0, 2)), np.zeros((0, 2), dtype=np.int64), 0,
            viewpoint=np.zeros((0, 2)),
        )

    def shown(self, params: MergeParams) -> np.ndarray:
        """(W,) bool: walls confirmed enough to be in the local map's output."""
        mask = np.zeros(len(self.hits), dtype=bool)
        mask[self.shown_walls(params)[0]] = True
        return mask

    def shown_walls(self, params: MergeParams) -> tuple[np.ndarray, np.ndarray]:
        """The shown walls' indices (S,) and their connections among them (S, 2), -1 none."""
        return shown_walls(self.hits, self.connected, float(params.confirm_hits), float(params.unconnected_hits))


def merge(
    state: LocalMapState, segs: Segments, pose: Pose, scan: ScanPoints, params: MergeParams,
    stamp: float = math.nan,
) -> LocalMapState:
    step = state.step + 1
    window, forget_scans = _forget_window(state.window, step, stamp, params)
    # 1-3. associate, fuse, add (the current map brought to the zero frame with the pose)
    new = np.ascontiguousarray(transform_segments(segs.segments, pose), dtype=float)
    cos_angle, distance, gap, max_weight = math.cos(params.angle), float(params.distance), float(params.gap), float(params.max_weight)
    walls, hits, last_seen, missed, seen_end, end_weight = fold_in(
        state.walls, state.hits, state.last_seen, state.missed, state.seen_end, state.end_weight,
        new, segs.end_kind != END_FLOATING, segs.end_kind == END_SEEN,  # real: a corner of the scan or a seen free end
        step, cos_angle, distance, gap, max_weight)
    # 4. merge local walls that became similar to each other
    viewpoint = np.zeros((len(walls), 2))  # the old walls' first, then the new ones (seen now)
    w_old = len(state.walls)
    viewpoint[:w_old] = pose[:2] if state.viewpoint is None else state.viewpoint
    viewpoint[last_seen == step] = pose[:2]
    walls, hits, last_seen, missed, seen_end, end_weight, viewpoint = merge_similar(
        walls, hits, last_seen, missed, seen_end, end_weight, viewpoint, cos_angle, distance, gap, max_weight)
    # 6a. walls the laser passed through; ends it passed through cut back
    _see_through(walls, last_seen, step, missed, pose, scan, params)
    if params.trim_step > 0:
        _trim_through(walls, pose, scan, params)
    # 5. connect ends into corners and T's
    connected, end_weight = connect(walls, hits, end_weight, seen_end, float(params.connect_radius),
                                    math.sin(params.connect_min_angle), float(params.confirm_hits), max_weight)
    # 6. drop
    keep = drop_mask(walls, hits, last_seen, missed, connected, float(pose[0]), float(pose[1]), step,
                     float(params.unconnected_hits), int(params.tentative_life), int(params.miss_limit),
                     forget_scans, float(params.keep_radius), float(params.min_length))
    if keep.sum() > params.max_walls:  # beyond max_walls, the least seen go (numpy's sort: its ties)
        linked = (connected >= 0).any(axis=1)
        order = np.argsort(-(hits + 0.5 * linked))
        cap = np.zeros(len(keep), dtype=bool)
        cap[order[: params.max_walls]] = True
        keep &= cap
    if not keep.all():
        walls, hits, last_seen, missed, seen_end, end_weight, connected = compact(
            keep, walls, hits, last_seen, missed, seen_end, end_weight, connected)
        viewpoint = viewpoint[keep]
    return LocalMapState(walls, hits, last_seen, missed, seen_end, end_weight, connected, step, window, viewpoint)


def _forget_window(window: tuple[tuple[int, float], ...], step: int, stamp: float,
                   params: MergeParams) -> tuple[tuple[tuple[int, float], ...], int]:
    """The steps stamped within `forget_seconds` of `stamp`, and the scans a wall may go
    unseen (-1: for ever): the lesser of `forget_scans` and the steps since the window's first
    (0 across a gap in a log longer than the window: only what this scan sees stays)."""
    forget = int(params.forget_scans) if params.forget_scans > 0 else -1
    if params.forget_seconds <= 0 or not math.isfinite(stamp):
        return (), forget
    if window and window[-1][1] > stamp:  # time ran backwards (a log restarted): start over
        window = ()
    cutoff, first = stamp - params.forget_seconds, 0
    while first < len(window) and window[first][1] < cutoff:  # stamps ascend: trim the front
        first += 1
    window = window[first:] + ((step, stamp),)
    span = step - window[0][0]
    return window, span if forget < 0 else min(forget, span)


def _beams(walls: np.ndarray, scan: ScanPoints) -> tuple[float, float] | None:
    """The scan's first beam's angle and the increment, or None when there is nothing to test
    (no walls, fewer than two beams, no usable increment)."""
    if len(walls) == 0 or len(scan.ranges) < 2:
        return None
    a0 = float(scan.angles[0])
    inc = (float(scan.angles[-1]) - a0) / (len(scan.angles) - 1)
    return None if inc == 0 or not math.isfinite(inc) else (a0, inc)


def _see_through(walls: np.ndarray, last_seen: np.ndarray, step: int, missed: np.ndarray, pose: Pose,
                 scan: ScanPoints, params: MergeParams) -> None:
    """Count, in place in `missed`, whether the laser passed through walls not seen this scan."""
    if (beams := _beams(walls, scan)) is None:
        return
    a0, inc = beams
    see_through(walls, last_seen, step, missed, float(pose[0]), float(pose[1]), float(pose[2]),
                np.ascontiguousarray(scan.ranges, dtype=float), np.ascontiguousarray(scan.valid, dtype=bool), a0, inc,
                float(params.see_through))


def _trim_through(walls: np.ndarray, pose: Pose, scan: ScanPoints, params: MergeParams) -> None:
    """Cut back, in place, wall ends the laser passed through (merge_kernels.trim_through)."""
    if (beams := _beams(walls, scan)) is None:
        return
    a0, inc = beams
    trim_through(walls, float(pose[0]), float(pose[1]), float(pose[2]),
                 np.ascontiguousarray(scan.ranges, dtype=float), np.ascontiguousarray(scan.valid, dtype=bool), a0, inc,
                 float(params.see_through), float(params.trim_step))


def scan_passes(walls: np.ndarray, pose: Pose, scan: ScanPoints, params: MergeParams) -> np.ndarray:
    """(W,) bool: the scan's beams pass through the wall (by `see_through`) at most of its
    points (merge_kernels.see_through's test, on a copy): it stands there no more. Out of view
    or behind something, a wall is not passed."""
    missed = np.zeros(len(walls), dtype=np.int64)  # 1 after the test: passed through
    _see_through(walls, np.full(len(walls), -1, dtype=np.int64), 0, missed, pose, scan, params)
    return missed > 0


def drop_near(state: LocalMapState, places: np.ndarray, radius: float, ages: np.ndarray | None = None,
              standing: np.ndarray | None = None) -> LocalMapState:
    """The state without walls lying entirely within `radius` of one of `places` (V, 2): what
    an object left where it stood before it turned out to move. With `ages` (V,), the scans
    since each object was first seen, and `standing` (W,), the walls the current scan does not
    pass through (`scan_passes`), a wall seen in more scans than the object is old and not seen
    through now stays: it stood there before the object came (a wall's end cap, tracked as an
    object while its seen end slid along as the view changed, leaves hospital_2019's doorway its
    walls; a table's side a box walked past, its smear merged into it, is seen through where the
    box was)."""
    if len(places) == 0 or len(state.walls) == 0:
        return state
    ends = state.walls.reshape(-1, 2, 2)
    d = np.hypot(*(ends[:, :, None, :] - places[None, None, :, :]).transpose(3, 0, 1, 2))  # (W, 2, V)
    near = (d <= radius).all(axis=1)  # (W, V)
    if ages is not None and standing is not None:
        near &= ~((state.hits[:, None] > np.asarray(ages, dtype=float)[None, :]) & standing[:, None])
    gone = near.any(axis=1)
    if not gone.any():
        return state
    s = state
    walls, hits, last_seen, missed, seen_end, end_weight, connected = compact(
        ~gone, s.walls, s.hits, s.last_seen, s.missed, s.seen_end, s.end_weight, s.connected)
    viewpoint = None if s.viewpoint is None else s.viewpoint[~gone]
    return LocalMapState(walls, hits, last_seen, missed, seen_end, end_weight, connected, s.step, s.window, viewpoint)


__all__ = ["END_SEEN", "LocalMapState", "drop_near", "merge", "scan_passes"]
