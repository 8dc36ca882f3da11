"""The scan stage's compiled loop: filter, resample and cluster a scan in one pass (scan.py's maths).

`scan_points` walks the beams once and does, top to bottom, what scan.py's docstring says:

1. Filter. Beam i is valid when its range r_i is finite and lo <= r_i <= hi; its point
   (r_i cos a_i, r_i sin a_i) is dropped when it lies in the footprint box
   |x| <= half_length and |y| <= half_width (the robot itself).
2. Break. Between consecutive valid points p_j, p_j+1 (step s_j = |p_j+1 - p_j|) a new
   cluster starts when

       s_j > max(break_distance + break_slope * min(r_j, r_j+1),  grazing spacing g_j)

   with, for a surface seen at a grazing angle (b between the beam and the chord of the
   three points before, c = p_j - p_max(j-3, 0)),

       g_j = min(grazing_factor * r_j |a_j+1 - a_j| / max(sin b, 1e-3), grazing_max_break)
       sin b = |u x c| / |c|,  u = p_j / |p_j|          (g_j = 0 when |c| = 0 or factor 0)

3. Resample. The arc length along the scan, A_j = sum over the steps before j that are not
   breaks, binned by `min_spacing`: a point is kept when floor(A_j / min_spacing) grows, and
   always at a cluster's first and last point (every point when min_spacing is 0).
4. End seen. Per cluster end, the neighbouring beam beyond it (outside the scan: not seen)
   either is valid and farther by more than break_distance + break_slope r (seen), or is
   invalid with the laser returning nothing nearer there (seen: not a dropped footprint
   point nor a short return), unless the wall going on could have been out of reach there:
   r + break_distance + break_slope r >= hi (a range past hi is farther by the margin only
   when the end lies that far inside it), or the line through the end and up to three points
   before it meets that beam beyond hi (`_runs_out_of_range`). An end whose next valid point
   past the break lies within `grazing_max_break` and on the end's extended line (see
   `on_line`) is the same wall going on at a grazing angle: not seen.

*On the line.* Forward: does point i + 1 lie within `line_distance` of the line through
points i - 3 and i; backward: does point i lie within it of the line through points i + 1
and i + 4? The distance of q to the line through a, b:

    |u x (q - a)| / |u|,   u = b - a       (a line of |u| <= 1e-6 m: no line, infinitely far)

Points without three neighbours on that side are on no line. `on_line` gives both flags for
every point (the cross-check); the scan needs them at the cluster ends only.

Every float is computed by the same operations, in the same order, as the numpy version this
replaced (so the results are the same to the last bit): e.g. the arc length is the running
sum, the grazing spacing (r |da|) / max(sin b, 1e-3). One exception, for speed: the steps
s_j are sqrt(dx^2 + dy^2) (`cheap_length`), within 4.4e-16 relative of the `hypot` they
were; a step that close to its break threshold, or an arc that close to a bin's edge, makes
the pass "uncertain" and the caller runs it again with hypot (`exact`), so the answers stay
hypot's.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel, njit


@njit
def _line_distance(ax: float, ay: float, bx: float, by: float, qx: float, qy: float) -> float:
    ux, uy = bx - ax, by - ay
    n = math.hypot(ux, uy)
    if not n > 1e-6:
        return np.inf
    return abs(ux * (qy - ay) - uy * (qx - ax)) / max(n, 1e-12)


@njit
def _forward_on_line(xy: np.ndarray, i: int, line_distance: float) -> bool:
    """Point i + 1 within `line_distance` of the line through points i - 3 and i."""
    if i < 3 or i + 1 >= xy.shape[0]:
        return False
    a = i - 3
    return _line_distance(xy[a, 0], xy[a, 1], xy[i, 0], xy[i, 1], xy[i + 1, 0], xy[i + 1, 1]) <= line_distance


@njit
def _backward_on_line(xy: np.ndarray, i: int, line_distance: float) -> bool:
    """Point i within `line_distance` of the line through points i + 1 and i + 4."""
    if i < 0 or i + 4 >= xy.shape[0]:
        return False
    b = i + 4
    return _line_distance(xy[b, 0], xy[b, 1], xy[i + 1, 0], xy[i + 1, 1], xy[i, 0], xy[i, 1]) <= line_distance


@njit
def _runs_out_of_range(xy: np.ndarray, j: int, b: int, cx: float, cy: float, hi: float) -> bool:
    """Would the wall through points b and j (its last points, j the end), going on past j,
    meet the beam of direction (cx, cy) only beyond `hi` (the laser's reach)? The ray t (cx, cy)
    meets the line j + s (j - b) at t = (j x d) / (c x d), d = j - b, c = (cx, cy); going on
    means s >= 0, t > 0."""
    if b == j:
        return False
    dx, dy = xy[j, 0] - xy[b, 0], xy[j, 1] - xy[b, 1]
    den = cx * dy - cy * dx
    if abs(den) <= 1e-12:
        return False  # along the beam: it never meets it, and says nothing
    t = (xy[j, 0] * dy - xy[j, 1] * dx) / den
    s = (xy[j, 0] * cy - xy[j, 1] * cx) / den
    return t > hi and s >= 0.0


def _example() -> tuple:
    xy = np.array([[1.0, 0.1 * i] for i in range(8)])
    return xy, 0.02


@kernel(_example)
def on_line(xy: np.ndarray, line_distance: float) -> tuple[np.ndarray, np.ndarray]:
    """((m - 1,) forward, (m - 1,) backward) bool of every point, as above."""
    m = xy.shape[0]
    fwd = np.zeros(max(m - 1, 0), dtype=np.bool_)
    bwd = np.zeros(max(m - 1, 0), dtype=np.bool_)
    for i in range(m - 1):
        fwd[i] = _forward_on_line(xy, i, line_distance)
        bwd[i] = _backward_on_line(xy, i, line_distance)
    return fwd, bwd


# With u = 2^-53 (1.1e-16) the unit roundoff: sqrt(dx^2 + dy^2) is within 2u of the length
# (three roundings, halved by the root, and the root's own), hypot within 2u: they differ by
# at most 4u relative, two such lengths by 8u (STEP_ERROR is twice that). A running sum of j
# steps then differs by at most (4 + 2 j) u of the sum (both sums round each addition), and
# the division by min_spacing rounds once more (ARC_ERROR per step: 9-18x that).
STEP_ERROR = 2e-15
ARC_ERROR = 4e-15


@njit
def cheap_length(dx: float, dy: float) -> float:
    """|(dx, dy)| as sqrt(dx^2 + dy^2): within 4u of `math.hypot`, a third of its cost (hypot
    itself where the squares would underflow). Every use of a step is a comparison (a break,
    a resampling bin), so a step within that of its threshold is decided again by hypot: the
    results are hypot's to the last bit."""
    sq = dx * dx + dy * dy
    return math.sqrt(sq) if sq > 1e-250 else math.hypot(dx, dy)


@njit
def too_close(a: float, b: float) -> bool:
    """Too close to compare two lengths by `cheap_length` (within its error of hypot's)."""
    return abs(a - b) <= STEP_ERROR * max(abs(a), abs(b))


@njit
def _step(xy: np.ndarray, j: int) -> float:
    """|p_j+1 - p_j|, by hypot."""
    return math.hypot(xy[j + 1, 0] - xy[j, 0], xy[j + 1, 1] - xy[j, 1])


def _scan_example() -> tuple:
    n = 12
    angles = np.linspace(-1.0, 1.0, n)
    cos, sin = np.cos(angles), np.sin(angles)
    for a in (angles, cos, sin):
        a.flags.writeable = False  # as scan.py's cached beam layouts
    ranges = np.array([2.0, 2.0, np.nan, 2.0, 2.1, 0.01, 3.0, 3.0, 3.0, np.inf, 1.0, 1.0])
    return (ranges, angles, cos, sin, 0.05, 10.0, 0.1, 0.2, 0.12, 0.02, 0.025, 1.0, 0.5, 0.03, False)


@kernel(_scan_example)
def scan_points(
    ranges: np.ndarray, angles: np.ndarray, cos: np.ndarray, sin: np.ndarray, lo: float, hi: float,
    half_length: float, half_width: float, break_distance: float, break_slope: float, min_spacing: float,
    grazing_factor: float, grazing_max_break: float, grazing_line_distance: float, exact: bool,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, bool]:
    """(valid (n,) bool, valid points (V, 2), kept points (M, 2), their beams (M,), clusters
    (K, 2) [start, end) into the kept points, end seen (K, 2) bool, certain).

    `exact`: the steps by `math.hypot`, else by the 3x cheaper `cheap_length`; then `certain` says
    whether every decision was as hypot's would be (see `cheap_length`; if not, call again exact)."""
    n = ranges.shape[0]
    # 1. filter: in range, outside the footprint
    valid = np.zeros(n, dtype=np.bool_)
    xy = np.empty((n, 2))
    idx = np.empty(n, dtype=np.int64)
    m = 0
    for i in range(n):
        r = ranges[i]
        if not (math.isfinite(r) and r >= lo and r <= hi):
            continue
        x, y = r * cos[i], r * sin[i]
        if abs(x) <= half_length and abs(y) <= half_width:
            continue
        valid[i] = True
        xy[m, 0], xy[m, 1] = x, y
        idx[m] = i
        m += 1
    # 2-3. one walk over the valid points: the break after point j (its step to point j + 1
    # against the allowed gap), then whether j is kept: a cluster's first or last point, or
    # where the binned arc length grows
    points = np.empty((m, 2))
    beam = np.empty(m, dtype=np.int64)
    clusters = np.empty((m, 2), dtype=np.int64)
    ends = np.empty((m, 2), dtype=np.int64)  # each cluster's first and last valid point
    grazing = m >= 5 and grazing_factor > 0
    certain = True
    n_kept = 0
    c = 0
    arc = 0.0
    bin_prev = 0.0
    brk_before, step_before = True, 0.0  # point 0 starts a cluster
    for j in range(m):
        brk_after, step = True, 0.0  # the last point ends its cluster
        if j + 1 < m:
            dx, dy = xy[j + 1, 0] - xy[j, 0], xy[j + 1, 1] - xy[j, 1]
            step = math.hypot(dx, dy) if exact else cheap_length(dx, dy)
            allowed = break_distance + break_slope * min(ranges[idx[j]], ranges[idx[j + 1]])
            if grazing:
                b = max(j - 3, 0)
                cx, cy = xy[j, 0] - xy[b, 0], xy[j, 1] - xy[b, 1]
                clen = math.hypot(cx, cy)
                rj = math.hypot(xy[j, 0], xy[j, 1])
                ux, uy = xy[j, 0] / max(rj, 1e-12), xy[j, 1] / max(rj, 1e-12)
                sin_b = abs(ux * cy - uy * cx) / max(clen, 1e-12)
                expected = rj * abs(angles[idx[j + 1]] - angles[idx[j]]) / max(sin_b, 1e-3)
                g = min(grazing_factor * expected, grazing_max_break) if clen > 0 else 0.0
                allowed = max(allowed, g)
            brk_after = step > allowed
            if not exact and too_close(step, allowed):
                certain = False  # too close to call without hypot
        keep = brk_before or brk_after or min_spacing <= 0
        if j > 0:
            arc = arc + (0.0 if brk_before else step_before)
        if min_spacing > 0:
            q = arc / min_spacing
            bin_j = np.floor(q)
            if not exact and arc > 0 and min(q - bin_j, bin_j + 1 - q) <= ARC_ERROR * (j + 1) * q:
                certain = False  # the arc's bin too close to call without hypot
            if j > 0 and bin_j > bin_prev:
                keep = True
            bin_prev = bin_j
        if keep:
            if brk_before:
                clusters[c, 0] = n_kept
                ends[c, 0] = j
                c += 1
            if brk_after:
                clusters[c - 1, 1] = n_kept + 1
                ends[c - 1, 1] = j
            points[n_kept, 0], points[n_kept, 1] = xy[j, 0], xy[j, 1]
            beam[n_kept] = idx[j]
            n_kept += 1
        brk_before, step_before = brk_after, step
    n_clusters = c
    # 4. did the laser look past each end?
    end_seen = np.zeros((n_clusters, 2), dtype=np.bool_)
    for c in range(n_clusters):
        for side in range(2):
            j = ends[c, side]
            own = ranges[idx[j]]
            nb = idx[j] + (1 if side else -1)
            if nb < 0 or nb >= n:
                continue  # the edge of the field of view
            raw = ranges[nb]
            if valid[nb]:
                seen = raw > own + break_distance + break_slope * own
            else:  # nothing there: seen, unless the laser returned something nearer, or the
                # wall going on could have been out of its reach there: farther than `hi` is
                # farther by the break's margin only when the end lies that far inside the reach,
                # and the wall's line (through the end and up to three points before it) meets
                # the beam within the reach (a far wall's end at the laser's range runs on unseen)
                seen = not (math.isfinite(raw) and raw > 0 and raw < own) \
                    and own + break_distance + break_slope * own < hi
                if seen:
                    b = max(j - 3, ends[c, 0]) if side else min(j + 3, ends[c, 1])
                    seen = not _runs_out_of_range(xy, j, b, cos[nb], sin[nb], hi)
            # a short break to a point on the end's extended line: the wall going on
            if side == 1 and j + 1 < m:
                seen = seen and not (_step(xy, j) <= grazing_max_break and _forward_on_line(xy, j, grazing_line_distance))
            if side == 0 and j > 0:
                seen = seen and not (_step(xy, j - 1) <= grazing_max_break
                                     and _backward_on_line(xy, j - 1, grazing_line_distance))
            end_seen[c, side] = seen
    return valid, xy[:m], points[:n_kept], beam[:n_kept], clusters[:n_clusters], end_seen, certain
