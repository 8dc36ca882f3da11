"""Scan-to-map alignment: refine a pose by Gauss-Newton, find one by a grid search.

Refinement (point-to-line Gauss-Newton). A laser point p (robot frame) lands at
q = R(a) p + t in the map. Its nearest map segment k (from the distance field) has unit
normal n_k and a point s_k on it; the residual is the signed distance to that line,

    r = n_k . (q - s_k),       dr/d(x, y, a) = [n_x, n_y, n_k . (R'(a) p)],  R'(a) p = perp(q - t).

Each iteration re-associates points with segments, drops points further than an outlier
distance (which shrinks over the iterations), weighs the rest by the Huber loss and solves
the 3 x 3 normal equations (J^T W J) d = -J^T W r.

Search (coarse, brute force). For each heading on a grid, rotate a subsample of the scan
once, then score every position of the grid at once by the mean truncated distance of the
points (nearest-cell lookups of the distance field); the best distinct candidates are then
refined and the one explaining most beams, less those through walls, wins. A wall thinner
than the inlier distance has two faces that explain its beams equally: a candidate refined
onto the far one sends beams through it, so such a candidate is refined again from a step
(2 x `inlier_distance`) to either side along both axes, and the best of those kept (a ward's
5 cm walls, a table 1-3 cm off a wall).

Quality = the fraction of the scan's points within `inlier_distance` of the map. Through-walls
= the fraction of beams that would cross a map wall before their end point (an unmapped
obstacle only makes beams short; a wrong pose sends them through walls).
Constraint = the smallest eigenvalue of the translation block of J^T W J / sum(W): how
firmly the matched walls pin the position down (0 in a corridor, up to 0.5 in a corner).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from pico_studio.config.localisation_params import MatcherParams, SearchParams
from pico_studio.core.geometry import wrap_angle
from pico_studio.core.localisation.distance_field import DistanceField
from pico_studio.core.localisation.match_kernels import (
    coarse_scores,
    quality_kernel,
    refine_kernel,
    through_kernel,
    usable_kernel,
)

Pose = tuple[float, float, float]


@dataclass(frozen=True)
class Match:
    pose: Pose
    quality: float  # fraction of points explained by the map at `pose`
    inliers: int  # number of points used in the last Gauss-Newton step
    converged: bool
    constraint: float = 0.0  # smallest eigenvalue of the per-point x-y information (0 .. 0.5)
    through: float | None = None  # fraction of beams passing through map walls (when checked)


def usable_points(points: np.ndarray, max_range: float) -> np.ndarray:
    """Finite points within range (robot frame)."""
    return usable_kernel(_c(np.asarray(points, dtype=float).reshape(-1, 2)), float(max_range))


def quality(field: DistanceField, points: np.ndarray, pose: Pose, inlier_distance: float) -> float:
    """Fraction of `points` (robot frame) lying within `inlier_distance` of the map at `pose`."""
    if len(points) == 0:
        return 0.0
    return float(quality_kernel(field.field, field.x0, field.y0, field.resolution, _c(points),
                                float(pose[0]), float(pose[1]), float(pose[2]), float(inlier_distance)))


def beams_through_walls(field: DistanceField, points: np.ndarray, pose: Pose,
                        params: MatcherParams) -> float:
    """Fraction of (about `ray_beams`) laser beams that would cross a map wall before their
    end point at `pose`: negative evidence a plain fit cannot see (an unmapped box only makes
    beams *short*; a wrong pose sends them *through* walls).

    Samples every `ray_step` along each beam up to `ray_clearance` before its end point (so a
    wall's far face, a few cm behind its near face, is seen as through the wall); a
    crossing is a sign change of the signed distance to the same nearest segment between two
    samples, at a point within that segment (so grazing a corner is no crossing). Doors
    (`field.passable`) are no walls. The loop: match_kernels.through_kernel.
    """
    if len(points) == 0:
        return 0.0
    pts = _c(points[:: max(1, len(points) // params.ray_beams)])
    passable = field.passable if field.passable is not None else np.zeros(len(field.segments), dtype=bool)
    return float(through_kernel(field.segment_index, field.x0, field.y0, field.resolution, _c(field.segments),
                                _c(field.normals), np.ascontiguousarray(passable, dtype=np.bool_), pts,
                                float(params.ray_step), float(params.ray_clearance),
                                float(pose[0]), float(pose[1]), float(pose[2])))


def refine(field: DistanceField, points: np.ndarray, pose: Pose, params: MatcherParams) -> Match:
    """Gauss-Newton point-to-line alignment of `points` (robot frame) starting at `pose`
    (one compiled loop: match_kernels.refine_kernel)."""
    x, y, a, used, converged, constraint = refine_kernel(
        field.field, field.segment_index, field.x0, field.y0, field.resolution, _c(field.segments),
        _c(field.normals), _c(points[:: params.beam_stride]), float(pose[0]), float(pose[1]), float(pose[2]),
        int(params.iterations), float(params.outlier_distance), float(params.final_outlier_distance),
        float(params.huber), float(params.inlier_distance))
    result: Pose = (float(x), float(y), float(a))
    return Match(result, quality(field, points, result, params.inlier_distance), int(used), bool(converged),
                 float(constraint))


def _c(a: np.ndarray) -> np.ndarray:
    """A C-contiguous float64 copy (or the array itself): the layout the kernels are built for."""
    return np.ascontiguousarray(a, dtype=np.float64)


def search(
    field: DistanceField,
    points: np.ndarray,
    center: tuple[float, float],
    half_extent: tuple[float, float],
    heading: float,
    heading_range: float,
    params: SearchParams,
    matcher: MatcherParams,
) -> Match | None:
    """Best pose in a box of positions and a range of headings; None without usable points."""
    if len(points) < 3:
        return None
    candidates = coarse_candidates(field, points, center, half_extent, heading, heading_range, params)
    best: Match | None = None
    for pose in candidates:
        m = _refined(field, points, pose, matcher)
        if m.through:
            # a wall thinner than the inlier distance has two faces either of which explains
            # the beams: refined onto the far one, beams pass through it. Start again a step
            # to either side, along both axes, and keep what explains the scan without
            # beams through walls
            step = 2 * matcher.inlier_distance
            for dx, dy in ((step, 0.0), (-step, 0.0), (0.0, step), (0.0, -step)):
                n = _refined(field, points, (m.pose[0] + dx, m.pose[1] + dy, m.pose[2]), matcher)
                if n.quality - (n.through or 0.0) > m.quality - m.through:
                    m = n
        # explained beams count for, beams through walls against a candidate
        if best is None or m.quality - (m.through or 0.0) > best.quality - (best.through or 0.0):
            best = m
    return best


def _refined(field: DistanceField, points: np.ndarray, pose: Pose, matcher: MatcherParams) -> Match:
    """`refine` from `pose`, with the share of beams through walls at the result."""
    m = refine(field, points, pose, matcher)
    return replace(m, through=beams_through_walls(field, points, m.pose, matcher))


def search_grid(
    half_extent: tuple[float, float], heading_range: float, params: SearchParams
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Offsets in x, y and heading of the search grid, coarsened to at most `max_cells` poses."""
    pos_step, head_step = params.position_step, params.heading_step
    while True:
        xs = _axis(half_extent[0], pos_step)
        ys = _axis(half_extent[1], pos_step)
        if heading_range >= math.pi:
            n = max(1, int(math.ceil(2 * math.pi / head_step)))
            hs = -math.pi + (np.arange(n) + 0.5) * (2 * math.pi / n)
        else:
            hs = _axis(heading_range, head_step)
        if len(xs) * len(ys) * len(hs) <= params.max_cells:
            return xs, ys, hs
        # too many cells: coarsen position and heading together
        pos_step *= 1.25
        head_step *= 1.25


def best_first(scores: np.ndarray, k: int) -> np.ndarray:
    """Flat indices of the k lowest scores, lowest first, ties in index order: a stable
    argsort's first k, without sorting the whole grid (a million poses: ~1 ms, not ~20)."""
    flat = scores.ravel()
    if k <= 0 or flat.size == 0:
        return np.zeros(0, dtype=np.int64)
    part = np.arange(flat.size)
    if k < flat.size:
        kth = np.partition(flat, k - 1)[k - 1]
        if not np.isnan(kth):  # (NaN sorts last: with fewer than k numbers, take them all)
            part = np.flatnonzero(flat <= kth)  # every tie of the k-th, so the order is stable
    return part[np.lexsort((part, flat[part]))][:k]


def _axis(half: float, step: float) -> np.ndarray:
    n = int(math.floor(half / step))
    return np.arange(-n, n + 1) * step


def coarse_candidates(
    field: DistanceField,
    points: np.ndarray,
    center: tuple[float, float],
    half_extent: tuple[float, float],
    heading: float,
    heading_range: float,
    params: SearchParams,
) -> list[Pose]:
    """The best distinct grid poses by mean truncated distance of a scan subsample.

    Positions lie on every `stride`-th node of the distance field, so a rotated scan point
    is a whole number of nodes away from the robot: the scores of all positions for one
    point are one shifted slice of the (coarse, truncated, padded) field, summed over points.
    """
    stride_n = max(1, len(points) // params.points)
    pts = points[::stride_n]
    xs, ys, hs = search_grid(half_extent, heading_range, params)
    stride = max(1, round((xs[1] - xs[0] if len(xs) > 1 else params.position_step) / field.resolution))
    step = stride * field.resolution
    # pad by the farthest point, rounded up to whole metres so the cached grid is reused
    reach = math.ceil(float(np.hypot(pts[:, 0], pts[:, 1]).max()))
    pad = int(math.ceil(reach / step)) + 1
    grid = field.coarse(stride, params.truncation, pad)
    rows, cols = grid.shape[0] - 2 * pad, grid.shape[1] - 2 * pad

    # the position grid as node ranges, clipped to the field
    jc, ic = (center[0] - field.x0) / step, (center[1] - field.y0) / step
    j0 = max(0, int(math.floor(jc - half_extent[0] / step)))
    j1 = min(cols - 1, int(math.ceil(jc + half_extent[0] / step)))
    i0 = max(0, int(math.floor(ic - half_extent[1] / step)))
    i1 = min(rows - 1, int(math.ceil(ic + half_extent[1] / step)))
    if j0 > j1 or i0 > i1:
        return []
    ny, nx = i1 - i0 + 1, j1 - j0 + 1

    # per heading, every point's offset in whole nodes; the scores: one compiled loop
    offsets = np.empty((len(hs), len(pts), 2), dtype=np.int64)
    for h, dh in enumerate(hs):
        a = heading + dh
        c, s = math.cos(a), math.sin(a)
        offsets[h] = np.rint(pts @ np.array([[c, s], [-s, c]]) / step)
    scores = coarse_scores(np.ascontiguousarray(grid, dtype=np.float32), offsets, pad + i0, pad + j0, ny, nx)

    # best first; skip candidates close to one already taken (non-maximum suppression)
    taken: list[Pose] = []
    for flat in best_first(scores, 50 * params.candidates):
        h, i, j = np.unravel_index(flat, scores.shape)
        pose = (field.x0 + (j0 + j) * step, field.y0 + (i0 + i) * step,
                float(wrap_angle(heading + hs[h])))
        sep = params.separation
        if any(math.hypot(pose[0] - t[0], pose[1] - t[1]) < sep * step
               and abs(float(wrap_angle(pose[2] - t[2]))) < sep * params.heading_step for t in taken):
            continue
        taken.append(pose)
        if len(taken) >= params.candidates:
            break
    return taken
