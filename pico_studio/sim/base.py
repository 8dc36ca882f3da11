"""The holonomic base: speed cap, exact twist integration, and a collision box that stops it.

Kinematics: a constant body twist (vx, vy, va) held for h seconds moves the robot, in its own
starting frame, by (with th = va h)

    dx = (vx sin th + vy (cos th - 1)) / va,   dy = (vx (1 - cos th) + vy sin th) / va,   da = th

(and by (vx h, vy h, 0) when va = 0).

Collisions: the footprint is a box (length along x, width along y) centred on the robot.
While the nearest solid segment is farther than the box's circumradius plus the distance
about to be travelled, moves are taken in one piece (a clearance budget is kept between moves
and re-measured when it runs out or the world changes). Near obstacles a move is cut into
sub-steps in which no point of the box moves more than `max_substep` (smaller than the box),
and each sub-step's box is tested against the nearby segments; the first blocked sub-step
stops the robot at the last free pose, so even a zero-thickness wall cannot be jumped at full
speed. A contact counts as one collision event until the robot moves freely again; a
collision also zeroes the reference (the robot is stopped until it is sent a new one).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pico_studio.config.sim_params import BaseParams
from pico_studio.core.geometry import Pose, compose, relative
from pico_studio.sim.base_kernels import box_first_hit, segment_distances
from pico_studio.sim.world import KIND_NAMES


@dataclass(frozen=True)
class CollisionEvent:
    time: float
    pose: Pose  # where the robot stopped
    kind: str  # what it touched: wall, object, door, moving object


def twist_displacement(vx: float, vy: float, va: float, h: float) -> Pose:
    """Motion (dx, dy, da) in the starting robot frame of a constant twist held for h s."""
    th = va * h
    if abs(th) < 1e-12:
        return (vx * h, vy * h, th)
    s, c = math.sin(th), math.cos(th)
    return ((vx * s + vy * (c - 1.0)) / va, (vx * (1.0 - c) + vy * s) / va, th)


def box_hits(pose: Pose, half_length: float, half_width: float, segments: np.ndarray) -> np.ndarray:
    """Which segments (N, 4, map frame) touch the box at `pose`.

    Separating axes for a box and a segment, in the robot frame: they are apart exactly when
    the segment lies beyond the box along x, along y, or along the segment's own normal n,
    where the box reaches |n_x| half_length + |n_y| half_width from its centre."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    local = ((segments.reshape(-1, 2) - pose[:2]) @ np.array([[c, -s], [s, c]])).reshape(-1, 4)
    x1, y1, x2, y2 = local.T
    apart = (np.minimum(x1, x2) > half_length) | (np.maximum(x1, x2) < -half_length)
    apart |= (np.minimum(y1, y2) > half_width) | (np.maximum(y1, y2) < -half_width)
    dx, dy = x2 - x1, y2 - y1
    cross = x1 * y2 - y1 * x2  # |d| times the distance to the line
    apart |= np.abs(cross) > np.abs(dy) * half_length + np.abs(dx) * half_width
    return ~apart


class Base:
    def __init__(self, params: BaseParams, pose: Pose, speed_cap: bool | None = None):
        self.params = params
        self.pose: Pose = pose
        self.speed_cap = params.speed_cap if speed_cap is None else speed_cap
        self.reference: tuple[float, float, float] = (0.0, 0.0, 0.0)
        self.half_length = params.footprint_length / 2
        self.half_width = params.footprint_width / 2
        self.radius = math.hypot(self.half_length, self.half_width)
        self.collisions: list[CollisionEvent] = []
        self.in_contact = False
        self.distance = 0.0  # true path length travelled (arc length of the centre)
        self._budget = -1.0  # how far a box point may still move before clearance is re-measured
        self._budget_world = -1  # the world version the budget was measured in

    def set_reference(self, vx: float, vy: float, va: float) -> None:
        if self.speed_cap:
            v, w = self.params.max_v, self.params.max_va
            vx, vy, va = min(max(vx, -v), v), min(max(vy, -v), v), min(max(va, -w), w)
        self.reference = (float(vx), float(vy), float(va))

    def collides(self, pose: Pose, segments: np.ndarray) -> np.ndarray:
        return box_hits(pose, self.half_length, self.half_width, segments)

    def move(self, h: float, segments: np.ndarray, kinds: np.ndarray, time: float, world_version: int = 0) -> Pose:
        """Drive the current reference for h seconds; returns the realised motion (dx, dy, da)
        in the starting robot frame."""
        vx, vy, va = self.reference
        if h <= 0.0 or (vx == 0.0 and vy == 0.0 and va == 0.0) or len(segments) == 0:
            if len(segments) == 0 and h > 0.0:
                return self._free_move(twist_displacement(vx, vy, va, h), math.hypot(vx, vy) * h)
            return (0.0, 0.0, 0.0)
        speed = math.hypot(vx, vy)
        travel = speed * h + abs(va) * h * self.radius  # bound on any box point's path
        segments = np.ascontiguousarray(segments, dtype=np.float64)
        if world_version != self._budget_world or self._budget < travel:
            # `point_segment_distance` of the centre, as one compiled loop
            dist = segment_distances(float(self.pose[0]), float(self.pose[1]), segments)
            self._budget = float(dist.min()) - self.radius
            self._budget_world = world_version
        if self._budget >= travel:
            self._budget -= travel
            return self._free_move(twist_displacement(vx, vy, va, h), speed * h)
        self._budget = -1.0
        # near something: only segments the box could reach during this move need testing
        near = np.flatnonzero(dist <= self.radius + travel)
        segments, kinds = segments[near], kinds[near]
        n = max(1, math.ceil(travel / self.params.max_substep))
        sub = twist_displacement(vx, vy, va, h / n)
        start = pose = self.pose
        done = 0
        for _ in range(n):
            candidate = compose(pose, sub)
            # `collides(candidate, segments)`'s first touching segment (a compiled loop)
            hit = box_first_hit(candidate[0], candidate[1], candidate[2], self.half_length, self.half_width, segments)
            if hit >= 0:
                if not self.in_contact:
                    kind = int(kinds[hit])
                    self.collisions.append(CollisionEvent(time, pose, KIND_NAMES[kind]))
                self.in_contact = True
                self.reference = (0.0, 0.0, 0.0)
                break
            pose = candidate
            done += 1
        else:
            self.in_contact = False
        self.pose = pose
        self.distance += speed * h * done / n
        return relative(start, pose)

    def _free_move(self, step: Pose, distance: float) -> Pose:
        self.in_contact = False
        self.pose = compose(self.pose, step)
        self.distance += distance
        return step
