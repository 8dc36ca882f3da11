"""Pose correction before merging: match the scan to the local map, point to line.

Odometry drifts (and on real logs at a few seconds per scan it drifts a lot between scans);
a local map merged at a wrong pose grows ghost walls. So before the merge the scan's points
are aligned to the local map's walls by Gauss-Newton, starting at the odometry pose x0.

A point p (robot frame) lands at q = R(a) p + t in the zero frame. Its nearest local wall k
(point-to-segment distance, within the gate) has unit normal n_k and a point s_k; the
residual is the signed distance to the wall's line:

    r = n_k . (q - s_k),      dr/d(x, y, a) = [n_x, n_y, n_k . perp(q - t)]

Each iteration re-associates, shrinks the gate towards `inlier_distance`, weighs points by
the Huber loss over the point noise sigma_p^2 (`point_sigma`) and solves

    (J^T W J + P) d = -(J^T W r + P (x - x0)),   P = diag(1/s_xy^2, 1/s_xy^2, 1/s_a^2)

with the odometry's noise over the step s_xy = `odometry_sigma` + `odometry_sigma_per_m` x
distance moved (likewise s_a for the heading): good odometry over a short step is hardly
moved, a long step of a slow log is left to the walls, and what the walls do not pin down
(along a corridor) stays where odometry put it. A pose already explaining `good_quality` of the scan is kept without matching. The start heading is the best of a few
within `search_angle` (the most points within half the gate), so a heading off by more
than the gate allows still converges.
Only points whose nearest point lies inside the wall (not beyond its end) are used: a
wall's end is where the map stops knowing, not a point to slide towards.

Quality = the share of the (subsampled) scan's points within `inlier_distance` of a local
wall after the correction. The
correction is kept when enough points matched (`min_matches`), the quality reaches
`min_quality`, it explains at least `min_gain` more of the scan than the odometry pose (so
good odometry is left alone: matching noise would otherwise random-walk the pose) and it
stays within `max_correction` / `max_correction_angle`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pico_studio.config.perception_params import ScanMatchParams
from pico_studio.core.geometry import transform_points, wrap_angle
from pico_studio.core.perception.scan_match_kernels import associate

Pose = tuple[float, float, float]


@dataclass(frozen=True)
class ScanMatch:
    pose: Pose  # the corrected pose (the odometry pose when not accepted)
    quality: float  # share of the scan's points within inlier_distance of a wall after it
    matches: int  # points matched in the last iteration
    accepted: bool


def match_scan(points: np.ndarray, walls: np.ndarray, pose: Pose, step: Pose | None,
               params: ScanMatchParams) -> ScanMatch:
    """Align `points` (M, 2) robot frame to `walls` (W, 4) zero frame, starting at `pose`;
    `step` is the odometry's motion since the previous scan (None: unknown)."""
    none = ScanMatch(pose, 0.0, 0, False)
    if len(points) < params.min_matches or len(walls) == 0:
        return none
    stride = max(1, int(math.ceil(len(points) / params.max_points)))
    pts = np.asarray(points, dtype=float)[::stride]
    # only walls that can be near a point: within the scan's reach (plus the gate) of the pose
    reach = float(np.hypot(pts[:, 0], pts[:, 1]).max()) + params.gate + params.max_correction
    lo = np.minimum(walls[:, 0:2], walls[:, 2:4])
    hi = np.maximum(walls[:, 0:2], walls[:, 2:4])
    near = ((lo[:, 0] <= pose[0] + reach) & (hi[:, 0] >= pose[0] - reach)
            & (lo[:, 1] <= pose[1] + reach) & (hi[:, 1] >= pose[1] - reach))
    walls = walls[near]
    if len(walls) == 0:
        return none
    a = walls[:, 0:2]
    ab = walls[:, 2:4] - a
    length = np.maximum(np.hypot(ab[:, 0], ab[:, 1]), 1e-12)
    normal = np.column_stack([-ab[:, 1], ab[:, 0]]) / length[:, None]
    # odometry's information: its noise grows with the step (unknown step: the largest allowed)
    if step is None:
        sig_xy, sig_a = params.max_correction, params.max_correction_angle
    else:
        moved = math.hypot(step[0], step[1])
        sig_xy = params.odometry_sigma + params.odometry_sigma_per_m * moved
        sig_a = params.odometry_sigma_angle + params.odometry_sigma_per_rad * abs(step[2])
    prior_info = np.diag([1 / sig_xy**2, 1 / sig_xy**2, 1 / sig_a**2])
    x0 = np.array(pose, dtype=float)
    _, quality0 = _explained(pts, x0, a, ab, normal, length, params)
    if quality0 >= params.good_quality:  # odometry is good here: nothing to correct
        return ScanMatch(pose, quality0, 0, False)
    x = x0.copy()
    x[2] = _best_heading(pts, a, ab, normal, length, x0, params)
    for it in range(params.iterations):
        gate = max(params.gate * 0.6**it, 2 * params.inlier_distance)
        q = transform_points(pts, (x[0], x[1], x[2]))
        k, r, ok = _associate(q, a, ab, normal, length, gate)
        if int(ok.sum()) < params.min_matches:
            return none
        n = normal[k[ok]]
        rr = r[ok]
        rel = q[ok] - x[:2]
        jac = np.column_stack([n[:, 0], n[:, 1], n[:, 0] * -rel[:, 1] + n[:, 1] * rel[:, 0]])
        huber = params.inlier_distance
        wgt = np.where(np.abs(rr) <= huber, 1.0, huber / np.maximum(np.abs(rr), 1e-12)) / params.point_sigma**2
        prior = x - x0
        prior[2] = wrap_angle(prior[2])
        hess = (jac * wgt[:, None]).T @ jac + prior_info
        grad = (jac * wgt[:, None]).T @ rr + prior_info @ prior
        try:
            d = -np.linalg.solve(hess, grad)
        except np.linalg.LinAlgError:
            return none
        x = x + d
        if abs(d[0]) + abs(d[1]) < 1e-4 and abs(d[2]) < 1e-4:
            break
    matched, quality = _explained(pts, x, a, ab, normal, length, params)
    moved = math.hypot(x[0] - x0[0], x[1] - x0[1])
    turned = abs(float(wrap_angle(x[2] - x0[2])))
    corrected = (float(x[0]), float(x[1]), float(wrap_angle(x[2])))
    accepted = (matched >= params.min_matches and quality >= params.min_quality
                and quality >= quality0 + params.min_gain
                and moved <= params.max_correction and turned <= params.max_correction_angle)
    return ScanMatch(corrected if accepted else pose, quality, matched, accepted)


def _explained(pts: np.ndarray, x: np.ndarray, a: np.ndarray, ab: np.ndarray, normal: np.ndarray,
               length: np.ndarray, params: ScanMatchParams) -> tuple[int, float]:
    """Points matched at pose x, and the share of all points within inlier_distance."""
    q = transform_points(pts, (x[0], x[1], x[2]))
    _, r, ok = _associate(q, a, ab, normal, length, 2 * params.inlier_distance)
    return int(ok.sum()), float((np.abs(r[ok]) <= params.inlier_distance).sum() / max(len(pts), 1))


def _best_heading(pts: np.ndarray, a: np.ndarray, ab: np.ndarray, normal: np.ndarray, length: np.ndarray,
                  x0: np.ndarray, params: ScanMatchParams) -> float:
    """The heading within `search_angle` of the odometry's under which most points lie
    within `gate` of a wall (ties: the one nearest the odometry's): a start the
    refinement can converge from when odometry turned wrong by more than the gate allows."""
    k = int(params.search_angle / params.search_step)
    if k == 0:
        return float(x0[2])
    offsets = np.arange(-k, k + 1) * params.search_step
    sub = pts[:: max(1, len(pts) // 60)]
    best, best_n = float(x0[2]), -1.0
    for off in offsets[np.argsort(np.abs(offsets), kind="stable")].tolist():
        q = transform_points(sub, (x0[0], x0[1], x0[2] + off))
        _, _, ok = _associate(q, a, ab, normal, length, params.gate / 2)
        if ok.sum() > best_n:
            best, best_n = float(x0[2] + off), float(ok.sum())
    return best


def _associate(q: np.ndarray, a: np.ndarray, ab: np.ndarray, normal: np.ndarray, length: np.ndarray,
               gate: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nearest wall of each point (index, signed distance to its line, usable): one compiled
    loop over points and walls (scan_match_kernels.associate)."""
    def c(v: np.ndarray) -> np.ndarray:
        return np.ascontiguousarray(v, dtype=np.float64)

    return associate(c(q), c(a), c(ab), c(normal), c(length), float(gate))
