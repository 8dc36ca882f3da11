"""A reference map from a replay's true poses: every scan's beams cast from where the robot was.

For a log whose true poses are known (a CARMEN *corrected* log, a recorded simulation) the
scans placed at those poses draw the building as the laser saw it. The reference is an
occupancy grid of `resolution` cells: a cell is occupied when beams ended in it at least
`min_hits` times and more often than they passed through it (`ray_step` samples along each
beam, so a person who walked by is carved away again by later beams). The distance to the
nearest occupied cell (a distance transform) is what `agreement` asks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from pico_studio.core.geometry import transform_points

Pose = tuple[float, float, float]


_OFF = 1 << 20  # cell keys: (y + _OFF) * 2^21 + (x + _OFF), any building fits


class _CellCounts:
    """Counts per grid cell, kept compact by merging the pending keys now and then."""

    def __init__(self) -> None:
        self.keys = np.zeros(0, np.int64)
        self.counts = np.zeros(0, np.int64)
        self._pending: list[np.ndarray] = []
        self._size = 0

    def add(self, keys: np.ndarray) -> None:
        self._pending.append(keys)
        self._size += len(keys)
        if self._size > 2_000_000:
            self.compact()

    def compact(self) -> None:
        if not self._pending:
            return
        new_k, new_c = np.unique(np.concatenate(self._pending), return_counts=True)
        k = np.concatenate([self.keys, new_k])
        c = np.concatenate([self.counts, new_c])
        self.keys, inv = np.unique(k, return_inverse=True)
        self.counts = np.bincount(inv, weights=c).astype(np.int64)
        self._pending, self._size = [], 0

    def lookup(self, keys: np.ndarray) -> np.ndarray:
        """(K,) the count of each key (0 for a key never added); compact first."""
        if len(self.keys) == 0:
            return np.zeros(len(keys), np.int64)
        pos = np.minimum(np.searchsorted(self.keys, keys), len(self.keys) - 1)
        return np.where(self.keys[pos] == keys, self.counts[pos], 0)


@dataclass
class ReferenceMap:
    """Accumulates scans (robot-frame points + true pose), then answers distances."""

    resolution: float = 0.05  # m per cell
    min_hits: int = 2  # beams ending in a cell before it is a wall
    ray_step: float = 0.1  # m between free-space samples along a beam
    free_margin: float = 0.15  # m: free samples stop this short of the beam's end

    def __post_init__(self) -> None:
        self._hits = _CellCounts()
        self._free = _CellCounts()  # scans whose beams passed through the cell
        self._dist: np.ndarray | None = None
        self._origin = (0.0, 0.0)  # world position of grid cell (0, 0) once built
        self._occupied = np.zeros((1, 1), bool)

    def _keys(self, world: np.ndarray) -> np.ndarray:
        c = np.floor(world / self.resolution).astype(np.int64) + _OFF
        return c[:, 1] * (2 * _OFF) + c[:, 0]

    def add_scan(self, points: np.ndarray, pose: Pose) -> None:
        """points (M, 2) in the robot frame (the laser's valid end points), pose its truth."""
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        if len(points) == 0:
            return
        world = transform_points(points, pose)
        self._hits.add(self._keys(world))
        r = np.hypot(points[:, 0], points[:, 1])
        # free space: samples every ray_step from the robot to free_margin short of the end,
        # each cell counted once per scan
        k = np.arange(1, int(math.ceil(float(r.max()) / self.ray_step)) + 1) * self.ray_step
        ok = k[None, :] < (r[:, None] - self.free_margin)
        frac = k[None, :] / np.maximum(r[:, None], 1e-9)
        origin = np.array(pose[:2])
        free = origin + frac[..., None] * (world[:, None, :] - origin)
        self._free.add(np.unique(self._keys(free[ok])))
        self._dist = None

    def _build(self) -> None:
        self._hits.compact()
        self._free.compact()
        strong = self._hits.counts >= self.min_hits
        keys = self._hits.keys[strong]
        keys = keys[self._hits.counts[strong] > self._free.lookup(keys)]
        if len(keys) == 0:
            self._dist = np.full((1, 1), np.inf, np.float32)
            self._occupied = np.zeros((1, 1), bool)
            return
        cx = keys % (2 * _OFF) - _OFF
        cy = keys // (2 * _OFF) - _OFF
        pad = 20
        x0, y0 = int(cx.min()) - pad, int(cy.min()) - pad
        w, h = int(cx.max()) - x0 + pad + 1, int(cy.max()) - y0 + pad + 1
        occupied = np.zeros((h, w), bool)
        occupied[cy - y0, cx - x0] = True
        self._occupied = occupied
        self._origin = (x0 * self.resolution, y0 * self.resolution)
        img = np.where(occupied, 0, 255).astype(np.uint8)
        self._dist = cv2.distanceTransform(img, cv2.DIST_L2, 5).astype(np.float32) * self.resolution

    def _cells(self, pts: np.ndarray) -> np.ndarray:
        return np.floor((np.asarray(pts) - self._origin) / self.resolution).astype(np.int64)

    def distance(self, pts: np.ndarray) -> np.ndarray:
        """(N,) distance (m) from each world point to the nearest reference wall (inf off the grid)."""
        if self._dist is None:
            self._build()
        assert self._dist is not None
        pts = np.asarray(pts, dtype=float).reshape(-1, 2)
        c = self._cells(pts)
        h, w = self._dist.shape
        ok = (c[:, 0] >= 0) & (c[:, 0] < w) & (c[:, 1] >= 0) & (c[:, 1] < h)
        out = np.full(len(pts), np.inf)
        out[ok] = self._dist[c[ok, 1], c[ok, 0]]
        return out

    def wall_points(self) -> np.ndarray:
        """(K, 2) centres of the occupied cells, world frame: the layer the page draws."""
        if self._dist is None:
            self._build()
        ys, xs = np.nonzero(self._occupied)
        return (np.column_stack([xs, ys]) + 0.5) * self.resolution + self._origin
