"""Rasterising a `GlobalMap` into an occupancy / heightmap image.

    from pico_studio.json_map.raster import rasterise
    r = rasterise(m)                       # map_server frame covering the map, 0.025 m/px
    r.image                                # (H, W) uint8: 0 wall/object, 128 door, 255 free
    r.frame.to_pixel(xy), r.frame.to_world(uv), r.frame.origin   # see grid.GridFrame
    r = rasterise(m, frame=other.frame)    # into a given frame (e.g. an original image's)

The image is what the emc simulator reads: walls and cabinets/tables black (0), closed
doors grey (128), free white (255). How walls are drawn depends on what they are:

- hand-written JSON walls are zero-thickness lines: drawn `wall_thickness` px wide; but a
  closed loop of them no wider than `solid_loop_width` (twice its area over its perimeter) is
  a solid wall drawn as its outline (a generated world's walls, a thick wall in a hand-made
  map): filled, its edge one pixel, so it comes out solid with square corners rather than
  as two lines with a free pixel between them and notched where they meet;
- walls vectorised from a heightmap (the map has `"heightmap": {"walls": "outlines"}`)
  are the outlines of solid blobs: their closed loops are filled even-odd (a ring of
  walls around a room stays a ring), plus a one-pixel line so slivers survive.

Cabinets/tables are filled; door polygons are filled grey. Pixel (c, r)'s centre is
(c + 0.5, r + 0.5) in the frame's continuous coordinates; OpenCV draws with 1/16-pixel
fixed-point coordinates so polygons land where the frame says.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from pico_studio.config.map_params import RasterParams
from pico_studio.json_map.grid import GridFrame
from pico_studio.json_map.image_header import check_raster_size
from pico_studio.json_map.model import GlobalMap, cycle_vertices
from pico_studio.json_map.model import wall_loops as closed_wall_groups

FREE = 255
DOOR = 128
OCCUPIED = 0
_SHIFT = 4  # OpenCV fixed-point bits: coordinates in 1/16 px


@dataclass
class Raster:
    """An occupancy image and where it lies in the world."""

    image: np.ndarray  # (H, W) uint8: OCCUPIED 0, DOOR 128, FREE 255
    frame: GridFrame

    @property
    def occupied(self) -> np.ndarray:
        return self.image == OCCUPIED

    @property
    def doors(self) -> np.ndarray:
        return self.image == DOOR

    @property
    def origin(self) -> tuple[float, float]:
        """World (x, y) of the bottom-left corner: the map_server YAML origin."""
        return self.frame.origin

    @property
    def resolution(self) -> float:
        return self.frame.resolution


def walls_are_outlines(m: GlobalMap) -> bool:
    """True when the walls are the outlines of solid blobs (a map vectorised from an image)."""
    info = m.extra.get("heightmap")
    return isinstance(info, dict) and info.get("walls") == "outlines"


def recorded_frame(m: GlobalMap) -> GridFrame | None:
    """The frame of the image a map was vectorised from, when the map records it."""
    info = m.extra.get("heightmap")
    return GridFrame.from_dict(info) if isinstance(info, dict) else None


def frame_for(m: GlobalMap, resolution: float | None = None, params: RasterParams | None = None) -> GridFrame:
    """A map_server frame covering every point of the map plus `params.margin`."""
    params = params or RasterParams()
    res = resolution if resolution is not None else params.resolution
    pts = m.points[m.used_point_indices()] if len(m.points) else np.zeros((1, 2))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    check_raster_size(*(hi - lo + 2 * params.margin), res, file=m.source)  # before allocating it
    return GridFrame.covering((lo[0], lo[1], hi[0], hi[1]), res, params.margin)


def rasterise(
    m: GlobalMap,
    frame: GridFrame | None = None,
    *,
    resolution: float | None = None,
    params: RasterParams | None = None,
    doors: bool = True,
) -> Raster:
    """Draw the map into an image; `frame` defaults to `frame_for(m, resolution, params)`."""
    params = params or RasterParams()
    if frame is None:
        frame = frame_for(m, resolution, params)
    img = np.full(frame.shape, FREE, dtype=np.uint8)

    def px(xy: np.ndarray) -> np.ndarray:
        uv = frame.to_pixel(xy) - 0.5  # OpenCV's integer coordinates are pixel centres
        return np.round(uv * (1 << _SHIFT)).astype(np.int32)

    if doors and m.doors:
        cv2.fillPoly(img, [px(p) for p in m.door_polygons], DOOR, cv2.LINE_8, _SHIFT)

    loops = wall_loops(m.walls) if walls_are_outlines(m) else None
    if loops is not None:
        polys = [px(m.points[loop]) for loop in loops]
        cv2.fillPoly(img, polys, OCCUPIED, cv2.LINE_8, _SHIFT)
        cv2.polylines(img, polys, True, OCCUPIED, 1, cv2.LINE_8, _SHIFT)
    else:
        solid, rest = solid_loops(m, params.solid_loop_width)
        if solid:
            polys = [px(m.points[loop]) for loop in solid]
            cv2.fillPoly(img, polys, OCCUPIED, cv2.LINE_8, _SHIFT)
            cv2.polylines(img, polys, True, OCCUPIED, 1, cv2.LINE_8, _SHIFT)
        bands = wall_bands(m.wall_segments[rest], params.wall_thickness * frame.resolution / 2)
        for band in bands:  # one by one: fillPoly's even-odd rule would clear where two overlap
            cv2.fillConvexPoly(img, px(band), OCCUPIED, cv2.LINE_8, _SHIFT)

    if m.objects:
        polys = [px(p) for p in m.object_polygons]
        cv2.fillPoly(img, polys, OCCUPIED, cv2.LINE_8, _SHIFT)
    return Raster(img, frame)


def wall_bands(segs: np.ndarray, half: float) -> np.ndarray:
    """Each zero-thickness wall as the rectangle (N, 4, 2) it is drawn as: `half` either side
    of it, lengthened by `half` at an end it shares with another wall (the same point) so two
    walls meeting at a corner fill its square, and cut square at a free end (a doorway keeps
    its width; a thick line's round caps would notch the corner and bulge into the door)."""
    if len(segs) == 0:
        return np.zeros((0, 4, 2))
    ends = segs.reshape(-1, 2)
    _, inverse, counts = np.unique(
        np.round(ends / 1e-6).astype(np.int64), axis=0, return_inverse=True, return_counts=True
    )
    joined = (counts[inverse.reshape(-1)] >= 2).reshape(-1, 2)
    d = segs[:, 2:] - segs[:, :2]
    length = np.hypot(d[:, 0], d[:, 1])
    u = np.where(length[:, None] > 1e-12, d / np.maximum(length, 1e-12)[:, None], [1.0, 0.0])
    n = np.stack([-u[:, 1], u[:, 0]], axis=1) * half
    a = segs[:, :2] - half * joined[:, :1] * u
    b = segs[:, 2:] + half * joined[:, 1:] * u
    return np.stack([a + n, b + n, b - n, a - n], axis=1)


def solid_loops(m: GlobalMap, max_width: float) -> tuple[list[np.ndarray], np.ndarray]:
    """The closed loops of a JSON map's walls that are solid walls drawn as their outlines
    (mean width 2 A / L at most `max_width`: a room's ring of walls is far wider), as point
    indices in order, and the rows of the other walls."""
    rest = np.ones(len(m.walls), dtype=bool)
    loops: list[np.ndarray] = []
    if max_width <= 0:
        return loops, np.flatnonzero(rest)
    for group in closed_wall_groups(m.walls):
        order = cycle_vertices(m.walls[group])
        if order is None:
            continue
        xy = m.points[order]
        x, y = xy[:, 0], xy[:, 1]
        area = 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))
        perimeter = float(np.hypot(*(np.roll(xy, -1, axis=0) - xy).T).sum())
        if perimeter > 0 and 2 * area / perimeter <= max_width:
            loops.append(order)
            rest[group] = False
    return loops, np.flatnonzero(rest)


def wall_loops(walls: np.ndarray) -> list[np.ndarray] | None:
    """The walls as disjoint closed loops of point indices, or None when they are not
    (every point must be used by exactly two walls)."""
    if len(walls) == 0:
        return None
    nbrs: dict[int, list[int]] = {}
    for a, b in walls.tolist():
        nbrs.setdefault(a, []).append(b)
        nbrs.setdefault(b, []).append(a)
    if any(len(v) != 2 for v in nbrs.values()):
        return None
    loops: list[np.ndarray] = []
    seen: set[int] = set()
    for start in nbrs:
        if start in seen:
            continue
        loop = [start]
        seen.add(start)
        prev, cur = start, nbrs[start][0]
        while cur != start:
            if cur in seen:
                return None
            loop.append(cur)
            seen.add(cur)
            a, b = nbrs[cur]
            prev, cur = cur, (b if a == prev else a)
        loops.append(np.array(loop, dtype=np.int64))
    return loops
