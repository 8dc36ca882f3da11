"""The base's compiled loops: the clearance to every segment and the first segment the
footprint box touches (`sim.base.Base.move`, every control step near a wall).

Clearance: `core.geometry.point_segment_distance` for one point p, segment by segment:

    t = clip(((p - a) . (b - a)) / max(|b - a|^2, 1e-18), 0, 1),   |p - a - t (b - a)|.

Box test: `sim.base.box_hits` segment by segment, stopping at the first that touches. In the
robot frame (the segment's ends e rotated by the pose's -a about its position,
(e_x c + e_y s, -e_x s + e_y c)), a segment is apart from the box exactly when it lies beyond
the box along x, along y, or along its own normal: |x1 y2 - y1 x2| > |dy| half_length +
|dx| half_width.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel


def _example() -> tuple:
    return 0.5, 0.5, np.array([[0.0, 0.0, 1.0, 0.0], [2.0, -1.0, 2.0, 1.0]])


@kernel(_example)
def segment_distances(px: float, py: float, segments: np.ndarray) -> np.ndarray:
    """(N,) distance from the point (px, py) to each of `segments` (N, 4)."""
    out = np.empty(segments.shape[0])
    for k in range(segments.shape[0]):
        ax, ay = segments[k, 0], segments[k, 1]
        dx, dy = segments[k, 2] - ax, segments[k, 3] - ay
        denom = max(dx * dx + dy * dy, 1e-18)
        t = min(max(((px - ax) * dx + (py - ay) * dy) / denom, 0.0), 1.0)
        ex, ey = px - ax - t * dx, py - ay - t * dy
        out[k] = math.sqrt(ex * ex + ey * ey)
    return out


def _box_example() -> tuple:
    return 0.5, 0.5, 0.3, 0.25, 0.2, np.array([[0.0, 0.0, 1.0, 0.0], [2.0, -1.0, 2.0, 1.0]])


@kernel(_box_example)
def box_first_hit(x: float, y: float, a: float, half_length: float, half_width: float, segments: np.ndarray) -> int:
    """The first of `segments` (N, 4, map frame) touching the box centred at (x, y), heading
    a, of half sizes (half_length, half_width); -1 when none does."""
    c, s = math.cos(a), math.sin(a)
    for k in range(segments.shape[0]):
        ex1, ey1 = segments[k, 0] - x, segments[k, 1] - y
        ex2, ey2 = segments[k, 2] - x, segments[k, 3] - y
        x1, y1 = ex1 * c + ey1 * s, -ex1 * s + ey1 * c
        x2, y2 = ex2 * c + ey2 * s, -ex2 * s + ey2 * c
        if min(x1, x2) > half_length or max(x1, x2) < -half_length:
            continue
        if min(y1, y2) > half_width or max(y1, y2) < -half_width:
            continue
        dx, dy = x2 - x1, y2 - y1
        if abs(x1 * y2 - y1 * x2) > abs(dy) * half_length + abs(dx) * half_width:
            continue
        return k
    return -1
