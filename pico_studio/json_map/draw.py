"""A picture of a `GlobalMap` for people (OpenCV): what `pico-studio map info --png` draws.

Walls black (outlines of a vectorised heightmap filled dark grey), cabinets/tables filled
blue with their front segment in thick red and their index, doors orange, the start area
green, a metre grid with labels, a 1 m scale bar and a title line. x to the right, y up.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import cv2
import numpy as np

from pico_studio.errors import MapError
from pico_studio.json_map.grid import GridFrame
from pico_studio.json_map.model import GlobalMap
from pico_studio.json_map.raster import wall_loops, walls_are_outlines

# BGR colours
_GRID = (225, 225, 225)
_GRID_TEXT = (150, 150, 150)
_WALL = (0, 0, 0)
_SOLID = (90, 90, 90)
_OBJECT_FILL = (235, 200, 160)
_OBJECT_EDGE = (160, 90, 30)
_FRONT = (0, 0, 220)
_DOOR_FILL = (80, 170, 255)
_DOOR_EDGE = (0, 110, 230)
_START_FILL = (200, 240, 200)
_START_EDGE = (40, 150, 40)
_TEXT = (40, 40, 40)
_FONT = cv2.FONT_HERSHEY_SIMPLEX
_TOP = 28  # px reserved for the title line


def draw_map(m: GlobalMap, *, max_size: int = 900, margin_m: float = 0.5, title: str = "") -> np.ndarray:
    """The map drawn into a BGR image whose longer side is at most `max_size` px."""
    pts = m.points[m.used_point_indices()] if len(m.points) else np.zeros((1, 2))
    lo, hi = pts.min(axis=0) - margin_m, pts.max(axis=0) + margin_m
    span = float(max(hi - lo))
    px_per_m = max(10.0, min(200.0, (max_size - _TOP) / max(span, 1e-6)))
    res = 1.0 / px_per_m
    w = int(math.ceil((hi[0] - lo[0]) * px_per_m))
    h = int(math.ceil((hi[1] - lo[1]) * px_per_m))
    frame = GridFrame.map_server((h, w), res, (float(lo[0]), float(lo[1])))
    img = np.full((h + _TOP, w, 3), 255, np.uint8)
    body = img[_TOP:]

    def px(xy: np.ndarray) -> np.ndarray:
        return np.round(frame.to_pixel(np.asarray(xy).reshape(-1, 2)) - 0.5).astype(np.int32)

    _grid(body, frame, px)
    for poly in m.start_polygons:
        cv2.fillPoly(body, [px(poly)], _START_FILL)
        cv2.polylines(body, [px(poly)], True, _START_EDGE, 2, cv2.LINE_AA)
        c = px(poly.mean(axis=0))[0]
        cv2.putText(body, "start", (int(c[0]) - 16, int(c[1]) + 4), _FONT, 0.4, _START_EDGE, 1, cv2.LINE_AA)
    for poly in m.door_polygons:
        cv2.fillPoly(body, [px(poly)], _DOOR_FILL)
        cv2.polylines(body, [px(poly)], True, _DOOR_EDGE, 1, cv2.LINE_AA)
    loops = wall_loops(m.walls) if walls_are_outlines(m) else None
    if loops is not None:
        cv2.fillPoly(body, [px(m.points[lp]) for lp in loops], _SOLID)
    for x1, y1, x2, y2 in m.wall_segments:
        a, b = px([x1, y1])[0], px([x2, y2])[0]
        cv2.line(body, (int(a[0]), int(a[1])), (int(b[0]), int(b[1])), _WALL, 2, cv2.LINE_AA)
    for k, (poly, front) in enumerate(zip(m.object_polygons, m.object_fronts, strict=True)):
        cv2.fillPoly(body, [px(poly)], _OBJECT_FILL)
        cv2.polylines(body, [px(poly)], True, _OBJECT_EDGE, 2, cv2.LINE_AA)
        a, b = px(front[:2])[0], px(front[2:])[0]
        cv2.line(body, (int(a[0]), int(a[1])), (int(b[0]), int(b[1])), _FRONT, 4, cv2.LINE_AA)
        c = px(poly.mean(axis=0))[0]
        cv2.putText(body, str(k), (int(c[0]) - 5, int(c[1]) + 5), _FONT, 0.5, _OBJECT_EDGE, 1, cv2.LINE_AA)
    _scale_bar(body, px_per_m)
    counts = ", ".join(f"{v} {k}" for k, v in m.counts().items() if v)
    ex, ey = m.extent
    text = f"{title}  {counts}  {ex:.2f} x {ey:.2f} m".strip()
    cv2.putText(img, text, (6, 19), _FONT, 0.45, _TEXT, 1, cv2.LINE_AA)
    return img


def _grid(body: np.ndarray, frame: GridFrame, px: Callable[[object], np.ndarray]) -> None:
    x0, y0, x1, y1 = frame.world_bounds
    for x in range(math.ceil(x0), math.floor(x1) + 1):
        a, b = px([x, y0])[0], px([x, y1])[0]
        cv2.line(body, (int(a[0]), 0), (int(b[0]), body.shape[0]), _GRID, 1)
        cv2.putText(body, f"{x}", (int(a[0]) + 2, body.shape[0] - 4), _FONT, 0.35, _GRID_TEXT, 1, cv2.LINE_AA)
    for y in range(math.ceil(y0), math.floor(y1) + 1):
        a = px([x0, y])[0]
        cv2.line(body, (0, int(a[1])), (body.shape[1], int(a[1])), _GRID, 1)
        cv2.putText(body, f"{y}", (2, int(a[1]) - 2), _FONT, 0.35, _GRID_TEXT, 1, cv2.LINE_AA)


def _scale_bar(body: np.ndarray, px_per_m: float) -> None:
    h, w = body.shape[:2]
    length = int(round(px_per_m))
    x1, y = w - 12, h - 14
    x0 = max(4, x1 - length)
    cv2.line(body, (x0, y), (x1, y), _TEXT, 3)
    cv2.putText(body, "1 m", (x0, y - 6), _FONT, 0.4, _TEXT, 1, cv2.LINE_AA)


def save_png(image: np.ndarray, path: str) -> None:
    """Write a drawn map; raises MapError when the file cannot be written."""
    ok, data = cv2.imencode(".png", image, [cv2.IMWRITE_PNG_COMPRESSION, 9])
    try:
        if not ok:  # pragma: no cover
            raise OSError("encoding failed")
        with open(path, "wb") as f:
            f.write(data.tobytes())
    except OSError as e:
        raise MapError(f"cannot write: {e.strerror or e}", file=path) from None
