"""True features of a map for scoring: corners (with the wall directions that meet there) and
door openings. Pure functions of segments, so scoring and tests can call them on any map.

Corners. End points closer than `snap` are one vertex. Each vertex keeps the directions of the
segments leaving it, and of every segment it abuts (lies within `abut` of: a T-junction, a wall
rectangle's corner on another's face, a table a few cm off a wall) both ways, or the one way
along it when near that segment's end. Seen from a point R, the segments at a vertex V cut the plane around V
into sectors; R lies in one of them, of angular width w:
- w < pi - tol: R looks into the corner: **concave** (a room's inner corner);
- w > pi + tol: the corner points at R: **convex** (the outer corner of a wall end, a jamb;
  a loose wall end, with one segment, has w = 2 pi);
- otherwise the walls continue straight on: not a corner.

The vertex graph and the map's door openings are `json_map.openings`'s (one definition for
the truth and the combined map).
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.json_map.openings import Vertices
from pico_studio.sim.truth_kernels import corner_classes


def classify_corners(
    graph: Vertices, viewpoint: tuple[float, float], straight_tolerance: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(vertex indices that are corners as seen from `viewpoint`, convex flags, loose-end flags):
    `sector_width` towards the viewpoint at every candidate, as one compiled loop
    (`truth_kernels.corner_classes`) over the candidates' directions flattened once per graph."""
    key = ("flat candidates", straight_tolerance)
    if key not in graph.cache:
        cand = corner_candidates(graph, straight_tolerance)
        counts = np.array([len(graph.directions[v]) for v in cand], dtype=np.int64)
        starts = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        dirs = np.concatenate([graph.directions[v] for v in cand]) if len(cand) else np.zeros(0)
        graph.cache[key] = (np.ascontiguousarray(graph.points, dtype=np.float64), cand, starts,
                            np.ascontiguousarray(dirs, dtype=np.float64))
    points, cand, starts, dirs = graph.cache[key]
    return corner_classes(points, cand, starts, dirs, float(viewpoint[0]), float(viewpoint[1]), float(straight_tolerance))


def corner_candidates(graph: Vertices, straight_tolerance: float) -> np.ndarray:
    """Vertices that can be a corner from somewhere: all but those where exactly two segments
    continue each other in a straight line (those are never corners), cached per graph."""
    key = ("candidates", straight_tolerance)
    cache = graph.cache
    if key not in cache:
        keep = []
        for v, dirs in enumerate(graph.directions):
            if len(dirs) == 0:
                continue
            if len(dirs) == 2 and abs(abs(math.remainder(dirs[0] - dirs[1], 2 * math.pi)) - math.pi) <= straight_tolerance:
                continue
            keep.append(v)
        cache[key] = np.array(keep, dtype=np.int64)
    return cache[key]

