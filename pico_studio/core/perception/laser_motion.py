"""Motion from the laser (seed 002): the robot's motion between two scans from matched corners.

Corners of the previous scan (robot frame then) and of this one (robot frame now) are matched
to their nearest neighbour within `match_radius`, after moving this scan's corners by the
predicted motion (odometry, or none). The motion (x, y, a) — this pose in the previous
robot frame, p_prev = R(a) p_now + (x, y) — is the least-squares rigid fit over all matches
(seed 002: "uses as many points as possible and the average translation"):

    a = atan2(sum cross(q_i - q̄, p_i - p̄), sum dot(q_i - q̄, p_i - p̄)),  t = p̄ - R(a) q̄

with p the previous and q the current corners; one match gives the translation only.
Matching and fitting are repeated `iterations` times.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config.perception_params import LaserMotionParams

Pose = tuple[float, float, float]


def laser_motion(
    previous: np.ndarray, current: np.ndarray, predicted: Pose | None, params: LaserMotionParams
) -> tuple[Pose | None, int]:
    """The estimated motion and the number of matched corners (None when nothing matched)."""
    if len(previous) == 0 or len(current) == 0:
        return None, 0
    motion = predicted if predicted is not None else (0.0, 0.0, 0.0)
    count = 0
    rows = np.arange(len(current))
    matched: tuple[np.ndarray, np.ndarray] | None = None
    for _ in range(params.iterations):
        q = _apply(current, motion)
        d = np.hypot(*(q[:, None, :] - previous[None, :, :]).transpose(2, 0, 1))
        nearest = np.argmin(d, axis=1)
        ok = d[rows, nearest] < params.match_radius
        # one previous corner takes at most one current corner: the nearest
        back = np.argmin(d, axis=0)
        ok &= back[nearest] == rows
        count = int(ok.sum())
        if count == 0:
            return None, 0
        pairs = (ok, nearest[ok])
        if matched is not None and np.array_equal(matched[0], pairs[0]) and np.array_equal(matched[1], pairs[1]):
            break  # the same matches give the same fit: a fixed point, later rounds repeat it
        matched = pairs
        motion = fit_rigid(previous[pairs[1]], current[ok], motion[2])
    return motion, count


def fit_rigid(p: np.ndarray, q: np.ndarray, angle_guess: float = 0.0) -> Pose:
    """(x, y, a) with p ≈ R(a) q + (x, y), least squares; one pair keeps `angle_guess`."""
    n = len(p)
    pm = p.sum(axis=0) / n
    qm = q.sum(axis=0) / n
    if n >= 2:
        pc, qc = p - pm, q - qm
        a = math.atan2(float((qc[:, 0] * pc[:, 1] - qc[:, 1] * pc[:, 0]).sum()), float((qc * pc).sum()))
    else:
        a = angle_guess
    c, s = math.cos(a), math.sin(a)
    qx, qy = float(qm[0]), float(qm[1])
    return float(pm[0]) - (c * qx - s * qy), float(pm[1]) - (s * qx + c * qy), a


def _apply(points: np.ndarray, motion: Pose) -> np.ndarray:
    c, s = math.cos(motion[2]), math.sin(motion[2])
    return points @ np.array([[c, s], [-s, c]]) + np.array(motion[:2])
