"""Hospital tour: visit cabinets (or restaurant tables) in a given order on the global map.

States:
    plan      A* (planner.py) from the robot's global pose to the spot in front of the next
              cabinet; no path: try once more without the remembered obstacles, then give up
              (at most 4 A* runs per tick, standing still meanwhile: no tick stalls the loop)
    drive     follow the plan (pure pursuit, `lookahead` ahead); ask doors on the plan to open
              when one is within `door_request_distance`; something not on the map within
              `blocked_distance` along the plan and within `path_clearance` of it: blocked
    blocked   stand still for `blocked_wait` s (people and carts move on; a door slides
              away), then replan round what is still there (at most `max_replans` times)
    face      turn to face the cabinet's front
    arrived   stand `arrive_pause` s, note the cabinet as visited, go on with the next one
bubbleRobot overrides any state.

The spot for a cabinet is `front_distance` in front of the middle of its front (its first
segment), facing it. Tables have no front that matters: spots along each side (front first,
middles first) are tried in order, the first reachable wins. A spot inside the inflated map is a bad target: the
constructor raises `UserError` for a cabinet, as for an index that does not exist.

Pose: the world model's `global_pose` (localisation) when present and not lost; otherwise
odometry from the last known global pose (at the start: `initial_pose`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from pico_studio.config.behaviour_params import BehaviourParams
from pico_studio.core.behaviours.base import BehaviourBase, Command, Pose, clamp, turn_rate
from pico_studio.core.behaviours.bubble import Bubble
from pico_studio.core.behaviours.planner import PlanGrid, astar, densify
from pico_studio.core.geometry import (
    compose,
    pairwise_distances,
    point_segment_distance,
    relative,
    transform_points,
    wrap_angle,
)
from pico_studio.core.localisation.distance_field import DistanceField
from pico_studio.errors import UserError
from pico_studio.json_map import GlobalMap

_PATH_STEP = 0.05  # m between the points the plan is followed along
_PLANS_PER_TICK = 4  # A* runs per tick at most (a few ms each, compiled): no replan stalls the 20 Hz loop


def object_spots(m: GlobalMap, index: int, front_distance: float,
                 fractions: tuple[float, ...] = (0.5,)) -> list[Pose]:
    """Candidate stand-points (x, y, heading facing the object) `front_distance` out from
    each side of object `index`, its front (first segment) first; on each side at the given
    `fractions` along it (the middle first)."""
    poly = m.objects[index]
    centroid = m.polygon_vertices(poly).mean(axis=0)
    spots: list[Pose] = []
    for seg in m.segments_of(poly):
        a, b = seg[:2], seg[2:]
        mid = (a + b) / 2
        t = (b - a) / max(float(np.hypot(*(b - a))), 1e-12)
        n = np.array([-t[1], t[0]])
        if n @ (mid - centroid) < 0:
            n = -n
        for f in fractions:
            p = a + (b - a) * f + n * front_distance
            spots.append((float(p[0]), float(p[1]), math.atan2(-n[1], -n[0])))
    return spots


# where along a table's side the robot may stand (a cabinet is faced at its middle only)
TABLE_FRACTIONS = (0.5, 0.3, 0.7, 0.15, 0.85)


class HospitalTour(BehaviourBase):
    name = "hospital"

    def __init__(self, params: BehaviourParams, global_map: GlobalMap, order: list[int],
                 initial_pose: Pose | None = None):
        super().__init__(params.common)
        self.p = params.hospital
        self.map = global_map
        self.bubble = Bubble(params.bubble, params.common)
        kind = global_map.object_key
        if not global_map.objects:
            raise UserError(f"the map has no {kind} to visit", field="--behaviour")
        if not order:
            raise UserError(f"give the {kind} to visit, e.g. hospital:0,2,1", field="--behaviour")
        for i in order:
            if not 0 <= i < len(global_map.objects):
                raise UserError(f"no {kind[:-1]} {i}: the map has {len(global_map.objects)} "
                                f"(0..{len(global_map.objects) - 1})", field="--behaviour")
        self.order = list(order)
        self.grid = PlanGrid.from_map(global_map, self.p)
        self.spots: list[list[Pose]] = []
        for i in self.order:
            if kind == "cabinets":  # a cabinet is opened from the middle of its front only
                candidates = object_spots(global_map, i, self.p.front_distance)[:1]
            else:
                candidates = object_spots(global_map, i, self.p.front_distance, TABLE_FRACTIONS)
            spots = [s for s in candidates if self.grid.free(s[:2])]
            if not spots:
                raise UserError(f"{kind[:-1]} {i}: the spot in front of it is inside a wall "
                                f"(closer than {self.p.inflation:g} m)", field="--behaviour")
            self.spots.append(spots)
        solid = [global_map.wall_segments] + [global_map.segments_of(o) for o in global_map.objects]
        self.door_segments = np.vstack([global_map.segments_of(d) for d in global_map.doors]) if global_map.doors else np.zeros((0, 4))
        self.map_field = DistanceField.from_segments(np.vstack(solid + [self.door_segments]),
                                                     resolution=self.p.cell, margin=1.0)
        self.initial_pose = initial_pose
        self._anchor: tuple[Pose, Pose] | None = None  # (global pose, odometry pose) pair
        self.global_pose: Pose | None = None
        self._k = 0  # index into order
        self._state = "plan"
        self._tries: list[tuple[PlanGrid, Pose]] | None = None  # plans left in this planning round
        self._goal: Pose | None = None
        self._path = np.zeros((0, 2))
        self._obstacles = np.zeros((0, 2))
        self._blocked_since: float | None = None
        self._replans = 0  # for the current target
        self.replans_total = 0
        self._arrived_at: float | None = None

    @property
    def frame(self) -> str:
        return "global"

    # ---- where are we ----
    def _locate(self) -> Pose | None:
        assert self.pose is not None
        wm = self.world_model
        g = getattr(wm, "global_pose", None) if wm is not None else None
        if g is not None and not getattr(wm, "lost", False):
            g = (float(g[0]), float(g[1]), float(g[2]))
            at_wm = getattr(wm, "pose", self.pose)
            odo_at_wm: Pose = (float(at_wm[0]), float(at_wm[1]), float(at_wm[2]))
            # the world model's pose is in the perceptor's zero frame; ours is raw odometry:
            # anchor the global pose to our odometry reading of the same instant
            zero = getattr(wm, "zero_pose", None)
            odo_raw = (compose((float(zero[0]), float(zero[1]), float(zero[2])), odo_at_wm)
                       if zero is not None else self.pose)
            self._anchor = (g, odo_raw)
        elif self._anchor is None and self.initial_pose is not None:
            self._anchor = (self.initial_pose, self.pose)
        if self._anchor is None:
            return None
        g0, o0 = self._anchor
        return compose(g0, relative(o0, self.pose))

    def _unmapped_points(self, pose: Pose) -> np.ndarray:
        """Laser points (global frame) that no wall, object or door of the map explains."""
        assert self.scan is not None
        pts = transform_points(self.scan.points, pose)
        if len(pts) == 0:
            return pts
        return pts[self.map_field.distance(pts) > self.p.map_match]

    def _door_points(self, pose: Pose) -> np.ndarray:
        assert self.scan is not None
        if len(self.door_segments) == 0 or len(self.scan.points) == 0:
            return np.zeros((0, 2))
        pts = transform_points(self.scan.points, pose)
        return pts[point_segment_distance(pts, self.door_segments).min(axis=1) <= self.p.map_match]

    # ---- the state machine ----
    def _step(self, now: float) -> Command:
        assert self.scan is not None and self.pose is not None
        pose = self._locate()
        self.global_pose = pose
        if pose is None:
            self.halted_reason = "waiting for a global pose"
            return Command()
        override = self.bubble.check(self.scan, self.pose)
        if override is not None:
            return override
        if self._state == "plan":
            return self._plan_step(pose)
        if self._state == "drive":
            return self._drive(pose, now)
        if self._state == "blocked":
            return self._blocked(pose, now)
        if self._state == "face":
            return self._face(pose, now)
        if self._state == "arrived":
            return self._arrived(now)
        return Command()

    def _plan_step(self, pose: Pose) -> Command:
        """Plan to the current target's spots (first round the obstacles met so far, then
        without them), at most `_PLANS_PER_TICK` A* runs per tick: a target with many
        unreachable spots takes a few ticks standing still, never one long tick."""
        i = self.order[self._k]
        if self._tries is None:  # a new planning round
            rounds = [self._obstacles, np.zeros((0, 2))] if len(self._obstacles) else [self._obstacles]
            grids = [self.grid.with_obstacles(o, self.p.obstacle_radius + self.p.inflation) if len(o) else self.grid
                     for o in rounds]
            self._tries = [(g, spot) for g in grids for spot in self.spots[self._k]]
        for _ in range(_PLANS_PER_TICK):
            if not self._tries:
                self._tries = None
                self.give_up(f"{self.map.object_key[:-1]} {i} cannot be reached")
                return Command()
            grid, spot = self._tries.pop(0)
            start = grid.nearest_free(pose[:2], 0.5) or pose[:2]
            path = astar(grid, start, spot[:2])
            if path is not None:
                self._tries = None
                self._goal = spot
                self._path = densify(np.vstack([[pose[:2]], path[1:]]), _PATH_STEP)
                self._plan = self._path
                self._target = (spot[0], spot[1])
                self._state = "drive"
                return Command()
        return Command()  # more spots to try next tick

    def _drive(self, pose: Pose, now: float) -> Command:
        assert self._goal is not None
        xy = np.array(pose[:2])
        d = np.hypot(*(self._path - xy).T)
        near = int(np.argmin(d))
        self._path = self._path[near:]
        self._plan = self._path
        goal_dist = math.hypot(self._goal[0] - pose[0], self._goal[1] - pose[1])
        if goal_dist < self.p.goal_tolerance or (len(self._path) <= 1 and goal_dist < 2 * self.p.goal_tolerance):
            self._state = "face"
            return Command()
        open_door = self._door_ahead(xy)
        if self._path_blocked(pose):
            self._blocked_since = now
            self._state = "blocked"
            return Command(open_door=open_door)
        ahead = np.flatnonzero(np.hypot(*(self._path - xy).T) >= self.p.lookahead)
        aim = self._path[ahead[0]] if len(ahead) else self._path[-1]
        err = float(wrap_angle(math.atan2(aim[1] - pose[1], aim[0] - pose[0]) - pose[2]))
        if abs(err) > 0.8:
            return Command(va=turn_rate(err, self.p.turn_speed, 0.3, 0.1), open_door=open_door)
        speed = min(self.p.speed, 0.6 * goal_dist + 0.05) * max(0.0, math.cos(err))
        return Command(vx=speed, va=clamp(self.p.heading_gain * err, self.p.turn_speed), open_door=open_door)

    def _door_ahead(self, xy: np.ndarray) -> bool:
        if len(self.door_segments) == 0:
            return False
        ahead = self._path[np.hypot(*(self._path - xy).T) <= self.p.door_request_distance]
        if len(ahead) == 0:
            return False
        return bool(point_segment_distance(ahead, self.door_segments).min() <= self.p.map_match)

    def _path_blocked(self, pose: Pose) -> bool:
        """Something not on the map (or a closed door) within `blocked_distance` on the plan."""
        xy = np.array(pose[:2])
        close = self._path[np.hypot(*(self._path - xy).T) <= self.p.blocked_distance + self.p.inflation]
        if len(close) == 0:
            return False
        pts = np.vstack([self._unmapped_points(pose), self._door_points(pose)])
        if len(pts) == 0:
            return False
        pts = pts[np.hypot(*(pts - xy).T) <= self.p.blocked_distance + self.p.inflation]
        if len(pts) == 0:
            return False
        gaps = pairwise_distances(pts, close)
        return bool(gaps.min() < self.p.path_clearance)

    def _blocked(self, pose: Pose, now: float) -> Command:
        assert self._blocked_since is not None
        door = self._door_ahead(np.array(pose[:2]))
        if not self._path_blocked(pose):
            self._state = "drive"
            return Command(open_door=door)
        seen = self._unmapped_points(pose)
        # an obstacle already waited for (a new side of it came into view): replan at once
        known = len(self._obstacles) > 0 and len(seen) > 0 and bool(
            pairwise_distances(seen, self._obstacles[::4]).min() < 0.3)
        waited = now - self._blocked_since
        if not known and (waited < self.p.blocked_wait or (door and waited < 3 * self.p.blocked_wait)):
            return Command(open_door=door)
        self._replans += 1
        self.replans_total += 1
        if self._replans > self.p.max_replans:
            self.give_up(f"blocked {self._replans} times on the way to {self.map.object_key[:-1]} {self.order[self._k]}")
            return Command()
        # remember what blocked us (what moved away is forgotten at the next cabinet)
        self._obstacles = np.vstack([self._obstacles, seen])[-2000:]
        self._state = "plan"
        return Command()

    def _face(self, pose: Pose, now: float) -> Command:
        assert self._goal is not None
        err = float(wrap_angle(self._goal[2] - pose[2]))
        if abs(err) > self.p.face_tolerance:
            return Command(va=turn_rate(err, self.p.turn_speed, 0.3, 0.1))
        self._arrived_at = now
        self._state = "arrived"
        return Command()

    def _arrived(self, now: float) -> Command:
        assert self._arrived_at is not None
        if now - self._arrived_at < self.p.arrive_pause:
            return Command()
        self.outcome.cabinets_visited.append(self.order[self._k])
        self._k += 1
        self._obstacles = np.zeros((0, 2))
        self._replans = 0
        if self._k >= len(self.order):
            self._plan = np.zeros((0, 2))
            self.finish()
        else:
            self._state = "plan"
        return Command()

    def result(self) -> dict[str, Any]:
        out = super().result()
        out["order"] = list(self.order)
        out["replans"] = self.replans_total
        return out
