"""The global map's distance field: distance to the nearest map segment, and which one it is.

Built once per map: the segments are drawn into a grid (OpenCV anti-alias-free lines, each
pixel remembering its segment), `cv2.distanceTransform` gives the Euclidean distance from
every cell to the nearest drawn cell, and `cv2.distanceTransformWithLabels` tells which
drawn cell that is — hence which segment. Lookups are compiled loops (match_kernels.py):

    field = DistanceField.from_segments(segments, resolution=0.02, margin=2.0)
    d = field.distance(points)          # (N,) metres, bilinear
    k = field.nearest_segment(points)   # (N,) segment index, -1 off the grid

Grid node (r, c) sits at (x0 + c * resolution, y0 + r * resolution).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import cv2
import numpy as np

from pico_studio.config.localisation_params import FieldParams
from pico_studio.core.localisation.match_kernels import field_distance, field_nearest
from pico_studio.json_map.model import GlobalMap

_SUBPIXEL_BITS = 4  # cv2.line's fixed-point shift: end points drawn to 1/16 of a cell


@dataclass
class DistanceField:
    segments: np.ndarray  # (S, 4) the map segments the field is built from
    x0: float
    y0: float
    resolution: float
    field: np.ndarray  # (H, W) float32 metres to the nearest segment
    segment_index: np.ndarray  # (H, W) int32 index of the nearest segment
    normals: np.ndarray  # (S, 2) unit normal of every segment
    # segments a beam may pass (doors, which open): not counted as walls passed through
    passable: np.ndarray | None = None  # (S,) bool
    _coarse: dict[tuple[int, float, int], np.ndarray] = dataclasses.field(default_factory=dict, repr=False)

    @classmethod
    def from_segments(cls, segments: np.ndarray, *, resolution: float, margin: float) -> DistanceField:
        segments = np.asarray(segments, dtype=float).reshape(-1, 4)
        if len(segments) == 0:
            raise ValueError("a distance field needs at least one segment")
        pts = segments.reshape(-1, 2)
        lo = pts.min(axis=0) - margin
        hi = pts.max(axis=0) + margin
        width = int(np.ceil((hi[0] - lo[0]) / resolution)) + 1
        height = int(np.ceil((hi[1] - lo[1]) / resolution)) + 1

        # 1. draw every segment with its index + 1 (0 = free) at sub-cell precision
        ids = np.zeros((height, width), dtype=np.int32)
        scale = float(1 << _SUBPIXEL_BITS)
        px = np.round((pts - lo) / resolution * scale).astype(np.int64).reshape(-1, 4)
        for k, (c1, r1, c2, r2) in enumerate(px):
            cv2.line(ids, (int(c1), int(r1)), (int(c2), int(r2)), k + 1, 1, cv2.LINE_8, _SUBPIXEL_BITS)

        # 2. Euclidean distance from every free cell to the nearest drawn one
        free = np.where(ids == 0, 255, 0).astype(np.uint8)
        dist = cv2.distanceTransform(free, cv2.DIST_L2, cv2.DIST_MASK_PRECISE) * resolution

        # 3. which drawn cell is nearest (its label), hence which segment
        _, labels = cv2.distanceTransformWithLabels(free, cv2.DIST_L2, 5, labelType=cv2.DIST_LABEL_PIXEL)
        drawn = ids > 0
        label_to_segment = np.full(int(labels.max()) + 1, -1, dtype=np.int32)
        label_to_segment[labels[drawn]] = ids[drawn] - 1
        segment_index = label_to_segment[labels]

        d = segments[:, 2:4] - segments[:, 0:2]
        length = np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-12)
        normals = np.stack([-d[:, 1], d[:, 0]], axis=1) / length[:, None]
        return cls(segments, float(lo[0]), float(lo[1]), resolution,
                   dist.astype(np.float32), segment_index, normals)

    @classmethod
    def from_map(cls, global_map: GlobalMap, params: FieldParams) -> DistanceField:
        segments = map_segments(global_map, params)
        out = cls.from_segments(segments, resolution=params.resolution, margin=params.margin)
        n_doors = sum(len(p) for p in global_map.doors) if params.doors_as_walls else 0
        out.passable = np.arange(len(segments)) >= len(segments) - n_doors
        return out

    @property
    def shape(self) -> tuple[int, int]:
        return self.field.shape

    def _grid(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Fractional (column, row) of every point."""
        return (points[..., 0] - self.x0) / self.resolution, (points[..., 1] - self.y0) / self.resolution

    def distance(self, points: np.ndarray) -> np.ndarray:
        """Bilinear distance (metres) at every point (..., 2); off the grid: the border value."""
        pts = np.ascontiguousarray(points, dtype=np.float64)
        d = field_distance(self.field, self.x0, self.y0, self.resolution, pts.reshape(-1, 2))
        return d.reshape(pts.shape[:-1])

    def coarse(self, stride: int, truncation: float, pad: int) -> np.ndarray:
        """Every `stride`-th node's distance, truncated, padded by `pad` nodes of `truncation`
        on every side: the grid the pose search shifts scans over (cached)."""
        key = (stride, truncation, pad)
        if key not in self._coarse:
            sub = np.minimum(self.field[::stride, ::stride], truncation)
            self._coarse[key] = np.pad(sub, pad, constant_values=truncation).astype(np.float32)
        return self._coarse[key]

    def nearest_segment(self, points: np.ndarray) -> np.ndarray:
        """Index of the nearest map segment at every point (nearest node); -1 off the grid."""
        pts = np.ascontiguousarray(points, dtype=np.float64)
        k = field_nearest(self.segment_index, self.x0, self.y0, self.resolution, pts.reshape(-1, 2))
        return k.reshape(pts.shape[:-1])


def map_segments(global_map: GlobalMap, params: FieldParams) -> np.ndarray:
    """The segments a laser can see: walls, and per the config objects and closed doors.

    Walls come first, so index k < len(global_map.walls) is wall k of the map; doors last.
    """
    parts = [global_map.wall_segments]
    if params.objects_as_walls:
        parts += [global_map.segments_of(p) for p in global_map.objects]
    if params.doors_as_walls:
        parts += [global_map.segments_of(p) for p in global_map.doors]
    return np.vstack(parts)
