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
refined and the one explaining most beams wins.

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
from pico_studio.core.geometry import transform_points, wrap_angle
from pico_studio.core.localisation.distance_field import DistanceField

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
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    ok = np.isfinite(points).all(axis=1)
    ok[ok] &= np.hypot(points[ok, 0], points[ok, 1]) <= max_range
    return points[ok]


def quality(field: DistanceField, points: np.ndarray, pose: Pose, inlier_distance: float) -> float:
    """Fraction of `points` (robot frame) lying within `inlier_distance` of the map at `pose`."""
    if len(points) == 0:
        return 0.0
    d = field.distance(transform_points(points, pose))
    return float(np.mean(d <= inlier_distance))


def beams_through_walls(field: DistanceField, points: np.ndarray, pose: Pose,
                        params: MatcherParams) -> float:
    """Fraction of (about `ray_beams`) laser beams that would cross a map wall before their
    end point at `pose`: negative evidence a plain fit cannot see (an unmapped box only makes
    beams *short*; a wrong pose sends them *through* walls).

    Samples every `ray_step` along each beam up to `ray_clearance` before its end point (so a
    wall's far face, a few cm behind its near face, is seen as through the wall); a
    crossing is a sign change of the signed distance to the same nearest segment between two
    samples, at a point within that segment (so grazing a corner is no crossing).
    """
    if len(points) == 0:
        return 0.0
    step, clearance = params.ray_step, params.ray_clearance
    pts = points[:: max(1, len(points) // params.ray_beams)]
    ranges = np.hypot(pts[:, 0], pts[:, 1])
    # samples every step, the last one exactly `clearance` before the end point (repeats of
    # it after that are harmless: a pair of equal samples has no sign change)
    last = np.maximum(ranges - clearance, 0.0)[:, None]
    t = np.minimum(np.arange(1, int(np.ceil(ranges.max() / step)) + 1)[None, :] * step, last)  # (B, n)
    ahead = t > 0.0
    dirs = pts / np.maximum(ranges, 1e-9)[:, None]
    q = transform_points((dirs[:, None, :] * t[:, :, None]).reshape(-1, 2), pose)
    q = q.reshape(t.shape[0], t.shape[1], 2)
    k = field.nearest_segment(q)  # (B, n)
    seg = field.segments[np.maximum(k, 0)]  # (B, n, 4)
    side = ((q - seg[..., 0:2]) * field.normals[np.maximum(k, 0)]).sum(axis=-1)
    flip = (k[:, :-1] == k[:, 1:]) & (k[:, 1:] >= 0) & ahead[:, 1:]
    if field.passable is not None:  # an open door is no wall
        flip &= ~field.passable[np.maximum(k[:, 1:], 0)]
    flip &= np.signbit(side[:, :-1]) != np.signbit(side[:, 1:])
    # where the beam crosses the line, and whether that is on the segment
    w = side[:, :-1] / np.where(flip, side[:, :-1] - side[:, 1:], 1.0)
    c = q[:, :-1] + w[..., None] * (q[:, 1:] - q[:, :-1])
    a, b = seg[:, :-1, 0:2], seg[:, :-1, 2:4]
    ab = b - a
    u = ((c - a) * ab).sum(axis=-1) / np.maximum((ab**2).sum(axis=-1), 1e-12)
    crossed = (flip & (u >= 0.0) & (u <= 1.0)).any(axis=1)
    return float(crossed.mean())


def refine(field: DistanceField, points: np.ndarray, pose: Pose, params: MatcherParams) -> Match:
    """Gauss-Newton point-to-line alignment of `points` (robot frame) starting at `pose`."""
    pts = points[:: params.beam_stride]
    x = np.array(pose, dtype=float)
    converged = False
    used = 0
    info = np.zeros((2, 2))  # the last step's per-point x-y information
    for it in range(params.iterations):
        # 1. outlier distance shrinks linearly over the first half of the iterations
        f = min(1.0, it / max(1, params.iterations // 2))
        outlier = params.outlier_distance + f * (params.final_outlier_distance - params.outlier_distance)

        # 2. points into the map, each with its nearest segment and signed line distance
        c, s = math.cos(x[2]), math.sin(x[2])
        q = pts @ np.array([[c, s], [-s, c]]) + x[:2]
        k = field.nearest_segment(q)
        ok = k >= 0
        n = field.normals[k[ok]]
        a = field.segments[k[ok], 0:2]
        r = ((q[ok] - a) * n).sum(axis=1)
        keep = np.abs(r) <= outlier
        # a point beyond the segment's ends is not on that line: use the true distance
        keep[keep] &= field.distance(q[ok][keep]) <= outlier
        used = int(keep.sum())
        if used < 3:
            break
        r, n, qk = r[keep], n[keep], q[ok][keep]

        # 3. Huber weights and the normal equations
        w = np.where(np.abs(r) <= params.huber, 1.0, params.huber / np.maximum(np.abs(r), 1e-12))
        rel = qk - x[:2]
        j = np.column_stack([n[:, 0], n[:, 1], n[:, 0] * -rel[:, 1] + n[:, 1] * rel[:, 0]])
        h = (j * w[:, None]).T @ j
        g = (j * w[:, None]).T @ r
        info = h[:2, :2] / w.sum()
        try:
            dx = -np.linalg.solve(h + 1e-9 * np.eye(3), g)
        except np.linalg.LinAlgError:
            break
        x += dx
        x[2] = math.remainder(x[2], 2 * math.pi)
        if it >= params.iterations // 2 and abs(dx[0]) + abs(dx[1]) < 1e-4 and abs(dx[2]) < 1e-4:
            converged = True
            break
    result: Pose = (float(x[0]), float(x[1]), float(x[2]))
    # how well the points pin down x and y: ~0 in a featureless corridor
    constraint = float(np.linalg.eigvalsh(info)[0])
    return Match(result, quality(field, points, result, params.inlier_distance), used, converged,
                 constraint)


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
        m = refine(field, points, pose, matcher)
        m = replace(m, through=beams_through_walls(field, points, m.pose, matcher))
        # explained beams count for, beams through walls against a candidate
        if best is None or m.quality - m.through > best.quality - (best.through or 0.0):
            best = m
    return best


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

    scores = np.empty((len(hs), ny, nx), dtype=np.float32)
    for h, dh in enumerate(hs):
        a = heading + dh
        c, s = math.cos(a), math.sin(a)
        offsets = np.rint(pts @ np.array([[c, s], [-s, c]]) / step).astype(np.int64)
        acc = np.zeros((ny, nx), dtype=np.float32)
        for dj, di in offsets:
            r, q = pad + i0 + di, pad + j0 + dj
            acc += grid[r : r + ny, q : q + nx]
        scores[h] = acc

    # best first; skip candidates close to one already taken (non-maximum suppression)
    order = np.argsort(scores, axis=None)
    taken: list[Pose] = []
    for flat in order[: 50 * params.candidates]:
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
