"""Small 2D geometry shared by every stage: angles, poses, rigid transforms, segments.

Conventions (REP 103): x forward, y left, angles counter-clockwise in radians wrapped to
(-pi, pi]. Segments are rows `(x1, y1, x2, y2)` of an (N, 4) array.
"""

from __future__ import annotations

import math

import numpy as np


def wrap_angle(a: float | np.ndarray) -> float | np.ndarray:
    """Wrap to (-pi, pi]."""
    w = np.mod(np.asarray(a, dtype=float) + math.pi, 2 * math.pi) - math.pi
    w = np.where(w == -math.pi, math.pi, w)
    return float(w) if np.ndim(w) == 0 else w


def compose(p: tuple[float, float, float], q: tuple[float, float, float]) -> tuple[float, float, float]:
    """Pose p (x) q: q expressed in p's frame, returned in p's parent frame."""
    c, s = math.cos(p[2]), math.sin(p[2])
    return (p[0] + c * q[0] - s * q[1], p[1] + s * q[0] + c * q[1], float(wrap_angle(p[2] + q[2])))


def invert(p: tuple[float, float, float]) -> tuple[float, float, float]:
    c, s = math.cos(p[2]), math.sin(p[2])
    return (-c * p[0] - s * p[1], s * p[0] - c * p[1], float(wrap_angle(-p[2])))


def relative(p: tuple[float, float, float], q: tuple[float, float, float]) -> tuple[float, float, float]:
    """q expressed in p's frame: invert(p) (x) q."""
    return compose(invert(p), q)


def transform_points(points: np.ndarray, pose: tuple[float, float, float]) -> np.ndarray:
    """Points (N, 2) from the frame of `pose` into its parent frame (rotate, then translate)."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    r = np.array([[c, -s], [s, c]])
    return points @ r.T + np.array(pose[:2])


def transform_segments(segments: np.ndarray, pose: tuple[float, float, float]) -> np.ndarray:
    """Segments (N, 4) from the frame of `pose` into its parent frame."""
    if len(segments) == 0:
        return np.zeros((0, 4))
    pts = transform_points(segments.reshape(-1, 2), pose)
    return pts.reshape(-1, 4)


def segment_lengths(segments: np.ndarray) -> np.ndarray:
    return np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1])


def point_segment_distance(points: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """Distance from every point (P, 2) to every segment (N, 4): a (P, N) array."""
    a = segments[None, :, 0:2]
    b = segments[None, :, 2:4]
    p = points[:, None, :]
    ab = b - a
    denom = np.maximum((ab**2).sum(-1), 1e-18)
    t = np.clip(((p - a) * ab).sum(-1) / denom, 0.0, 1.0)
    closest = a + t[..., None] * ab
    return np.linalg.norm(p - closest, axis=-1)
