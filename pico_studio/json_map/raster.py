"""Rasterising a `GlobalMap` into an occupancy / heightmap image.

    from pico_studio.json_map.raster import rasterise
    r = rasterise(m)                       # map_server frame covering the map, 0.025 m/px
    r.image                                # (H, W) uint8: 0 wall/object, 128 door, 255 free
    r.frame.to_pixel(xy), r.frame.to_world(uv), r.frame.origin   # see grid.GridFrame
    r = rasterise(m, frame=other.frame)    # into a given frame (e.g. an original image's)

The image is what the emc simulator reads: walls and cabinets/tables black (0), closed
doors grey (128), free white (255). How walls are drawn depends on what they are:

- hand-written JSON walls are zero-thickness lines: drawn `wall_thickness` px wide;
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
from pico_studio.json_map.model import GlobalMap

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
        segs = m.wall_segments
        a, b = px(segs[:, :2]), px(segs[:, 2:])
        lines = [np.stack([a[k], b[k]]) for k in range(len(segs))]
        cv2.polylines(img, lines, False, OCCUPIED, params.wall_thickness, cv2.LINE_8, _SHIFT)

    if m.objects:
        polys = [px(p) for p in m.object_polygons]
        cv2.fillPoly(img, polys, OCCUPIED, cv2.LINE_8, _SHIFT)
    return Raster(img, frame)


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
