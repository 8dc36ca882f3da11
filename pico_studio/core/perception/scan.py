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
   a new cluster: walls never span a range jump. A surface seen at a grazing angle spreads its
   points (spacing r dtheta / sin b, b between beam and surface): there the allowed gap grows
   to `grazing_factor` times that, at most `grazing_max_break`.

Each cluster end also records whether the wall's end was *seen*: the neighbouring beam
beyond it returned nothing or hit something farther away (the laser looked past the end,
as the spike method assumes). An end next to a nearer point (occluded) or at the edge of the
field of view is not seen: a floating end; so is an end whose next point past the break lies
on the wall's extended line less than `grazing_max_break` away (the same wall going on,
seen at a grazing angle; a door in line is wider).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pico_studio.config.perception_params import ProximityParams, ScanParams
from pico_studio.core.io import LaserData
from pico_studio.core.perception.proximity import in_footprint
from pico_studio.core.perception.scan_kernels import on_line


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
    ranges = np.asarray(laser.ranges, dtype=float).reshape(-1)
    angles, cos, sin, warnings = _layout(laser)
    n = len(ranges)
    if len(angles) != n:  # unusable angles: no beam can be placed
        angles = np.zeros(n)
        valid = np.zeros(n, dtype=bool)
        idx = np.zeros(0, dtype=np.int64)
        xy = np.zeros((0, 2))
    else:
        lo = max(_finite_or(laser.range_min, 0.0), params.min_range)
        hi = min(_finite_or(laser.range_max, math.inf), params.max_range)
        with np.errstate(invalid="ignore"):
            valid = np.isfinite(ranges) & (ranges >= lo) & (ranges <= hi)
        # Cartesian points of the in-range beams only; those in the footprint are dropped
        idx = np.flatnonzero(valid)
        r = ranges[idx]
        xy = np.empty((len(idx), 2))
        np.multiply(r, cos[idx], out=xy[:, 0])
        np.multiply(r, sin[idx], out=xy[:, 1])
        inside = in_footprint(xy, footprint)
        if inside.any():
            valid[idx[inside]] = False
            idx = idx[~inside]
            xy = xy[~inside]
    if n and not len(idx):
        warnings.append(f"no valid range among {n} beams")
    elif not n:
        warnings.append("empty scan")
    return _cluster(ranges, angles, valid, idx, xy, params), warnings


def _finite_or(v: float, default: float) -> float:
    v = float(v)
    return v if math.isfinite(v) else default


def _cluster(
    ranges: np.ndarray, angles: np.ndarray, valid: np.ndarray, idx: np.ndarray, xy: np.ndarray, p: ScanParams
) -> ScanPoints:
    """Resample and break the valid beams `idx` (points `xy`) into clusters."""
    m = len(idx)
    if m == 0:
        z2 = np.zeros((0, 2))
        return ScanPoints(ranges, angles, valid, z2, np.zeros(0, dtype=np.int64),
                          np.zeros((0, 2), dtype=np.int64), np.zeros((0, 2), dtype=bool), z2)
    r = ranges[idx]
    d = xy[1:] - xy[:-1]
    step = np.hypot(d[:, 0], d[:, 1])
    base = p.break_distance + p.break_slope * np.minimum(r[:-1], r[1:])
    # a break to a point on the wall's extended line, shorter than a door (`grazing_max_break`)
    short = np.append(step <= p.grazing_max_break, False)
    fwd, bwd = (np.append(f, False) & short for f in _on_line(xy, p))  # padded: index by a point's own index
    brk = step > np.maximum(base, _grazing_spacing(xy, angles[idx], p))
    first = np.empty(m, dtype=bool)  # first point of each cluster
    first[0] = True
    first[1:] = brk
    last = np.empty(m, dtype=bool)
    last[:-1] = brk
    last[-1] = True
    keep = first | last
    if p.min_spacing > 0:
        # arc length restarted at every cluster, binned by the minimum spacing
        arc = np.zeros(m)
        np.cumsum(np.where(brk, 0.0, step), out=arc[1:])
        bins = np.floor(arc / p.min_spacing)
        keep[1:] |= bins[1:] > bins[:-1]
    else:
        keep[:] = True
    kept = np.flatnonzero(keep)
    points = xy[kept]
    beam = idx[kept]
    # clusters in kept-point indices: every cluster's first point is kept
    starts = np.flatnonzero(first[kept])
    ends = np.empty_like(starts)
    ends[:-1] = starts[1:]
    ends[-1] = len(kept)
    clusters = np.column_stack([starts, ends])
    end_seen = _ends_seen(ranges, valid, beam[starts], beam[ends - 1], p)
    # a short break whose next point lies on the wall's extended line is the wall going on at
    # a grazing angle, not its end: floating (breaks are between valid points i and i + 1; a
    # door's width in line is a real end)
    end_seen[:, 1] &= ~fwd[kept[ends - 1]]  # (the last point: padded False)
    end_seen[:, 0] &= ~((kept[starts] > 0) & bwd[np.maximum(kept[starts] - 1, 0)])
    return ScanPoints(ranges, angles, valid, points, beam, clusters, end_seen, xy)


def _grazing_spacing(xy: np.ndarray, ang: np.ndarray, p: ScanParams) -> np.ndarray:
    """(m - 1,) allowed gap between valid points i and i + 1 on a surface seen at a grazing
    angle: `grazing_factor` x the spacing the surface's incidence predicts, r dtheta / sin(b)
    (b between the beam and the surface, whose direction is the chord of the three points
    before), at most `grazing_max_break`."""
    m = len(xy)
    if m < 5 or p.grazing_factor <= 0:
        return np.zeros(max(m - 1, 0))
    back = np.maximum(np.arange(m - 1) - 3, 0)
    chord = xy[np.arange(m - 1)] - xy[back]
    beam = xy[:-1] / np.maximum(np.hypot(xy[:-1, 0], xy[:-1, 1]), 1e-12)[:, None]
    clen = np.hypot(chord[:, 0], chord[:, 1])
    sin_b = np.abs(beam[:, 0] * chord[:, 1] - beam[:, 1] * chord[:, 0]) / np.maximum(clen, 1e-12)
    r = np.hypot(xy[:-1, 0], xy[:-1, 1])
    expected = r * np.abs(ang[1:] - ang[:-1]) / np.maximum(sin_b, 1e-3)
    return np.where(clen > 0, np.minimum(p.grazing_factor * expected, p.grazing_max_break), 0.0)


def _on_line(xy: np.ndarray, p: ScanParams) -> tuple[np.ndarray, np.ndarray]:
    """(m - 1,) each twice: does point i + 1 lie within `grazing_line_distance` of the line
    through points i - 3 and i (forward), and point i of the line through i + 1 and i + 4
    (backward)? One compiled loop (scan_kernels.on_line)."""
    return on_line(np.ascontiguousarray(xy, dtype=np.float64), float(p.grazing_line_distance))


def _ends_seen(
    ranges: np.ndarray, valid: np.ndarray, first_beam: np.ndarray, last_beam: np.ndarray, p: ScanParams
) -> np.ndarray:
    """Per cluster (first end, last end): did the laser look past that end?

    The neighbouring beam outside the cluster is either invalid but not at the edge of the
    field of view (nothing there within range: seen), or valid and farther by more than the
    break distance (seen), or nearer (occluded: not seen)."""
    n = len(ranges)
    beams = np.column_stack([first_beam, last_beam])  # (K, 2): both ends at once
    nb = beams + np.array([-1, 1])
    inside = (nb >= 0) & (nb < n)
    nbc = np.clip(nb, 0, n - 1)
    nvalid = valid[nbc]
    raw = ranges[nbc]
    own = ranges[beams]
    nr = np.where(nvalid, raw, np.inf)
    farther = nr > own + p.break_distance + p.break_slope * own
    # an invalid neighbour counts as far only when the laser itself returned nothing
    # there (a dropped footprint point or a too-short return is not "far")
    far_invalid = ~nvalid & ~(np.isfinite(raw) & (raw > 0) & (raw < own))
    return inside & np.where(nvalid, farther, far_invalid)
