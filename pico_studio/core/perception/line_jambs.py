"""A doorway in a straight wall seen at a grazing angle: its far jamb as scan points in line.

From a corridor, a doorway in the corridor's wall far ahead is seen at a few degrees: past the
doorway the wall spreads its points 0.1-0.3 m apart, too sparse for a wall of the local map,
and the doorway's near jamb (a building wall's seen end) is left a lone jamb. Its far side is
there in the scan, on the wall's line drawn on past the gap. With the end E, the wall's
direction d out of it (unit), and every valid point P of the scan in the zero frame,

    s = (P - E) . d  (along),    o = |(P - E) x d|  (off the line),

the points in line are those with o <= `door_offset_short`, none a tracked object's (a person
walking in line with the wall is no jamb), and no nearer than that to a wall of the local map (a wall in line is door_pairs' to judge, a table's front among them). The end
is a door's jamb when

1. walking the points in line outwards from the end (s > 0), the first step between neighbours
   (the end itself at s_0 = 0) of at least `door_min_width` runs from s_0 to s_1, at most
   `door_max_width`: the gap, empty of points on the line. The points before it are the wall
   itself running on past the local map's end (a merged end lags the scan's by a few cm to
   0.2 m at 7-9 m), and the door starts at the last of them;
2. at least three points in line lie in [s_1, s_1 + door_max_width], spanning at least
   `line_jamb_run`: the wall running on (a chair's leg or a person's feet are shorter);
3. of five rays from the robot to points across the gap (at 0.1, 0.3, ..., 0.9 of it), at least
   `door_min_free_rays` run on more than `door_occlusion` past the point, or return nothing (an
   invalid beam whose range is not a return nearer than the point): the gap is seen through
   (the beam nearest each ray's direction, within the field of view).

The door runs from E + s_0 d to E + s_1 d.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config.perception_params import IdentifyParams
from pico_studio.core.perception.identify_kernels import _beam_towards, _on_any
from pico_studio.jit import kernel, njit


def line_jamb_doors(lone: np.ndarray, walls: np.ndarray, ranges: np.ndarray, angles: np.ndarray, valid: np.ndarray,
                    wall_beams: np.ndarray, pose: tuple[float, float, float],
                    params: IdentifyParams) -> tuple[np.ndarray, np.ndarray]:
    """(doors (K, 4), used (L,) bool): the lone jambs `lone` (L, 4: from the end along its wall)
    that the scan (ranges, angles (robot frame), valid; `pose` the robot's in the zero frame)
    shows to be doors, and which of them did; `walls` (W, 4) the local map's; `wall_beams` (n,)
    the valid beams that may be a wall's points (not a tracked object's: a person walking in
    the wall's line is no jamb)."""
    if params.line_jamb_run <= 0 or len(lone) == 0 or len(ranges) < 2:
        return np.zeros((0, 4)), np.zeros(len(lone), dtype=bool)
    angles = np.ascontiguousarray(angles, dtype=float)
    doors, used = line_jambs(
        np.ascontiguousarray(lone, dtype=float).reshape(-1, 4), np.ascontiguousarray(walls, dtype=float).reshape(-1, 4),
        np.ascontiguousarray(ranges, dtype=float), angles, np.ascontiguousarray(valid, dtype=bool),
        np.ascontiguousarray(wall_beams, dtype=bool), float(pose[0]), float(pose[1]), float(pose[2]),
        bool(np.all(np.diff(angles) > 0)), float(params.door_offset_short), float(params.door_min_width),
        float(params.door_max_width), float(params.line_jamb_run), float(params.door_occlusion),
        int(params.door_min_free_rays))
    return doors[used], used


def _example() -> tuple:
    angles = np.linspace(-1.0, 1.0, 9)
    return (np.array([[1.0, 1.0, 2.0, 1.0]]), np.array([[0.0, 1.0, 1.0, 1.0]]), np.full(9, 2.0), angles,
            np.ones(9, dtype=np.bool_), np.ones(9, dtype=np.bool_), 0.0, 0.0, 0.0, True, 0.05, 0.5, 1.3, 0.3, 0.1, 1)


@kernel(_example)
def line_jambs(lone: np.ndarray, walls: np.ndarray, ranges: np.ndarray, angles: np.ndarray, valid: np.ndarray,
               wall_beams: np.ndarray, x: float, y: float, heading: float, ascending: bool, offset: float,
               min_width: float, max_width: float, run: float, occlusion: float,
               min_free: int) -> tuple[np.ndarray, np.ndarray]:
    """(doors (L, 4), used (L,) bool; a door's row meaningful where used): steps 1-3 of the
    module doc for each lone jamb, over the beams between the bearings of its end and a point
    2 x max_width on along its wall (every beam when the angles are not ascending)."""
    n_lone = lone.shape[0]
    doors = np.zeros((n_lone, 4))
    used = np.zeros(n_lone, dtype=np.bool_)
    n = ranges.shape[0]
    reach = 2.0 * max_width  # the gap and the wall running on past it
    found = np.empty(n)
    every = np.ones(walls.shape[0], dtype=np.bool_)
    a0, inc = angles[0], (angles[-1] - angles[0]) / (n - 1)  # as identify._view_arrays
    for k in range(n_lone):
        ex, ey = lone[k, 0], lone[k, 1]
        dx, dy = lone[k, 2] - ex, lone[k, 3] - ey
        length = math.hypot(dx, dy)
        if length <= 0:
            continue
        dx, dy = dx / length, dy / length
        b0, b1 = 0, n
        if ascending:
            ba = _bearing(ex, ey, x, y, heading)
            bb = _bearing(ex + reach * dx, ey + reach * dy, x, y, heading)
            lo, hi = min(ba, bb), max(ba, bb)
            if hi - lo <= math.pi:
                b0, b1 = int(np.searchsorted(angles, lo)), int(np.searchsorted(angles, hi, side="right"))
        m = 0
        for b in range(b0, b1):
            if not wall_beams[b] or not math.isfinite(ranges[b]):
                continue
            px = x + ranges[b] * math.cos(heading + angles[b]) - ex
            py = y + ranges[b] * math.sin(heading + angles[b]) - ey
            along = px * dx + py * dy
            if along <= 0 or along > reach or abs(px * dy - py * dx) > offset:
                continue
            if _on_any(px + ex, py + ey, walls, every, offset):
                continue  # a wall of the local map's: door_pairs' to judge
            found[m] = along
            m += 1
        if m < 3:
            continue
        # the wall runs on in points past the local map's end (the merged end lags the scan's):
        # the gap opens at the first step along the line of at least a door's width
        pts = np.sort(found[:m])
        start, first = 0.0, -1.0
        for q in range(m):
            if pts[q] - start >= min_width:
                first = pts[q]
                break
            start = pts[q]
        if first < 0 or first - start > max_width:
            continue
        count, last = 0, first
        for q in range(m):
            if first <= found[q] and found[q] <= first + max_width:
                count += 1
                last = max(last, found[q])
        if count < 3 or last - first < run:
            continue
        sx, sy = ex + start * dx, ey + start * dy
        fx, fy = ex + first * dx, ey + first * dy
        if inc == 0 or _free_rays(sx, sy, fx, fy, ranges, valid, x, y, heading, a0, inc, occlusion) < min_free:
            continue
        doors[k, 0], doors[k, 1], doors[k, 2], doors[k, 3] = sx, sy, fx, fy
        used[k] = True
    return doors, used


@njit
def _bearing(px: float, py: float, x: float, y: float, heading: float) -> float:
    """The bearing of point p from the robot (x, y, heading), in [-pi, pi)."""
    return (math.atan2(py - y, px - x) - heading + math.pi) % (2 * math.pi) - math.pi


@njit
def _free_rays(ax: float, ay: float, bx: float, by: float, ranges: np.ndarray, valid: np.ndarray, x: float, y: float,
               heading: float, a0: float, inc: float, occlusion: float) -> int:
    """How many of five rays from the robot to points across the gap a -> b run on more than
    `occlusion` past the point, or return nothing (the beam towards each point,
    identify_kernels._beam_towards; none out of view). Along the ray, not off the gap's line: at a
    grazing angle a ray through a doorway ends on the far jamb's side a few cm behind the line,
    a metre on."""
    free = 0
    for f in (0.1, 0.3, 0.5, 0.7, 0.9):
        px, py = ax + f * (bx - ax), ay + f * (by - ay)
        beam = _beam_towards(px, py, ranges.shape[0], x, y, heading, a0, inc)
        if beam < 0:
            continue
        r, dist = ranges[beam], math.hypot(px - x, py - y)
        if valid[beam]:
            if r > dist + occlusion:
                free += 1
        elif not (math.isfinite(r) and 0 < r < dist):  # nothing returned, no nearer return dropped
            free += 1
    return free
