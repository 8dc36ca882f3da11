"""Small 2D geometry shared by every stage: angles, poses, rigid transforms, segments.

Conventions (REP 103): x forward, y left, angles counter-clockwise in radians wrapped to
(-pi, pi]. Segments are rows `(x1, y1, x2, y2)` of an (N, 4) array. Poses are plain float
tuples `(x, y, a)`; the pose functions use `math` only, because the simulator and the
trackers call them once per step and numpy's per-call overhead would dominate (see
benchmarks/bench_geometry.py).
"""

from __future__ import annotations

import math
from typing import overload

import numpy as np

from pico_studio.jit import kernel

Pose = tuple[float, float, float]
_TWO_PI = 2.0 * math.pi


@overload
def wrap_angle(a: float) -> float: ...


@overload
def wrap_angle(a: np.ndarray) -> np.ndarray: ...


def wrap_angle(a: float | np.ndarray) -> float | np.ndarray:
    """Wrap to (-pi, pi]: a float for a float, an array for an array."""
    if isinstance(a, float | int):
        # IEEE remainder is already in [-pi, pi]; only -pi itself moves to the other end
        w = math.remainder(a, _TWO_PI)
        return math.pi if w == -math.pi else w
    arr = np.mod(np.asarray(a, dtype=float) + math.pi, _TWO_PI) - math.pi
    arr = np.where(arr == -math.pi, math.pi, arr)
    return float(arr) if np.ndim(arr) == 0 else arr


def compose(p: Pose, q: Pose) -> Pose:
    """Pose p (x) q: q expressed in p's frame, returned in p's parent frame."""
    c, s = math.cos(p[2]), math.sin(p[2])
    a = math.remainder(p[2] + q[2], _TWO_PI)
    return (p[0] + c * q[0] - s * q[1], p[1] + s * q[0] + c * q[1], math.pi if a == -math.pi else a)


def invert(p: Pose) -> Pose:
    """The pose of p's parent frame seen from p: compose(p, invert(p)) is the identity."""
    c, s = math.cos(p[2]), math.sin(p[2])
    a = math.remainder(-p[2], _TWO_PI)
    return (-c * p[0] - s * p[1], s * p[0] - c * p[1], math.pi if a == -math.pi else a)


def relative(p: Pose, q: Pose) -> Pose:
    """q expressed in p's frame: invert(p) (x) q, i.e. R(-p_a) (q_xy - p_xy), q_a - p_a."""
    c, s = math.cos(p[2]), math.sin(p[2])
    dx, dy = q[0] - p[0], q[1] - p[1]
    a = math.remainder(q[2] - p[2], _TWO_PI)
    return (c * dx + s * dy, -s * dx + c * dy, math.pi if a == -math.pi else a)


def transform_points(points: np.ndarray, pose: Pose) -> np.ndarray:
    """Points (N, 2) (any (..., 2)) from the frame of `pose` into its parent frame (rotate,
    then translate): one compiled loop, `_rigid` — a few dozen points per call, several calls
    a frame, where a matmul's set-up costs more than the arithmetic."""
    pts = np.ascontiguousarray(points, dtype=np.float64)
    out = _rigid(pts.reshape(-1, 2), float(pose[0]), float(pose[1]), math.cos(pose[2]), math.sin(pose[2]))
    return out.reshape(pts.shape)


def _rigid_example() -> tuple:
    return np.array([[1.0, 2.0], [3.0, 4.0]]), 0.5, -0.5, math.cos(0.3), math.sin(0.3)


@kernel(_rigid_example)
def _rigid(points: np.ndarray, x: float, y: float, c: float, s: float) -> np.ndarray:
    """(N, 2): p' = R p + t with R = [[c, -s], [s, c]], t = (x, y), point by point (each
    product rounded on its own: no fused multiply-add, the same floats as the Python)."""
    out = np.empty_like(points)
    for i in range(points.shape[0]):
        px, py = points[i, 0], points[i, 1]
        out[i, 0] = c * px - s * py + x
        out[i, 1] = s * px + c * py + y
    return out


def transform_segments(segments: np.ndarray, pose: Pose) -> np.ndarray:
    """Segments (N, 4) from the frame of `pose` into its parent frame."""
    if len(segments) == 0:
        return np.zeros((0, 4))
    pts = transform_points(segments.reshape(-1, 2), pose)
    return pts.reshape(-1, 4)


def segment_lengths(segments: np.ndarray) -> np.ndarray:
    return np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1])


def pairwise_distances(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Euclidean distance from every point of a (M, 2) to every point of b (N, 2): (M, N)."""
    a = np.asarray(a, dtype=float).reshape(-1, 2)
    b = np.asarray(b, dtype=float).reshape(-1, 2)
    return np.hypot(a[:, None, 0] - b[None, :, 0], a[:, None, 1] - b[None, :, 1])


def point_segment_distance(points: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """Distance from every point (P, 2) to every segment (N, 4): a (P, N) array.

    The closest point of segment a-b to p is a + t (b - a) with t the projection
    ((p - a) . (b - a)) / |b - a|^2 clipped to [0, 1] (a degenerate segment is its point a)."""
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    # per coordinate, (P, 1) against (N,): no trailing axis of 2 to reduce over, which keeps
    # the one-point case (the simulator's clearance check, every few steps) cheap
    px, py = points[:, 0:1], points[:, 1:2]
    ax, ay = segments[:, 0], segments[:, 1]
    dx, dy = segments[:, 2] - ax, segments[:, 3] - ay
    denom = np.maximum(dx * dx + dy * dy, 1e-18)
    t = np.minimum(np.maximum(((px - ax) * dx + (py - ay) * dy) / denom, 0.0), 1.0)
    ex, ey = px - ax - t * dx, py - ay - t * dy
    return np.sqrt(ex * ex + ey * ey)


def point_segment_distance_paired(points: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """Distance from point k (K, 2) to segment k (K, 4), row by row: a (K,) array."""
    a = segments[:, 0:2]
    ab = segments[:, 2:4] - a
    ap = np.asarray(points, dtype=float).reshape(-1, 2) - a
    t = np.clip((ap * ab).sum(-1) / np.maximum((ab**2).sum(-1), 1e-18), 0.0, 1.0)
    d = ap - t[:, None] * ab
    return np.sqrt((d**2).sum(-1))


def _orient(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Twice the signed area of the triangle p q r (> 0 when r is left of p -> q)."""
    return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])


def segments_cross(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray,
                   *, end_on_line: bool = False) -> np.ndarray:
    """Does segment a-b cross segment c-d? Points (..., 2), broadcast; a bool array.

    They cross when c and d lie strictly on opposite sides of line a-b and a and b strictly on
    opposite sides of line c-d. With `end_on_line`, an end of a-b lying on c-d counts too
    (a move that ends on a wall has reached it)."""
    a, b, c, d = (np.asarray(v, dtype=float) for v in (a, b, c, d))
    cd_apart = _orient(a, b, c) * _orient(a, b, d) < 0
    ab_side = _orient(c, d, a) * _orient(c, d, b)
    return cd_apart & ((ab_side <= 0) if end_on_line else (ab_side < 0))


def _door_example() -> tuple:
    doors = np.array([[0.0, 0.0, 0.9, 0.0], [5.0, 5.0, 5.0, 6.0]])
    return doors, doors[:1] + 0.05, 0.3, math.cos(0.3)


@kernel(_door_example)
def door_matches(found: np.ndarray, truth: np.ndarray, distance: float, cos_angle: float) -> np.ndarray:
    """(F, T) bool: door f (F, 4) matches opening t (T, 4): their middles within `distance`
    and their directions within the angle, |u_f . u_t| >= cos_angle (u = (b - a) / |b - a|).
    The truth's scoring and the combined map's confirmation both ask this."""
    out = np.zeros((found.shape[0], truth.shape[0]), dtype=np.bool_)
    for f in range(found.shape[0]):
        fx, fy = (found[f, 0] + found[f, 2]) / 2, (found[f, 1] + found[f, 3]) / 2
        ux, uy = found[f, 2] - found[f, 0], found[f, 3] - found[f, 1]
        norm = max(np.hypot(ux, uy), 1e-12)
        ux, uy = ux / norm, uy / norm
        for t in range(truth.shape[0]):
            mx, my = (truth[t, 0] + truth[t, 2]) / 2, (truth[t, 1] + truth[t, 3]) / 2
            if np.hypot(fx - mx, fy - my) > distance:
                continue
            vx, vy = truth[t, 2] - truth[t, 0], truth[t, 3] - truth[t, 1]
            norm_t = max(np.hypot(vx, vy), 1e-12)
            out[f, t] = abs(ux * (vx / norm_t) + uy * (vy / norm_t)) >= cos_angle
    return out
