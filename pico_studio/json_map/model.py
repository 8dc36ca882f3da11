"""The global map model: points plus index-pair segments, as the challenge's JSON has it.

Geometry is numpy: `points` (P, 2) and `walls` (N, 2) point indices; every polygon
(cabinet/table, door, start area) is a (K, 2) array of point-index segments, and for a
cabinet or table the first segment is its front. Heightmaps are vectorised into the same
model, so everything downstream sees one kind of map.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from pico_studio.config.map_params import OpeningParams
from pico_studio.json_map.openings import door_openings

# A map coordinate beyond 10 km is a typo or junk (the challenge's buildings are < 100 m):
# refused at validation, before 1e308 overflows a raster size or a distance somewhere later.
MAX_COORDINATE_M = 10_000.0
# Self-crossing checks compare every pair of a loop's edges: bounded by checking only loops
# up to this many edges (hand-drawn loops have a few dozen).
MAX_CHECKED_LOOP = 1000
MAX_CHECKED_WALLS = 20_000  # and only in maps up to this many walls (finding the loops is a Python walk)


@dataclass
class GlobalMap:
    points: np.ndarray  # (P, 2) float64, metres
    walls: np.ndarray  # (N, 2) int64, indices into points
    objects: list[np.ndarray] = field(default_factory=list)  # cabinets/tables, (K, 2) each
    object_key: str = "cabinets"  # which JSON key `objects` came from: "cabinets" or "tables"
    doors: list[np.ndarray] = field(default_factory=list)  # door polygons, (K, 2) each
    start_area: list[np.ndarray] = field(default_factory=list)  # usually one polygon
    finish: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=np.int64))
    extra: dict[str, Any] = field(default_factory=dict)  # unknown top-level keys, kept verbatim
    point_extras: list[dict[str, Any]] = field(default_factory=list)  # e.g. "_comment" per point
    key_order: list[str] = field(default_factory=list)  # top-level key order of the source file
    source: Path | None = None
    warnings: list[str] = field(default_factory=list)
    opening_params: OpeningParams = field(default_factory=OpeningParams, compare=False)  # what a door opening is
    _openings: dict[OpeningParams, np.ndarray] = field(default_factory=dict, init=False, compare=False, repr=False)

    # ----- derived geometry -------------------------------------------------------------
    def segments_of(self, pairs: np.ndarray) -> np.ndarray:
        """(K, 2) index pairs -> (K, 4) float segments."""
        if len(pairs) == 0:
            return np.zeros((0, 4))
        return np.hstack([self.points[pairs[:, 0]], self.points[pairs[:, 1]]])

    @property
    def wall_segments(self) -> np.ndarray:
        return self.segments_of(self.walls)

    def polygon_vertices(self, polygon: np.ndarray) -> np.ndarray:
        """A closed polygon's vertices in loop order (K, 2), starting at its first segment.

        Hand-written files list a polygon's segments in any order and direction (the official
        example does), so the loop is chained rather than read off segment by segment.
        """
        order = cycle_vertices(polygon)
        return self.points[order if order is not None else polygon[:, 0]]

    @property
    def object_polygons(self) -> list[np.ndarray]:
        return [self.polygon_vertices(p) for p in self.objects]

    @property
    def object_fronts(self) -> np.ndarray:
        """(M, 4): the front segment (the first one) of every cabinet or table."""
        if not self.objects:
            return np.zeros((0, 4))
        return np.vstack([self.segments_of(p[:1]) for p in self.objects])

    @property
    def door_polygons(self) -> list[np.ndarray]:
        return [self.polygon_vertices(p) for p in self.doors]

    def openings(self) -> np.ndarray:
        """(D, 4) the map's door openings, jamb to jamb (`json_map.openings.door_openings` with
        `opening_params`: its doors, gaps between wall ends, passage mouths; tables and cabinets
        block a gap but have none of their own). Computed once per parameters."""
        p = self.opening_params
        if p not in self._openings:
            objects = [self.segments_of(o) for o in self.objects]
            self._openings[p] = door_openings(
                self.wall_segments, self.door_polygons, obstacles=np.vstack(objects) if objects else None,
                min_width=p.door_min_width, max_width=p.door_max_width, max_thickness=p.max_wall_thickness,
                mouth_probe=p.mouth_probe, mouth_margin=p.mouth_margin, mouth_wall_length=p.mouth_wall_length,
                mouth_depth=p.mouth_depth,
                straight_tolerance=p.straight_tolerance, abut=p.abut_tolerance,
            )
        return self._openings[p].copy()

    @property
    def start_polygons(self) -> list[np.ndarray]:
        return [self.polygon_vertices(p) for p in self.start_area]

    @property
    def finish_segments(self) -> np.ndarray:
        return self.segments_of(self.finish)

    @property
    def solid_segments(self) -> np.ndarray:
        """Everything a laser sees when all doors are closed: walls, then object edges."""
        parts = [self.wall_segments] + [self.segments_of(p) for p in self.objects]
        return np.vstack(parts) if parts else np.zeros((0, 4))

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) over every point that a segment uses."""
        used = self.used_point_indices()
        pts = self.points[used] if len(used) else self.points
        if len(pts) == 0:
            return (0.0, 0.0, 0.0, 0.0)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        return (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))

    @property
    def extent(self) -> tuple[float, float]:
        x0, y0, x1, y1 = self.bounds
        return (x1 - x0, y1 - y0)

    def used_point_indices(self) -> np.ndarray:
        groups = [self.walls.reshape(-1), self.finish.reshape(-1)]
        groups += [p.reshape(-1) for p in self.objects + self.doors + self.start_area]
        return np.unique(np.concatenate(groups)) if groups else np.zeros(0, dtype=np.int64)

    @property
    def start_center(self) -> tuple[float, float] | None:
        """Centre of the first start-area polygon, or None when the map has none."""
        if not self.start_area:
            return None
        c = self.polygon_vertices(self.start_area[0]).mean(axis=0)
        return (float(c[0]), float(c[1]))

    def counts(self) -> dict[str, int]:
        return {
            "points": int(len(self.points)),
            "walls": int(len(self.walls)),
            self.object_key: len(self.objects),
            "doors": len(self.doors),
            "start_area": len(self.start_area),
        }


def cycle_vertices(pairs: np.ndarray) -> np.ndarray | None:
    """Point indices of the one closed loop the segments form (from the first segment on),
    or None when they do not form exactly one loop. Linear in the number of segments (a
    50 MB map may hold a polygon of 10^5 of them)."""
    if len(pairs) < 3:
        return None
    at: dict[int, list[int]] = {}  # point -> the segments that use it
    for k, (a, b) in enumerate(pairs.tolist()):
        at.setdefault(a, []).append(k)
        at.setdefault(b, []).append(k)
    if any(len(v) != 2 for v in at.values()):
        return None  # a loop uses every point exactly twice
    used = np.zeros(len(pairs), bool)
    used[0] = True
    order = [int(pairs[0, 0]), int(pairs[0, 1])]
    while len(order) <= len(pairs):
        tail = order[-1]
        nxt = [k for k in at[tail] if not used[k]]
        if not nxt:
            break
        used[nxt[0]] = True
        a, b = (int(v) for v in pairs[nxt[0]])
        order.append(b if a == tail else a)
    if order[-1] != order[0] or len(set(order[:-1])) != len(pairs):
        return None
    return np.array(order[:-1], dtype=np.int64)


def wall_loops(walls: np.ndarray) -> list[np.ndarray]:
    """The simple closed loops among the walls: connected groups of walls in which every
    point is used by exactly two of them, each as (K,) wall indices (in no set order).
    None are looked for in a map of more than `MAX_CHECKED_WALLS` walls."""
    if len(walls) == 0 or len(walls) > MAX_CHECKED_WALLS:
        return []
    pairs = walls.tolist()
    degree = np.bincount(walls.reshape(-1)).tolist()
    by_point: dict[int, list[int]] = {}
    for k, (i, j) in enumerate(pairs):
        by_point.setdefault(i, []).append(k)
        by_point.setdefault(j, []).append(k)
    seen = [False] * len(pairs)
    loops: list[np.ndarray] = []
    for start in range(len(pairs)):
        if seen[start]:
            continue
        # walk the component, collecting its walls; it is a loop when all its points have degree 2
        group, stack, ok = [], [start], True
        seen[start] = True
        while stack:
            k = stack.pop()
            group.append(k)
            for p in pairs[k]:
                ok = ok and degree[p] == 2
                for nxt in by_point[p]:
                    if not seen[nxt]:
                        seen[nxt] = True
                        stack.append(nxt)
        if ok and len(group) >= 3:  # connected, every point used twice: one simple loop
            loops.append(np.array(group))
    return loops


def first_crossing(points: np.ndarray, pairs: np.ndarray) -> tuple[int, int, float, float] | None:
    """The first two segments (indices into `pairs`) of one closed loop whose interiors
    cross — a self-intersecting loop — as (k, l, x, y), or None. Neighbouring segments,
    which share an end point, are not a crossing; touching without crossing is not either."""
    k = len(pairs)
    if k < 4 or k > MAX_CHECKED_LOOP:
        return None
    a, b = points[pairs[:, 0]], points[pairs[:, 1]]
    d = b - a
    # for every pair (i, j): solve a_i + t d_i = a_j + u d_j
    den = d[:, None, 0] * d[None, :, 1] - d[:, None, 1] * d[None, :, 0]
    r = a[None, :, :] - a[:, None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (r[..., 0] * d[None, :, 1] - r[..., 1] * d[None, :, 0]) / den
        u = (r[..., 0] * d[:, None, 1] - r[..., 1] * d[:, None, 0]) / den
    eps = 1e-9
    cross = (np.abs(den) > 1e-12) & (t > eps) & (t < 1 - eps) & (u > eps) & (u < 1 - eps)
    shares = (pairs[:, None, :, None] == pairs[None, :, None, :]).any(axis=(2, 3))
    cross &= ~shares
    cross = np.triu(cross, 1)
    hit = np.argwhere(cross)
    if len(hit) == 0:
        return None
    i, j = (int(v) for v in hit[0])
    x, y = a[i] + t[i, j] * d[i]
    return i, j, float(x), float(y)
