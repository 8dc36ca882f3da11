"""Scan (seed 001): polar to Cartesian, range filtering, resampling, breaking into clusters.

1. Beam i points at `angle_min + i * angle_increment` (any layout: PICO sim, Hokuyo, CARMEN).
   When the fields disagree with the number of ranges, the increment wins if it is usable,
   else the beams are spread evenly over [angle_min, angle_max]; either way with a warning.
2. A range is valid when finite and within [max(range_min, min_range), min(range_max,
   max_range)], and its point lies outside the robot's footprint. 0, NaN and inf are dropped.
3. Resampling keeps a point when the arc length along the scan since the last kept point
   reaches `min_spacing` (vectorised: the first point of every `min_spacing` bin of the
   cumulative arc length), and always the first and last point of a cluster.
4. Consecutive valid points farther apart than `break_distance + break_slope * range` start
   a new cluster: walls never span a range jump.

Each cluster end also records whether the wall's end was *seen*: the neighbouring beam
beyond it returned nothing or hit something farther away (the laser looked past the end,
as the spike method assumes). An end next to a nearer point (occluded) or at the edge of the
field of view is not seen: a floating end.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pico_studio.core.config.perception_params import ProximityParams, ScanParams
from pico_studio.core.io import LaserData
from pico_studio.core.perception.proximity import in_footprint


@dataclass(frozen=True)
class ScanPoints:
    ranges: np.ndarray  # (n,) raw ranges
    angles: np.ndarray  # (n,) beam angles
    valid: np.ndarray  # (n,) bool
    points: np.ndarray  # (M, 2) resampled valid points, scan order, robot frame
    beam: np.ndarray  # (M,) beam index of each point
    clusters: np.ndarray  # (K, 2) int [start, end) into points
    end_seen: np.ndarray  # (K, 2) bool: the cluster's first / last end was seen as a true end

    @property
    def all_points(self) -> np.ndarray:
        """Every valid beam's point (before resampling), robot frame."""
        r = self.ranges[self.valid]
        a = self.angles[self.valid]
        return np.column_stack([r * np.cos(a), r * np.sin(a)])


def beam_angles(laser: LaserData) -> tuple[np.ndarray, list[str]]:
    """(n,) angle per beam and warnings about inconsistent angle fields."""
    n = len(laser.ranges)
    lo, hi, inc = float(laser.angle_min), float(laser.angle_max), float(laser.angle_increment)
    if n == 0:
        return np.zeros(0), []
    usable_inc = math.isfinite(inc) and inc != 0.0 and abs(inc) * (n - 1) < 2 * math.pi + 1e-6
    if math.isfinite(lo) and usable_inc:
        angles = lo + np.arange(n) * inc
        if math.isfinite(hi) and n > 1 and abs(angles[-1] - hi) > max(abs(inc), 1e-6):
            return angles, [
                f"laser angle fields disagree: {n} beams from {lo:.4g} by {inc:.4g} end at "
                f"{angles[-1]:.4g}, not angle_max {hi:.4g}; used angle_min + i * angle_increment"
            ]
        return angles, []
    if math.isfinite(lo) and math.isfinite(hi) and n > 1 and hi > lo:
        return np.linspace(lo, hi, n), [
            f"laser angle_increment {inc!r} is unusable; beams spread over angle_min..angle_max"
        ]
    return np.zeros(0), [f"laser angle fields unusable (min {lo!r}, max {hi!r}, increment {inc!r})"]


def process_scan(
    laser: LaserData, params: ScanParams, footprint: ProximityParams
) -> tuple[ScanPoints, list[str]]:
    ranges = np.asarray(laser.ranges, dtype=float).reshape(-1)
    angles, warnings = beam_angles(laser)
    if len(angles) != len(ranges):  # unusable angles: no beam can be placed
        angles = np.zeros(len(ranges))
        valid = np.zeros(len(ranges), dtype=bool)
    else:
        lo = max(_finite_or(laser.range_min, 0.0), params.min_range)
        hi = min(_finite_or(laser.range_max, math.inf), params.max_range)
        with np.errstate(invalid="ignore"):
            valid = np.isfinite(ranges) & (ranges >= lo) & (ranges <= hi)
        if valid.any():
            xy = np.column_stack([ranges * np.cos(angles), ranges * np.sin(angles)])
            valid &= ~in_footprint(np.nan_to_num(xy), footprint)
    if len(ranges) and not valid.any():
        warnings.append(f"no valid range among {len(ranges)} beams")
    elif not len(ranges):
        warnings.append("empty scan")
    return _cluster(ranges, angles, valid, params), warnings


def _finite_or(v: float, default: float) -> float:
    v = float(v)
    return v if math.isfinite(v) else default


def _cluster(ranges: np.ndarray, angles: np.ndarray, valid: np.ndarray, p: ScanParams) -> ScanPoints:
    idx = np.flatnonzero(valid)
    if len(idx) == 0:
        z2 = np.zeros((0, 2))
        return ScanPoints(ranges, angles, valid, z2, np.zeros(0, dtype=np.int64),
                          np.zeros((0, 2), dtype=np.int64), np.zeros((0, 2), dtype=bool))
    r = ranges[idx]
    a = angles[idx]
    xy = np.column_stack([r * np.cos(a), r * np.sin(a)])
    step = np.hypot(np.diff(xy[:, 0]), np.diff(xy[:, 1]))
    brk = step > p.break_distance + p.break_slope * np.minimum(r[:-1], r[1:])
    first = np.concatenate([[True], brk])  # first point of each cluster
    last = np.concatenate([brk, [True]])
    # arc length restarted at every cluster, binned by the minimum spacing
    arc = np.concatenate([[0.0], np.cumsum(np.where(brk, 0.0, step))])
    if p.min_spacing > 0:
        bins = np.floor(arc / p.min_spacing)
        keep = first | last | np.concatenate([[True], np.diff(bins) > 0])
    else:
        keep = np.ones(len(idx), dtype=bool)
    cluster_id = np.cumsum(first) - 1
    kept = np.flatnonzero(keep)
    points = xy[kept]
    beam = idx[kept]
    kid = cluster_id[kept]
    starts = np.flatnonzero(np.concatenate([[True], np.diff(kid) > 0]))
    ends = np.concatenate([starts[1:], [len(kept)]])
    clusters = np.column_stack([starts, ends])
    end_seen = _ends_seen(ranges, valid, beam[starts], beam[ends - 1], p)
    return ScanPoints(ranges, angles, valid, points, beam, clusters, end_seen)


def _ends_seen(
    ranges: np.ndarray, valid: np.ndarray, first_beam: np.ndarray, last_beam: np.ndarray, p: ScanParams
) -> np.ndarray:
    """Per cluster (first end, last end): did the laser look past that end?

    The neighbouring beam outside the cluster is either invalid but not at the edge of the
    field of view (nothing there within range: seen), or valid and farther by more than the
    break distance (seen), or nearer (occluded: not seen)."""
    n = len(ranges)
    out = np.zeros((len(first_beam), 2), dtype=bool)
    for col, beams, d in ((0, first_beam, -1), (1, last_beam, 1)):
        nb = beams + d
        inside = (nb >= 0) & (nb < n)
        nbc = np.clip(nb, 0, n - 1)
        nr = np.where(valid[nbc], ranges[nbc], np.inf)
        own = ranges[beams]
        farther = nr > own + p.break_distance + p.break_slope * own
        # an invalid neighbour counts as far only when the laser itself returned nothing
        # there (a dropped footprint point or a too-short return is not "far")
        raw = ranges[nbc]
        far_invalid = ~valid[nbc] & ~(np.isfinite(raw) & (raw > 0) & (raw < own))
        out[:, col] = inside & np.where(valid[nbc], farther, far_invalid)
    return out
