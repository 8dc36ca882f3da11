"""Ground truth beside the robot interface: where the robot really is and what it really sees.

`sim.truth` is never reachable through the `RobotIO` methods. Everything is in the map frame
and refers to the robot's pose now (the visible-wall pieces to the latest scan).

Visibility, two definitions (each method says which it uses):
- *hit*: a wall is visible where beams of the latest scan actually hit it (noise-free): each
  run of at least `min_wall_beams` consecutive beams on one segment is one visible piece,
  from the first to the last hit point (so a piece is shorter than the truth by less than a
  beam spacing at each end);
- *in view*: a point (corner) is visible when it lies within the laser's range and
  field of view and the ray from the laser to it is not blocked more than `visible_tolerance`
  before it.

A door opening is visible when beams of the latest scan (noise-free) hit the wall at each of
its jambs over at least `jamb_min_seen` (counted within `jamb_reach` of the jamb), its
middle is *in view* (doors themselves, open or closed, do not occlude), and no door leaf is
shut across it (its middle outside every door's outline as the door is now) — so a jamb
whose single corner peeks into view does not make a door visible, and a closed door, which
to a laser is a piece of wall, is not an opening it could see.

End points: the vertices a seen wall end may lie on are the static geometry's
(`static_vertices` of the scorer) and `dynamic_vertices()`, the corners of the door leaves
and moving objects where they are now (a standing box's corner, a closed door's ends against
its jambs are real corners).

Corners are those of the static geometry (walls, cabinets/tables), classified convex/concave
as seen from the robot (see `map_features`); door openings are the map's own
(`GlobalMap.openings`: its doors, the gaps between wall ends of a door's width, and passage
mouths), the ones the combined map confirms doors against.

The truth is given the parts of the simulator it reads (world, base, laser, odometry and the
truth parameters), so `sim.truth` does not import `sim.simulator`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import cached_property
from typing import Any, NamedTuple, TypeVar, cast

import cv2
import numpy as np

from pico_studio.config.sim_params import TruthParams
from pico_studio.json_map.model import GlobalMap
from pico_studio.json_map.openings import Vertices, vertex_graph
from pico_studio.json_map.raster import recorded_frame, walls_are_outlines
from pico_studio.sim.base import Base, CollisionEvent
from pico_studio.sim.laser import Laser
from pico_studio.sim.map_features import classify_corners
from pico_studio.sim.odometry import Odometry
from pico_studio.sim.truth_kernels import (
    beam_ends,
    corners_in_view,
    hit_runs,
    in_view,
    jamb_seen_lengths,
)
from pico_studio.sim.world import KIND_DOOR, World

Pose = tuple[float, float, float]
T = TypeVar("T")


def abut_tolerance(m: GlobalMap, tolerance: float) -> float:
    """How close a vertex lies to another segment to abut it, in this map: `tolerance`, plus a
    pixel where the walls are the outlines of a heightmap image's blobs (a table 3 cm off a wall
    is drawn 1 or 2 pixels off it, its outline and the wall's up to 5 cm apart at 0.025 m/px)."""
    frame = recorded_frame(m) if walls_are_outlines(m) else None
    return tolerance + (frame.resolution if frame is not None else 0.0)


class Corners(NamedTuple):
    points: np.ndarray  # (C, 2) map frame
    convex: np.ndarray  # (C,) bool, as seen from the robot
    loose_end: np.ndarray  # (C,) bool: the free end of a thin wall (always convex)


class GroundTruth:
    def __init__(self, world: World, base: Base, laser: Laser, odometry: Odometry, params: TruthParams):
        self._world, self._base, self._laser, self._odometry = world, base, laser, odometry
        self._params = params
        self._scan_cache: dict[str, tuple[int, Any]] = {}  # per-scan answers, by the laser's scan count

    @property
    def pose(self) -> Pose:
        """The robot's true pose (x, y, a) in the map frame."""
        return self._base.pose

    @property
    def collisions(self) -> int:
        """How many times the robot ran into something (one per contact)."""
        return len(self._base.collisions)

    @property
    def collision_events(self) -> list[CollisionEvent]:
        return list(self._base.collisions)

    @property
    def in_contact(self) -> bool:
        return self._base.in_contact

    @property
    def distance(self) -> float:
        """True path length travelled, metres."""
        return self._base.distance

    @property
    def odometry_pose(self) -> Pose:
        """The odometry's current pose in its own frame (whatever the reading form)."""
        return self._odometry.pose

    def segments(self) -> np.ndarray:
        """Every solid segment of the world as it is now (walls, objects, doors, moving objects)."""
        return self._world.segments().copy()

    def doors(self) -> list[tuple[np.ndarray, bool]]:
        """Every sliding door as it is now: (outline vertices (K, 2), opened?)."""
        return [(d.vertices + d.offset * d.slide, d.opening) for d in self._world.doors]

    def moving_objects(self) -> list[np.ndarray]:
        """Every moving object's box as it is now: corners (4, 2)."""
        return [m.corners() for m in self._world.moving]

    def scan_hits(self) -> tuple[np.ndarray, np.ndarray]:
        """Noise-free ranges of the latest scan and the world segment index each beam hit (-1: none)."""
        return self._laser.true_ranges.copy(), self._laser.true_hits.copy()

    # ----- what the robot sees --------------------------------------------------------------
    def visible_walls(self) -> np.ndarray:
        """(N, 4) the visible pieces of solid segments in the latest scan (*hit* visibility)."""
        return self._visible_pieces()[0].copy()

    def visible_wall_sources(self) -> np.ndarray:
        """(N,) for each row of `visible_walls()`: the index into `segments()` it is a piece of
        (`sim.world.kinds()` says wall, object, door or moving object)."""
        return self._visible_pieces()[1].copy()

    def visible_corners(self) -> Corners:
        """Corners of the static geometry *in view* from the robot, convex/concave from there."""
        idx, convex, loose = classify_corners(self._graph, self.pose[:2], self._params.straight_tolerance)
        # `_in_view` of `_graph.points[idx]` and the selection, as one compiled call
        pts, convex, loose = corners_in_view(np.ascontiguousarray(self._graph.points, dtype=np.float64), idx, convex, loose,
                                             *self._view(), self._c4(self._world.segments()), float(self._params.visible_tolerance))
        return Corners(pts, convex, loose)

    def door_openings(self) -> np.ndarray:
        """(D, 4) every door opening of the map, jamb to jamb (`GlobalMap.openings`)."""
        return self._openings.copy()

    def visible_doors(self) -> np.ndarray:
        """(D, 4) door openings seen in the latest scan: beams hit the wall at each jamb over
        at least `jamb_min_seen`, and the middle is *in view* (doors do not occlude)."""
        o = self._openings
        if len(o) == 0:
            return o.copy()
        middles, jambs, not_door = self._opening_points
        seen = self._in_view(middles, self._world.segments()[not_door])
        if not seen.any():  # (then neither their jambs nor the door leaves matter)
            return o[seen]
        # the jambs of openings whose middle is out of view cannot make them visible
        both = np.concatenate([seen, seen])
        seen_length = np.zeros(len(jambs))
        seen_length[both] = self.jamb_seen_length(jambs[both])
        seen &= (seen_length[: len(o)] >= self._params.jamb_min_seen) & (seen_length[len(o):] >= self._params.jamb_min_seen)
        seen &= ~self._shut(middles)
        return o[seen]

    def _shut(self, points: np.ndarray) -> np.ndarray:
        """(P,) bool: the point lies inside a door leaf's outline as the door is now."""
        out = np.zeros(len(points), dtype=bool)
        for outline, _ in self.doors():
            poly = np.asarray(outline, dtype=np.float32).reshape(-1, 1, 2)
            out |= np.array([cv2.pointPolygonTest(poly, (float(x), float(y)), False) >= 0 for x, y in points], dtype=bool)
        return out

    def dynamic_vertices(self) -> np.ndarray:
        """(K, 2) the corners of the door leaves and the moving objects where they are now
        (the static geometry's corners are the scorer's `static_vertices`)."""
        parts = [np.asarray(v, dtype=float).reshape(-1, 2) for v, _ in self.doors()] + self.moving_objects()
        return np.vstack(parts) if parts else np.zeros((0, 2))

    def jamb_seen_length(self, jambs: np.ndarray) -> np.ndarray:
        """(J,) for each jamb point: how long a stretch of the walls touching it (within
        `max_wall_thickness / 2`: a thin wall's end, or a thick wall's end cap and the faces
        next to it) the latest scan's beams hit, within `jamb_reach` of the jamb — per wall
        segment from its first to its last hit point, summed over the segments (one compiled
        loop: `truth_kernels.jamb_seen_lengths`; walls come first in `world.segments()`)."""
        t = self._params
        jambs = np.ascontiguousarray(jambs, dtype=np.float64).reshape(-1, 2)
        return jamb_seen_lengths(jambs, *self._scan(), self._walls, self._world.map.opening_params.max_wall_thickness / 2 + 1e-3, float(t.jamb_reach))

    @cached_property
    def _walls(self) -> np.ndarray:
        return np.ascontiguousarray(self._world.walls, dtype=np.float64).reshape(-1, 4)

    @cached_property
    def _opening_points(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The openings' middles (D, 2) and jambs (2 D, 2: first ends, then second ends), and
        which rows of `world.segments()` are not doors (fixed per world): per map, not per frame."""
        o = self._openings
        middles = np.ascontiguousarray((o[:, :2] + o[:, 2:]) / 2)
        return middles, np.ascontiguousarray(np.concatenate([o[:, :2], o[:, 2:]])), self._world.kinds() != KIND_DOOR

    @cached_property
    def _graph(self) -> Vertices:
        return vertex_graph(self._world.static, abut=abut_tolerance(self._world.map, self._params.abut_tolerance))

    @cached_property
    def _openings(self) -> np.ndarray:
        return self._world.map.openings()

    def _in_fov(self, points: np.ndarray) -> np.ndarray:
        """Within the laser's range and angular field of view from the current pose (the numpy
        form of `truth_kernels.in_view`'s first test; the tests compare the two)."""
        x, y, a = self.pose
        p = self._laser.profile
        d = points - (x, y)
        dist = np.hypot(d[:, 0], d[:, 1])
        bearing = np.mod(np.arctan2(d[:, 1], d[:, 0]) - a + math.pi, 2 * math.pi) - math.pi
        return (dist <= p.range_max) & (bearing >= p.angle_min) & (bearing <= p.angle_max)

    def _in_view(self, points: np.ndarray, segments: np.ndarray) -> np.ndarray:
        """In the field of view and not occluded by `segments`: `_in_fov` and the rays cast
        towards the points in it as one compiled loop (`truth_kernels.in_view`)."""
        return in_view(np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2), *self._view(),
                       self._c4(segments), float(self._params.visible_tolerance))

    def _view(self) -> tuple[float, float, float, float, float, float]:
        """The laser's view now, as the kernels take it: x, y, a, range_max, angle_min, angle_max."""
        x, y, a = self.pose
        p = self._laser.profile
        return float(x), float(y), float(a), float(p.range_max), float(p.angle_min), float(p.angle_max)

    @staticmethod
    def _c4(segments: np.ndarray) -> np.ndarray:
        return np.ascontiguousarray(segments, dtype=np.float64).reshape(-1, 4)

    def _hit_points(self) -> tuple[np.ndarray, np.ndarray]:
        """(B, 2) map-frame noise-free end points of the latest scan's beams and (B,) the
        segment each hit (-1: none, its point then at infinity). Once per scan: every query
        of a frame reads them."""
        return self._per_scan("hit points", self._compute_hit_points)

    def _per_scan(self, name: str, compute: Callable[[], T]) -> T:
        """`compute()` once per scan of the laser (kept by `name` until the next scan)."""
        scan = self._laser.scans
        kept = self._scan_cache.get(name)
        if kept is None or kept[0] != scan:
            kept = (scan, compute())
            self._scan_cache[name] = kept
        return cast(T, kept[1])

    def _compute_hit_points(self) -> tuple[np.ndarray, np.ndarray]:
        scan = self._scan()
        return beam_ends(*scan[:6]), scan[6]

    def _scan(self) -> tuple[float, float, float, float, float, np.ndarray, np.ndarray]:
        """The latest scan as the kernels take it: (x, y, a) where it was taken, angle_min,
        increment, its noise-free ranges (B,) and the segment each beam hit (B,) (-1: none),
        once per scan; the kernels compute the beams' end points they need from it."""
        return self._per_scan("scan", self._compute_scan)

    def _compute_scan(self) -> tuple[float, float, float, float, float, np.ndarray, np.ndarray]:
        laser = self._laser
        x, y, a = laser.last_pose
        return (float(x), float(y), float(a), float(laser.fan.angle_min), float(laser.fan.increment),
                np.ascontiguousarray(laser.true_ranges, dtype=np.float64),
                np.ascontiguousarray(laser.true_hits, dtype=np.int64))

    def _visible_pieces(self) -> tuple[np.ndarray, np.ndarray]:
        return self._per_scan("visible pieces", self._compute_visible_pieces)

    def _compute_visible_pieces(self) -> tuple[np.ndarray, np.ndarray]:
        # runs of consecutive beams on the same segment (one compiled loop)
        return hit_runs(*self._scan(), int(self._params.min_wall_beams))

    def as_dict(self) -> dict[str, object]:
        """The small per-frame truth the session records (JSON-friendly)."""
        return {"pose": self.pose, "collisions": self.collisions, "in_contact": self.in_contact}
