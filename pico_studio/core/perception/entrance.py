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
from pico_studio.jit import kernel

Estimate = tuple[float, float, bool]  # angle, distance, hallway


def entrance_in_scan(segments: np.ndarray, params: EntranceParams) -> Estimate | None:
    kind, angle, distance = scan_entrance(
        np.ascontiguousarray(segments, dtype=float).reshape(-1, 4), float(params.parallel_tolerance),
        float(params.min_gap), float(params.max_gap), float(params.hallway_min_width), float(params.hallway_max_width))
    return None if kind == _NONE else (angle, distance, kind == _HALLWAY)


_NONE, _ENTRANCE, _HALLWAY = 0, 1, 2


def _example() -> tuple:
    return np.array([[1.0, -1.0, 1.0, 1.0], [1.0, 1.8, 1.0, 3.0], [-1.0, 3.0, -1.0, -1.0]]), 0.2, 0.5, 1.5, 1.0, 3.0


@kernel(_example)
def scan_entrance(segments: np.ndarray, tol: float, min_gap: float, max_gap: float, hallway_min: float,
                  hallway_max: float) -> tuple[int, float, float]:
    """(kind: 0 none, 1 entrance, 2 hallway; angle; distance) of the current map (S, 4).

    Directions theta = atan2(dy, dx); two directions are parallel when
    |((theta_j - theta_i + pi/2) mod pi) - pi/2| < tol (perpendicular: that minus pi/2).
    Two walls, parallel and hallway_min..hallway_max apart (|n_0 . (mid_1 - p_0)|, n the
    normal): a hallway, its point midway between their far ends. Else the widest gap
    min_gap..max_gap from a wall's end to the start of one of the next two, parallel or
    perpendicular: an entrance, its point midway."""
    s = segments.shape[0]
    if s < 2:
        return _NONE, 0.0, 0.0
    theta = np.empty(s)
    for i in range(s):
        theta[i] = np.arctan2(segments[i, 3] - segments[i, 1], segments[i, 2] - segments[i, 0])
    if s == 2:
        diff = abs((theta[1] - theta[0] + math.pi / 2) % math.pi - math.pi / 2)
        if diff < tol:
            nx, ny = -math.sin(theta[0]), math.cos(theta[0])
            mx, my = (segments[1, 0] + segments[1, 2]) / 2, (segments[1, 1] + segments[1, 3]) / 2
            width = abs(nx * (mx - segments[0, 0]) + ny * (my - segments[0, 1]))
            if hallway_min <= width <= hallway_max:
                px = py = 0.0
                for w in range(2):  # each wall's end farther from the robot (the first on ties)
                    far = 2 if np.hypot(segments[w, 2], segments[w, 3]) > np.hypot(segments[w, 0], segments[w, 1]) else 0
                    px, py = px + segments[w, far], py + segments[w, far + 1]
                px, py = px / 2, py / 2
                return _HALLWAY, math.atan2(py, px), np.hypot(px, py)
    best, bx, by = -1.0, 0.0, 0.0
    for i in range(s - 1):
        for j in range(i + 1, min(i + 3, s)):
            gap = np.hypot(segments[j, 0] - segments[i, 2], segments[j, 1] - segments[i, 3])
            if not (min_gap <= gap <= max_gap) or (best >= 0 and gap <= best):
                continue
            diff = abs((theta[j] - theta[i] + math.pi / 2) % math.pi - math.pi / 2)
            if diff < tol or abs(diff - math.pi / 2) < tol:
                best, bx, by = gap, (segments[i, 2] + segments[j, 0]) / 2, (segments[i, 3] + segments[j, 1]) / 2
    if best < 0:
        return _NONE, 0.0, 0.0
    return _ENTRANCE, math.atan2(by, bx), np.hypot(bx, by)


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
