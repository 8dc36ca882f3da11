"""Scoring one world model against the simulator's ground truth (`score_frame`).

Everything is compared in the map frame. The world model's zero frame is placed there with
the true pose of the same frame (map_T_zero = truth_pose (x) wm.pose^-1), so wall, corner
and door scores measure the *map* the perceptor built, not its odometry; the pose error is
reported on its own.

- **Walls** (length-weighted, sampled every `sample_step`): *precision* = the share of the
  local map's wall length lying within `wall_distance` of a true solid segment whose
  direction is within `wall_angle`; *recall* = the share of the truly visible wall length
  (`truth.visible_walls()`: the pieces the scan's beams hit) within the same tolerances of a
  local-map wall.
- **End points**: mean distance from each non-floating local-map wall end (a corner or a seen
  end) to the nearest true vertex: the static geometry's corners and, when the truth has
  them, `truth.dynamic_vertices()` (door leaves and moving objects where they are now: a
  standing box's corner or a closed door's end seen rightly is no error).
- **Corners**: detected corners vs the true corners in view (`truth.visible_corners()`),
  matched one to one, nearest first, within `corner_distance`: precision, recall, and the
  share of matched corners whose convex/concave property is right.
- **Doors**: a detected door matches a true opening (`truth.door_openings()`: the map's doors
  and the gaps between wall ends of a door's width) when their middles are within
  `door_distance` and their directions within `door_angle`. Precision over detected doors
  (against every opening), recall over the openings in view: `truth.visible_doors()` (the
  middle in view, and the scan's beams hit the wall at each jamb over a minimum length: see
  `sim/truth.py`). A door whose jamb is not seen cannot be told from a wall's loose end; the
  perceptor reports it as a possible door at best.
- **Map-confirmed doors**: when the world model was localised (`wm.combined`, the combined
  map), its doors the global map confirmed (`combined.door_confirmed`) are scored the same
  way in the global frame (the simulator's map frame): precision and recall of the doors a
  localised robot would act on. The perceptor's own doors above are scored without the map.
- **Pose**: the perceptor's pose relative to its zero vs the true motion since that frame.

Counts and lengths are summed over frames (`run_score.RunScore`), so a run's figures weigh
every metre of wall and every door the same.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from pico_studio.core.geometry import (
    compose,
    door_matches,
    invert,
    relative,
    transform_points,
    transform_segments,
)
from pico_studio.core.world_model import FLOATING, WorldModel
from pico_studio.evaluation.score_kernels import (
    match_nearest,
    nearest_distances,
    wall_coverage,
)

Pose = tuple[float, float, float]


@dataclass(frozen=True)
class Tolerances:
    """How close counts as right (the scoring's own settings, not the perceptor's)."""

    wall_distance: float = 0.1  # m
    wall_angle: float = 0.2  # rad
    sample_step: float = 0.02  # m
    corner_distance: float = 0.15  # m
    door_distance: float = 0.3  # m
    door_angle: float = 0.3  # rad


@dataclass
class FrameScore:
    """Sums for one frame; ratios come from `run_score.RunScore`."""

    wall_len: float = 0.0
    wall_len_ok: float = 0.0
    truth_len: float = 0.0
    truth_len_ok: float = 0.0
    endpoint_err_sum: float = 0.0
    endpoints: int = 0
    corners: int = 0
    corners_ok: int = 0
    truth_corners: int = 0
    truth_corners_ok: int = 0
    corners_paired: int = 0  # detected corners paired one to one with a true corner in view
    convexity_ok: int = 0
    doors: int = 0
    doors_ok: int = 0
    truth_doors: int = 0
    truth_doors_ok: int = 0
    map_frames: int = 0  # frames with a combined (localised) map
    map_doors: int = 0  # its map-confirmed doors
    map_doors_ok: int = 0
    map_truth_doors_ok: int = 0
    pose_err_m: float = 0.0
    pose_err_rad: float = 0.0


# ----- geometry helpers ----------------------------------------------------------------------


def _samples(segments: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points along each segment about `step` apart: (points (P, 2), owner (P,), weight (P,) m)."""
    if len(segments) == 0:
        return np.zeros((0, 2)), np.zeros(0, dtype=np.int64), np.zeros(0)
    length = np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1])
    n = np.maximum(np.ceil(length / step).astype(np.int64), 1)
    owner = np.repeat(np.arange(len(segments)), n)
    start = np.concatenate([[0], np.cumsum(n)[:-1]])
    k = np.arange(n.sum()) - np.repeat(start, n)
    t = (k + 0.5) / np.repeat(n, n)
    s = segments[owner]
    pts = s[:, 0:2] + t[:, None] * (s[:, 2:4] - s[:, 0:2])
    return pts, owner, (length / n)[owner]


def covered(points: np.ndarray, owner_dir: np.ndarray, segments: np.ndarray, tol: Tolerances) -> np.ndarray:
    """(P,) bool: each point lies within `wall_distance` of a segment within `wall_angle` of
    its owner's direction (owner_dir (P, 2) unit vectors). With `_samples`, the readable numpy
    form of `score_kernels.wall_coverage`, which `score_arrays` runs (tests compare the two)."""
    out = np.zeros(len(points), dtype=bool)
    if len(points) == 0 or len(segments) == 0:
        return out
    a, b = segments[:, 0:2], segments[:, 2:4]
    ab = b - a
    len2 = np.maximum((ab**2).sum(-1), 1e-18)
    # only the (point, segment) pairs that can match get the exact distance: parallel enough,
    # and the point inside the segment's box grown by the distance tolerance
    r = tol.wall_distance
    lo, hi = np.minimum(a, b) - r, np.maximum(a, b) + r
    x, y = points[:, 0:1], points[:, 1:2]
    near = (x >= lo[:, 0]) & (x <= hi[:, 0]) & (y >= lo[:, 1]) & (y <= hi[:, 1])
    near &= np.abs(owner_dir @ (ab / np.sqrt(len2)[:, None]).T) >= math.cos(tol.wall_angle)
    pi, si = np.nonzero(near)
    if len(pi) == 0:
        return out
    ap = points[pi] - a[si]
    t = np.clip((ap * ab[si]).sum(-1) / len2[si], 0.0, 1.0)
    d = np.hypot(*(ap - t[:, None] * ab[si]).T)
    out[pi[d <= r]] = True
    return out


def _dirs(segments: np.ndarray) -> np.ndarray:
    d = segments[:, 2:4] - segments[:, 0:2]
    return d / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-12)[:, None]


def match_points(a: np.ndarray, b: np.ndarray, radius: float) -> list[tuple[int, int]]:
    """One-to-one pairs (i, j), nearest first, with |a_i - b_j| <= radius (one compiled loop:
    `score_kernels.match_nearest`; equal distances are taken in (i, j) order)."""
    ia, ib = match_nearest(_c2(a), _c2(b), float(radius))
    return list(zip(ia.tolist(), ib.tolist(), strict=True))


def doors_match(found: np.ndarray, truth: np.ndarray, tol: Tolerances) -> np.ndarray:
    """(F, T) bool: door f matches opening t (middles close, directions parallel; one compiled
    loop: `geometry.door_matches`, the combined map's test too)."""
    return door_matches(_c4(found), _c4(truth), float(tol.door_distance), math.cos(tol.door_angle))


# ----- one frame -----------------------------------------------------------------------------


def _c4(segments: np.ndarray) -> np.ndarray:
    """Segments as a C-contiguous float64 (N, 4): the layout the kernels are built for."""
    return np.ascontiguousarray(segments, dtype=np.float64).reshape(-1, 4)


def _c2(points: np.ndarray) -> np.ndarray:
    """Points as a C-contiguous float64 (N, 2)."""
    return np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)


def score_arrays(
    *,
    walls: np.ndarray,
    endpoint_property: np.ndarray,
    corners: np.ndarray,
    corner_convex: np.ndarray,
    doors: np.ndarray,
    solid: np.ndarray,
    visible_walls: np.ndarray,
    true_vertices: np.ndarray,
    visible_corners: np.ndarray,
    visible_convex: np.ndarray,
    openings: np.ndarray,
    visible_doors: np.ndarray,
    tol: Tolerances = Tolerances(),
) -> FrameScore:
    """Score map-frame detections against map-frame truth (all arrays in the map frame)."""
    s = FrameScore()
    # wall precision and recall: `_samples` + `covered` as one compiled loop (score_kernels)
    walls, solid, visible_walls = _c4(walls), _c4(solid), _c4(visible_walls)
    cos_angle = math.cos(tol.wall_angle)
    s.wall_len, s.wall_len_ok = wall_coverage(walls, tol.sample_step, solid, tol.wall_distance, cos_angle)
    s.truth_len, s.truth_len_ok = wall_coverage(visible_walls, tol.sample_step, walls, tol.wall_distance, cos_angle)
    true_vertices = np.ascontiguousarray(true_vertices, dtype=np.float64).reshape(-1, 2)
    if len(walls) and len(true_vertices):
        ends = walls.reshape(-1, 2)[endpoint_property.reshape(-1) != FLOATING]
        if len(ends):
            d = nearest_distances(ends, true_vertices)
            s.endpoint_err_sum, s.endpoints = float(d.sum()), len(d)
    corners = _c2(corners)
    pa, pb = match_nearest(corners, _c2(visible_corners), float(tol.corner_distance))  # `match_points`' pairs
    s.corners, s.truth_corners = len(corners), len(visible_corners)
    s.corners_ok = s.truth_corners_ok = s.corners_paired = len(pa)
    s.convexity_ok = int(np.count_nonzero(np.asarray(corner_convex, dtype=bool)[pa] == np.asarray(visible_convex, dtype=bool)[pb]))
    # a detected corner next to a true corner that is just out of view is still a true corner
    if len(corners) > len(pa) and len(true_vertices):
        rest = np.ones(len(corners), dtype=bool)
        rest[pa] = False
        d = nearest_distances(corners[rest], true_vertices)
        s.corners_ok += int((d <= tol.corner_distance).sum())
    s.doors = len(doors)
    s.doors_ok = int(doors_match(doors, openings, tol).any(axis=1).sum())
    s.truth_doors = len(visible_doors)
    s.truth_doors_ok = int(doors_match(doors, visible_doors, tol).any(axis=0).sum())
    return s


def as_pose(v: Any) -> Pose:
    """Any (x, y, a) sequence as a pose tuple of floats."""
    return (float(v[0]), float(v[1]), float(v[2]))


def zero_to_map(wm: WorldModel, true_pose: Pose) -> Pose:
    """The pose of the world model's zero frame in the map frame, placed by the true pose."""
    return compose(true_pose, invert(as_pose(wm.pose)))


def score_frame(wm: WorldModel, truth: Any, tol: Tolerances = Tolerances(),
                true_zero: Pose | None = None, true_vertices: np.ndarray | None = None) -> FrameScore:
    """Score one world model against the simulator's truth for the same frame.

    `true_zero`: the true pose at the frame the perceptor took as zero (for the pose error);
    `true_vertices`: every corner of the static geometry (for the end-point error; default
    the corners in view), joined by the truth's `dynamic_vertices()` when it has them."""
    true_pose = as_pose(truth.pose)
    z = zero_to_map(wm, true_pose)
    walls = transform_segments(np.asarray(wm.local_map.walls, dtype=float), z)
    corners = transform_points(np.asarray(wm.corners, dtype=float).reshape(-1, 2), z)
    doors = transform_segments(np.asarray(wm.doors, dtype=float).reshape(-1, 4), z)
    vc = truth.visible_corners()
    visible_doors = truth.visible_doors()
    vertices = vc.points if true_vertices is None else true_vertices
    dynamic = getattr(truth, "dynamic_vertices", None)
    more = dynamic() if dynamic is not None else np.zeros((0, 2))
    if len(more):  # (none: no door leaves or moving objects, nothing to copy)
        vertices = np.concatenate([np.asarray(vertices, dtype=float).reshape(-1, 2), more])
    s = score_arrays(
        walls=walls,
        endpoint_property=np.asarray(wm.local_map.endpoint_property),
        corners=corners,
        corner_convex=np.asarray(wm.corner_convex, dtype=bool),
        doors=doors,
        solid=truth.segments(),
        visible_walls=truth.visible_walls(),
        true_vertices=vertices,
        visible_corners=vc.points,
        visible_convex=vc.convex,
        openings=truth.door_openings(),
        visible_doors=visible_doors,
        tol=tol,
    )
    combined = getattr(wm, "combined", None)
    if combined is not None:
        confirmed = np.asarray(combined.doors, dtype=float).reshape(-1, 4)[np.asarray(combined.door_confirmed, dtype=bool)]
        s.map_frames, s.map_doors = 1, len(confirmed)
        s.map_doors_ok = int(doors_match(confirmed, truth.door_openings(), tol).any(axis=1).sum())
        s.map_truth_doors_ok = int(doors_match(confirmed, visible_doors, tol).any(axis=0).sum())
    if true_zero is not None:
        true_rel = relative(true_zero, true_pose)
        err = relative(true_rel, as_pose(wm.pose))
        s.pose_err_m, s.pose_err_rad = math.hypot(err[0], err[1]), abs(err[2])
    return s


def true_zero_pose(wm: WorldModel, sim: Any) -> Pose | None:
    """The true map pose of the frame the perceptor took as zero (absolute odometry only)."""
    return true_zero_from(wm, sim.truth, sim.params.odometry.form)


def true_zero_from(wm: WorldModel, truth: Any, odometry_form: str) -> Pose | None:
    """`true_zero_pose` from a truth with `pose` and `odometry_pose` (the simulator's or a kept
    one): map_T_odom = truth (x) odom^-1 now, applied to the zero pose's odometry reading."""
    if wm.zero_pose is None or odometry_form != "absolute":
        return None
    map_from_odom = compose(as_pose(truth.pose), invert(as_pose(truth.odometry_pose)))
    return compose(map_from_odom, as_pose(wm.zero_pose))


def static_vertices(sim: Any) -> np.ndarray:
    """Every corner of the simulated world's static geometry (for the end-point error)."""
    static = sim.world.static
    if len(static) == 0:
        return np.zeros((0, 2))
    return np.unique(np.round(static.reshape(-1, 2), 6), axis=0)
