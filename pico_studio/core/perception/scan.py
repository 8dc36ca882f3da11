"""Scan (seed 001): polar to Cartesian, range filtering, resampling, breaking into clusters.

1. Beam i points at `angle_min + i * angle_increment` (any layout: PICO sim, Hokuyo, CARMEN).
   When the fields disagree with the number of ranges, the increment wins if it is usable,
   else the beams are spread evenly over [angle_min, angle_max]; either way with a warning.
2. A range is valid when finite and within [max(range_min, min_range), min(range_max,
   max_range)], and its point lies outside the robot's footprint. 0, NaN and inf are dropped.
3. Resampling keeps a point when the arc length along the scan since the last kept point
   reaches `min_spacing` (the first point of every `min_spacing` bin of the cumulative arc
   length), and always the first and last point of a cluster.
4. Consecutive valid points farther apart than `break_distance + break_slope * range` start
   a new cluster: walls never span a range jump. A surface seen at a grazing angle spreads its
   points (spacing r dtheta / sin b, b between beam and surface): there the allowed gap grows
   to `grazing_factor` times that, at most `grazing_max_break`.

Each cluster end also records whether the wall's end was *seen*: the neighbouring beam
beyond it returned nothing or hit something farther away (the laser looked past the end,
as the spike method assumes). An end next to a nearer point (occluded) or at the edge of the
field of view is not seen: a floating end; so is an end beside nothing returned where the
wall going on could have run out of the laser's reach (the end within the break's margin of
it, or the wall's line meeting that beam beyond it: a far wall seen to 10 m); so is an end
whose next point past the break lies
on the wall's extended line less than `grazing_max_break` away (the same wall going on,
seen at a grazing angle; a door in line is wider).

Steps 2-4 and the end checks are one compiled pass over the beams (`scan_kernels.scan_points`,
with the formulas); this module places the beams and wraps the result.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pico_studio.config.perception_params import ProximityParams, ScanParams
from pico_studio.core.io import LaserData
from pico_studio.core.perception.scan_kernels import scan_points


@dataclass(frozen=True)
class ScanPoints:
    ranges: np.ndarray  # (n,) raw ranges
    angles: np.ndarray  # (n,) beam angles
    valid: np.ndarray  # (n,) bool
    points: np.ndarray  # (M, 2) resampled valid points, scan order, robot frame
    beam: np.ndarray  # (M,) beam index of each point
    clusters: np.ndarray  # (K, 2) int [start, end) into points
    end_seen: np.ndarray  # (K, 2) bool: the cluster's first / last end was seen as a true end
    valid_xy: np.ndarray | None = None  # (V, 2) every valid beam's point, when already computed

    @property
    def all_points(self) -> np.ndarray:
        """Every valid beam's point (before resampling), robot frame."""
        if self.valid_xy is not None:
            return self.valid_xy
        r = self.ranges[self.valid]
        a = self.angles[self.valid]
        return np.column_stack([r * np.cos(a), r * np.sin(a)])


# beam layouts seen so far: (n, angle_min, angle_max, increment) -> (angles, cos, sin, warnings).
# A robot has one or two layouts; the cap only guards against a stream of odd ones.
_LAYOUTS: dict[tuple[int, float, float, float], tuple[np.ndarray, np.ndarray, np.ndarray, list[str]]] = {}
_MAX_LAYOUTS = 16


def _layout(laser: LaserData) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[str]]:
    """Angles, their cosines and sines (read-only, cached per beam layout) and warnings."""
    key = (len(laser.ranges), float(laser.angle_min), float(laser.angle_max), float(laser.angle_increment))
    hit = _LAYOUTS.get(key)
    if hit is None:
        angles, warnings = beam_angles(laser)
        cos, sin = np.cos(angles), np.sin(angles)
        for a in (angles, cos, sin):
            a.flags.writeable = False
        hit = (angles, cos, sin, warnings)
        if len(_LAYOUTS) >= _MAX_LAYOUTS:
            _LAYOUTS.clear()
        _LAYOUTS[key] = hit
    return hit[0], hit[1], hit[2], list(hit[3])


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
    ranges = np.ascontiguousarray(laser.ranges, dtype=np.float64).reshape(-1)
    if not ranges.flags.writeable:  # one array type for the compiled pass (no second compile)
        ranges = ranges.copy()
    ranges = _no_return_as_zero(ranges, _finite_or(laser.range_min, 0.0))
    angles, cos, sin, warnings = _layout(laser)
    n = len(ranges)
    if len(angles) != n:  # unusable angles: no beam can be placed
        z2 = np.zeros((0, 2))
        scan = ScanPoints(ranges, np.zeros(n), np.zeros(n, dtype=bool), z2, np.zeros(0, dtype=np.int64),
                          np.zeros((0, 2), dtype=np.int64), np.zeros((0, 2), dtype=bool), z2)
    else:  # filter, resample and cluster: one compiled pass (scan_kernels.scan_points)
        lo = max(_finite_or(laser.range_min, 0.0), float(params.min_range))
        hi = min(_finite_or(laser.range_max, math.inf), float(params.max_range))
        args = (ranges, angles, cos, sin, lo, hi,
                float(footprint.footprint_length) / 2, float(footprint.footprint_width) / 2,
                float(params.break_distance), float(params.break_slope), float(params.min_spacing),
                float(params.grazing_factor), float(params.grazing_max_break), float(params.grazing_line_distance))
        out = scan_points(*args, False)
        if not out[6]:  # a step within rounding of a threshold (about once in 10^5 scans): by hypot
            out = scan_points(*args, True)
        valid, xy, points, beam, clusters, end_seen, _ = out
        scan = ScanPoints(ranges, angles, valid, points, beam, clusters, end_seen, xy)
    if n and not len(scan.points):
        warnings.append(f"no valid range among {n} beams")
    elif not n:
        warnings.append("empty scan")
    return scan, warnings


def _finite_or(v: float, default: float) -> float:
    v = float(v)
    return v if math.isfinite(v) else default


def _no_return_as_zero(ranges: np.ndarray, range_min: float) -> np.ndarray:
    """`ranges` with every reading below the laser's own `range_min` set to 0: the no-return
    code. The official simulator's range buffer starts at 0 and its noise lifts a beam that hit
    nothing to [0, noise], below range_min; a real laser measures nothing that near. Read as
    "something nearer" such a beam would hide what it looked past (an end seen, a gap seen
    through into the open) on half the beams, by the noise's sign; the compiled passes read 0,
    as inf, as nothing there. A copy when anything changes: the laser's array is the caller's."""
    if not range_min > 0:
        return ranges
    below = ranges < range_min  # NaN compares False: dropped as before
    if not below.any():
        return ranges
    out = ranges.copy()
    out[below] = 0.0
    return out
