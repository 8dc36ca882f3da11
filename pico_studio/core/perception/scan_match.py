"""Pose correction before merging: point-to-line ICP of the scan against the local map's walls.

Odometry drifts (and on real logs at a few seconds per scan it drifts a lot between scans);
a local map merged at a wrong pose grows ghost walls. So before the merge the scan is aligned
to the local map's walls, starting at the odometry pose x0 (as PL-ICP, Censi 2008, with the
odometry as a prior and the degenerate directions held to it). One compiled loop,
`scan_match_kernels.fit_pose`; the maths:

Association. A point p (robot frame) lands at q = R(a) p + t in the zero frame. Its wall is
the nearest local wall k whose foot lies inside it (a wall's end is where the map stops
knowing, not a point to slide towards), within the gate, and whose direction agrees with the
scan's own direction at p (its neighbours within `neighbour_distance`) to `normal_angle`: a
point on one wall is never pulled onto the crossing wall at a corner. The residual is the
signed distance to the wall's line,

    r = n_k . (q - s_k),      dr/d(x, y, a) = [n_x, n_y, n_k . perp(q - t)].

Robust weights. Tukey's biweight w = (1 - (r/c)^2)^2 / sigma_p^2 (c: the gate, shrinking
0.6x per iteration to 2 x `inlier_distance`; sigma_p `point_sigma`): a point that fits no
wall (a person, a ghost) weighs nothing.

Odometry-whitened Gauss-Newton. With the odometry's noise over the step S = diag(s_xy,
s_xy, s_a) — s_xy = `odometry_sigma` + `odometry_sigma_per_m` x distance moved, s_a =
`odometry_sigma_angle` + `odometry_sigma_per_rad` x |turn| + `odometry_sigma_angle_per_m` x
distance — and z = S^-1 (x - x0), the cost is sum w r^2 + |z|^2 (the walls and the odometry
prior). Its information in whitened units is H' = S (J^T W J) S (g' = S J^T W r): an
eigenvalue says how many times better than odometry the walls know a direction. Which
directions the walls pin down: the heading when H'_aa >= `min_information`; the position
by the eigenvalues l1 >= l2 (eigenvectors u1, u2) of its information once the heading is
solved with it, the Schur complement T = H'_tt - H'_ta H'_aa^-1 H'_at: u1 when l1 >=
`min_information`, u2 when also l2 >= `min_information` and l2 >= `min_conditioning` x l1.
With B the free directions (columns) and w = B^T z, each iteration takes the MAP step

    (B^T H' B + I) dw = -(B^T g' + w),   z <- B (w + dw),   x = x0 + S z

so the held directions stay exactly odometry's: along a corridor (l2 a sliver of l1) a door
jamb's few points or a stray association cannot slide the pose.

Two starts. The refinement runs from the odometry pose; when that explains less than
`good_quality` of the scan (odometry's heading may have failed: real odometry's errors are
heavy-tailed) it runs again from the heading within `search_angle` of the odometry's under
which most points lie within half the gate (ties: the nearer), so a heading off by more than
the gate allows still converges; the result explaining more of the scan wins (a tie: the
odometry start's).

Quality (`wm.pose_correction_quality`) = the share of the (subsampled) scan's points within
`inlier_distance` of a local wall at the pose returned; 0 when nothing could be matched (an
empty or NaN scan, no local map). The correction is accepted only when
- enough points matched (`min_matches`) and its quality reaches `min_quality` and that of
  the odometry pose plus `min_gain`;
- it is significant: the objective (the walls' robust cost, Tukey's rho over sigma_p^2 with
  an unmatched point at rho's ceiling, plus |z|^2) drops by at least `min_evidence` from the
  odometry pose to the fit, a likelihood-ratio test. A correction within the matching noise
  is not applied: applied every scan, such corrections random-walk the pose and the local
  map merged from it together (seen on the PICO bag and on simulated runs at 20 Hz);
- it is plausible against odometry: within `max_sigmas` of the odometry's noise (the
  Mahalanobis length |z|) and `max_correction` / `max_correction_angle`.
Otherwise the pose stays the odometry's.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from pico_studio.config.perception_params import ScanMatchParams
from pico_studio.core.geometry import wrap_angle
from pico_studio.core.perception import scan_match_kernels as kn

Pose = tuple[float, float, float]


@dataclass(frozen=True)
class ScanMatch:
    pose: Pose  # the corrected pose (the odometry pose when not accepted)
    quality: float  # share of the scan's points within inlier_distance of a wall at `pose`
    matches: int  # points matched at the fitted pose
    accepted: bool
    observable: int = 0  # directions (of x, y, heading) the walls pinned down; the rest held to odometry
    conditioning: float = 0.0  # the position's weaker / stronger information eigenvalue (0: a corridor)


def odometry_sigma(step: Pose | None, params: ScanMatchParams) -> tuple[float, float]:
    """(position, heading) noise of the odometry over `step` (None: unknown, the largest allowed)."""
    if step is None:
        return params.max_correction, params.max_correction_angle
    moved = math.hypot(step[0], step[1])
    sig_xy = params.odometry_sigma + params.odometry_sigma_per_m * moved
    sig_a = (params.odometry_sigma_angle + params.odometry_sigma_per_rad * abs(step[2])
             + params.odometry_sigma_angle_per_m * moved)
    return sig_xy, sig_a


def match_scan(points: np.ndarray, walls: np.ndarray, pose: Pose, step: Pose | None,
               params: ScanMatchParams) -> ScanMatch:
    """Align `points` (M, 2) robot frame, scan order, to `walls` (W, 4) zero frame, starting
    at `pose`; `step` is the odometry's motion since the previous scan (None: unknown)."""
    none = ScanMatch(pose, 0.0, 0, False)
    pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
    walls = np.ascontiguousarray(walls, dtype=np.float64).reshape(-1, 4)
    if len(pts) < params.min_matches or len(walls) == 0 or not all(math.isfinite(v) for v in pose):
        return none
    sig_xy, sig_a = odometry_sigma(step, params)
    x0 = np.array(pose, dtype=np.float64)
    x, info = kn.fit_pose(pts, walls, x0, np.array([sig_xy, sig_xy, sig_a]), _settings(params))
    quality, matched, quality0 = float(info[0]), int(info[1]), float(info[2])
    observable, conditioning, evidence = int(info[3]), float(info[4]), float(info[5])
    dx, dy, da = x[0] - x0[0], x[1] - x0[1], float(wrap_angle(x[2] - x0[2]))
    mahalanobis = math.sqrt((dx * dx + dy * dy) / sig_xy**2 + da * da / sig_a**2)
    corrected = (float(x[0]), float(x[1]), float(wrap_angle(x[2])))
    accepted = (matched >= params.min_matches and quality >= params.min_quality and evidence >= params.min_evidence
                and quality >= quality0 + params.min_gain and mahalanobis <= params.max_sigmas
                and math.hypot(dx, dy) <= params.max_correction and abs(da) <= params.max_correction_angle)
    if not accepted:
        return ScanMatch(pose, quality0, matched, False, observable, conditioning)
    return ScanMatch(corrected, quality, matched, True, observable, conditioning)


@functools.lru_cache(maxsize=16)
def _settings(params: ScanMatchParams) -> np.ndarray:
    """The kernel's scalar settings, in scan_match_kernels' S_* order (one array per params;
    the kernel only reads it)."""
    s = np.zeros(kn.N_SETTINGS)
    s[kn.S_MAX_POINTS] = params.max_points
    s[kn.S_NEIGHBOUR] = params.neighbour_distance
    s[kn.S_GATE] = params.gate
    s[kn.S_INLIER] = params.inlier_distance
    s[kn.S_SIGMA] = params.point_sigma
    s[kn.S_GOOD] = params.good_quality
    s[kn.S_INFORMATION] = params.min_information
    s[kn.S_SEARCH_ANGLE] = params.search_angle
    s[kn.S_SEARCH_STEP] = params.search_step
    s[kn.S_NORMAL_ANGLE] = params.normal_angle
    s[kn.S_ITERATIONS] = params.iterations
    s[kn.S_CONDITIONING] = params.min_conditioning
    s[kn.S_SEARCH_POINTS] = params.search_points
    return s
