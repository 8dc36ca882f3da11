"""The simulated world: the map's solid geometry, its sliding doors and the moving objects.

Everything solid is a line segment (x1, y1, x2, y2) in the map frame: walls (or a heightmap's
vectorised outlines), the edges of cabinets/tables, the outlines of doors where they are now,
and the outlines of moving objects where they are now. `segments()` returns them all in that
order, with `kinds()` saying which is which; the laser and the collision checks both use it.
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from pico_studio.config.sim_params import SimParams
from pico_studio.json_map import GlobalMap
from pico_studio.json_map.openings import cast_rays
from pico_studio.sim.doors import SlidingDoor
from pico_studio.sim.moving_objects import MovingObject
from pico_studio.sim.sim_config import SimConfigFile

KIND_WALL, KIND_OBJECT, KIND_DOOR, KIND_MOVING = 0, 1, 2, 3
KIND_NAMES = ("wall", "object", "door", "moving object")


class World:
    def __init__(self, global_map: GlobalMap, params: SimParams, sim_config: SimConfigFile | None = None):
        self.map = global_map
        self.params = params
        self.walls = global_map.wall_segments
        objects = [global_map.segments_of(p) for p in global_map.objects]
        self.objects = np.vstack(objects) if objects else np.zeros((0, 4))
        self.static = np.vstack([self.walls, self.objects])
        greys = _door_greys(global_map)
        self.doors = [SlidingDoor(v, g) for v, g in zip(global_map.door_polygons, greys, strict=True)]
        specs = sim_config.objects if sim_config is not None else ()
        self.moving = [
            MovingObject(s, pause_margin=params.objects.pause_margin, arrive_tolerance=params.objects.arrive_tolerance)
            for s in specs
        ]
        self._cache: np.ndarray | None = None
        self._kinds: np.ndarray | None = None
        self.version = 0  # bumped whenever a door or object moves

    # ----- geometry as it is now ----------------------------------------------------------
    def segments(self) -> np.ndarray:
        """All solid segments now (static, then doors, then moving objects), (N, 4)."""
        if self._cache is None:
            parts = [self.static] + [d.segments() for d in self.doors] + [m.segments() for m in self.moving]
            self._cache = np.vstack(parts)
        return self._cache

    def kinds(self) -> np.ndarray:
        """KIND_* of every row of `segments()`."""
        if self._kinds is None:
            parts = [
                np.full(len(self.walls), KIND_WALL),
                np.full(len(self.objects), KIND_OBJECT),
                *[np.full(len(d.vertices), KIND_DOOR) for d in self.doors],
                *[np.full(4, KIND_MOVING) for _ in self.moving],
            ]
            self._kinds = np.concatenate(parts).astype(np.int8)
        return self._kinds

    # ----- dynamics -------------------------------------------------------------------------
    def update(self, dt: float, robot_xy: tuple[float, float]) -> None:
        """Move doors and objects on by `dt` seconds."""
        if not self.doors and not self.moving:
            return
        changed = False
        for d in self.doors:
            if d.moving:
                d.update(dt, self.params.doors.speed)
                changed = True
        for m in self.moving:
            before = m.pos.copy()
            m.update(dt, robot_xy)
            changed = changed or bool((m.pos != before).any())
        if changed:
            self._cache = None
            self.version += 1

    def request_open_door(self, robot_xy: tuple[float, float]) -> bool:
        """Open every closed door the robot is in front of; True if one started opening."""
        opened = False
        for d in self.doors:
            opened = d.request_open(robot_xy, self.params.doors.open_distance) or opened
        return opened

    # ----- free space ---------------------------------------------------------------------
    def enclosed(self, xy: tuple[float, float], rays: int = 16) -> bool:
        """True when rays in `rays` directions from xy all hit something: inside the walls."""
        angles = np.arange(rays) * (2 * math.pi / rays)
        return bool(np.isfinite(cast_rays(xy, angles, self.segments())).all())

    def farthest_free_place(self, clearance: float) -> tuple[float, float] | None:
        """The point of a grid (spacing `start_grid`) inside the walls that is farthest from
        every solid segment, if that distance is at least `clearance`; ties go to the lowest x,
        then the lowest y (deterministic). None when there is no such place.

        The segments are drawn into an image (with a free margin around the map);
        OpenCV's distance transform gives every grid point's clearance, and the free space's
        4-connected components tell inside from outside: the component of the margin is
        outside. Candidates are taken farthest first until one is enclosed (rays in every
        direction hit something) and its exact clearance is enough. A map whose outer wall
        is open has no inside component; then every free point is a candidate."""
        x0, y0, x1, y1 = self.map.bounds
        step = self.params.start_grid
        pad = 2
        w, h = int(math.ceil((x1 - x0) / step)) + 1 + 2 * pad, int(math.ceil((y1 - y0) / step)) + 1 + 2 * pad
        if w < 2 * pad + 2 or h < 2 * pad + 2:
            return None
        ox, oy = x0 - pad * step, y0 - pad * step  # the map point of pixel (0, 0)
        segs = self.segments()
        img = np.full((h, w), 255, np.uint8)
        pix = np.round((segs - (ox, oy, ox, oy)) / step).astype(np.int32)
        for a, b, c, d in pix:
            cv2.line(img, (int(a), int(b)), (int(c), int(d)), 0, 1)
        dist = cv2.distanceTransform(img, cv2.DIST_L2, cv2.DIST_MASK_PRECISE) * step
        _, labels = cv2.connectedComponents(img, connectivity=4)
        ok = dist >= clearance
        inside = ok & (labels != labels[0, 0])
        rows, cols = np.nonzero(inside if inside.any() else ok)
        if len(rows) == 0:
            return None
        order = np.lexsort((rows, cols, -dist[rows, cols]))
        for k in order[:_MAX_START_CANDIDATES]:
            p = (ox + float(cols[k]) * step, oy + float(rows[k]) * step)
            if self.enclosed(p) and _distance_to_segments(np.array([p]), segs)[0] >= clearance:
                return p
        return None


_MAX_START_CANDIDATES = 2000  # bounds the search on an open map (no inside component)


def _door_greys(m: GlobalMap) -> list[int | None]:
    """Each door's grey value when the map is a heightmap that recorded them, else None."""
    info = m.extra.get("heightmap")
    greys = info.get("door_grey") if isinstance(info, dict) else None
    if not isinstance(greys, list) or len(greys) != len(m.doors):
        return [None] * len(m.doors)
    return [g if isinstance(g, int) and not isinstance(g, bool) else None for g in greys]


def _distance_to_segments(points: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """Distance from every point to its nearest segment."""
    a = segments[:, 0:2]
    ab = segments[:, 2:4] - a
    denom = np.maximum((ab**2).sum(1), 1e-18)
    p = points[:, None, :]
    t = np.clip(((p - a) * ab).sum(-1) / denom, 0.0, 1.0)
    d = p - (a + t[..., None] * ab)
    return np.sqrt((d**2).sum(-1).min(axis=1))
