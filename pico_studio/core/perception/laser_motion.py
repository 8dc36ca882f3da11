"""Motion from the laser (seed 002): the robot's motion between two scans from matched corners.

Corners of the previous scan (robot frame then) and of this one (robot frame now) are matched
to their nearest neighbour within `match_radius`, after moving this scan's corners by the
predicted motion (odometry, or none). The motion (x, y, a) — this pose in the previous
robot frame, p_prev = R(a) p_now + (x, y) — is the least-squares rigid fit over all matches
(seed 002: "uses as many points as possible and the average translation"):

    a = atan2(sum cross(q_i - q̄, p_i - p̄), sum dot(q_i - q̄, p_i - p̄)),  t = p̄ - R(a) q̄

with p the previous and q the current corners; one match gives the translation only.
Matching and fitting are repeated `iterations` times (one compiled loop, `_match_and_fit`),
stopping early when the matches repeat: the same matches give the same fit.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config.perception_params import LaserMotionParams
from pico_studio.jit import kernel

Pose = tuple[float, float, float]


def _example() -> tuple:
    prev = np.array([[1.0, 0.0], [0.0, 1.0], [2.0, 2.0]])
    return prev, prev + 0.01, 0.0, 0.0, 0.0, 0.3, 3


@kernel(_example)
def _match_and_fit(previous: np.ndarray, current: np.ndarray, x: float, y: float, a: float,
                   radius: float, iterations: int) -> tuple[float, float, float, int]:
    """(x, y, a, matches) from the predicted motion (x, y, a); matches -1: nothing matched."""
    n_c, n_p = current.shape[0], previous.shape[0]
    d = np.empty((n_c, n_p))
    nearest = np.empty(n_c, dtype=np.int64)
    ok = np.zeros(n_c, dtype=np.bool_)
    was_ok = np.zeros(n_c, dtype=np.bool_)
    was_nearest = np.full(n_c, -1, dtype=np.int64)
    count = 0
    for it in range(iterations):
        # this scan's corners moved by the motion: q = R(a) p + (x, y)
        c, s = math.cos(a), math.sin(a)
        for i in range(n_c):
            qx = current[i, 0] * c - current[i, 1] * s + x
            qy = current[i, 0] * s + current[i, 1] * c + y
            for j in range(n_p):
                d[i, j] = math.hypot(qx - previous[j, 0], qy - previous[j, 1])
        # nearest neighbours both ways: one previous corner takes at most one current corner
        count = 0
        for i in range(n_c):
            nearest[i] = np.argmin(d[i])
        for i in range(n_c):
            j = nearest[i]
            ok[i] = d[i, j] < radius and np.argmin(d[:, j]) == i
            count += ok[i]
        if count == 0:
            return x, y, a, -1
        same = it > 0
        for i in range(n_c):
            if ok[i] != was_ok[i] or (ok[i] and nearest[i] != was_nearest[i]):
                same = False
            was_ok[i] = ok[i]
            was_nearest[i] = nearest[i]
        if same:
            break  # the same matches give the same fit: a fixed point, later rounds repeat it
        # least-squares rigid fit p ~ R(a) q + t over the matches (p previous, q current)
        pmx = pmy = qmx = qmy = 0.0
        for i in range(n_c):
            if ok[i]:
                pmx += previous[nearest[i], 0]
                pmy += previous[nearest[i], 1]
                qmx += current[i, 0]
                qmy += current[i, 1]
        pmx, pmy, qmx, qmy = pmx / count, pmy / count, qmx / count, qmy / count
        if count >= 2:
            cross = dot = 0.0
            for i in range(n_c):
                if ok[i]:
                    pcx, pcy = previous[nearest[i], 0] - pmx, previous[nearest[i], 1] - pmy
                    qcx, qcy = current[i, 0] - qmx, current[i, 1] - qmy
                    cross += qcx * pcy - qcy * pcx
                    dot += qcx * pcx + qcy * pcy
            a = math.atan2(cross, dot)  # one pair keeps the angle it had
        c, s = math.cos(a), math.sin(a)
        x, y = pmx - (c * qmx - s * qmy), pmy - (s * qmx + c * qmy)
    return x, y, a, count


def laser_motion(
    previous: np.ndarray, current: np.ndarray, predicted: Pose | None, params: LaserMotionParams
) -> tuple[Pose | None, int]:
    """The estimated motion and the number of matched corners (None when nothing matched)."""
    if len(previous) == 0 or len(current) == 0:
        return None, 0
    x, y, a = predicted if predicted is not None else (0.0, 0.0, 0.0)
    x, y, a, count = _match_and_fit(np.ascontiguousarray(previous, dtype=np.float64),
                                    np.ascontiguousarray(current, dtype=np.float64), float(x), float(y), float(a),
                                    float(params.match_radius), int(params.iterations))
    return (None, 0) if count < 0 else ((x, y, a), count)


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
