"""Entrance and hallway detection (seed 003), the median over several scans.

On the current map (walls in scan order, robot frame), each wall is compared with the next
and the one after: when their directions are parallel or perpendicular (within
`parallel_tolerance`) and the end of the first lies between `min_gap` and `max_gap` from the
start of the other, the gap is an entrance, its point midway. The widest such gap wins. With
exactly two walls, parallel and `hallway_min_width`..`hallway_max_width` apart, the robot is
in a hallway: the entrance point lies midway between them at their far ends. Single scans
are noisy, so the estimate is the median angle and distance over the last `median_scans`.
"""

from __future__ import annotations

import math
import statistics

import numpy as np

from pico_studio.config.perception_params import EntranceParams
from pico_studio.core.geometry import wrap_angle

Estimate = tuple[float, float, bool]  # angle, distance, hallway


def entrance_in_scan(segments: np.ndarray, params: EntranceParams) -> Estimate | None:
    s = len(segments)
    if s < 2:
        return None
    d = segments[:, 2:4] - segments[:, 0:2]
    theta = np.arctan2(d[:, 1], d[:, 0])
    if s == 2:
        diff = abs((theta[1] - theta[0] + math.pi / 2) % math.pi - math.pi / 2)
        if diff < params.parallel_tolerance:
            n = np.array([-math.sin(theta[0]), math.cos(theta[0])])
            mid1 = (segments[1, 0:2] + segments[1, 2:4]) / 2
            width = abs(float(n @ (mid1 - segments[0, 0:2])))
            if params.hallway_min_width <= width <= params.hallway_max_width:
                ends = segments.reshape(-1, 2)
                r = np.hypot(ends[:, 0], ends[:, 1])
                far0 = ends[0:2][np.argmax(r[0:2])]
                far1 = ends[2:4][np.argmax(r[2:4])]
                p = (far0 + far1) / 2
                return math.atan2(p[1], p[0]), math.hypot(p[0], p[1]), True
    best: tuple[float, float, float] | None = None
    th = theta.tolist()
    seg = segments.tolist()
    tol = params.parallel_tolerance
    for i in range(s - 1):
        for j in range(i + 1, min(i + 3, s)):
            gap = math.hypot(seg[j][0] - seg[i][2], seg[j][1] - seg[i][3])
            if not params.min_gap <= gap <= params.max_gap or (best is not None and gap <= best[0]):
                continue
            diff = abs((th[j] - th[i] + math.pi / 2) % math.pi - math.pi / 2)
            if diff < tol or abs(diff - math.pi / 2) < tol:
                best = (gap, (seg[i][2] + seg[j][0]) / 2, (seg[i][3] + seg[j][1]) / 2)
    if best is None:
        return None
    return math.atan2(best[2], best[1]), math.hypot(best[1], best[2]), False


def median_entrance(history: tuple[Estimate, ...]) -> tuple[tuple[float, float] | None, bool]:
    """Median (angle, distance) over the recent estimates, and whether most were hallways."""
    if not history:
        return None, False
    a = [h[0] for h in history]
    # the median of angles near +-pi: taken relative to the circular mean
    ref = math.atan2(math.fsum(map(math.sin, a)) / len(a), math.fsum(map(math.cos, a)) / len(a))
    rel = [wrap_angle(x - ref) for x in a]
    ang = wrap_angle(ref + statistics.median(rel))
    dist = float(statistics.median([h[1] for h in history]))
    hallway = sum(h[2] for h in history) * 2 > len(history)
    return (ang, dist), hallway
