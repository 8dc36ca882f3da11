"""The holonomic base: speed cap, exact twist integration, and a collision box that stops it.

Kinematics: a constant body twist (vx, vy, va) held for h seconds moves the robot, in its own
starting frame, by (with th = va h)

    dx = (vx sin th + vy (cos th - 1)) / va,   dy = (vx (1 - cos th) + vy sin th) / va,   da = th

(and by (vx h, vy h, 0) when va = 0).

Collisions: the footprint is a box (length along x, width along y) centred on the robot. Far
from everything (nearest segment beyond the box's circumradius plus the distance about to be
travelled) the move is taken in one piece. Near obstacles it is cut into sub-steps in which no
point of the box moves more than `max_substep` (smaller than the box), and each sub-step's box
is tested against every segment; the first blocked sub-step stops the robot at the last free
pose, so even a zero-thickness wall cannot be jumped at full speed. A contact counts as one
collision event until the robot moves freely again; a collision also zeroes the reference
(the robot is stopped until it is sent a new one).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pico_studio.core.config.sim_params import BaseParams
from pico_studio.core.geometry import compose, relative
from pico_studio.sim.world import KIND_NAMES

Pose = tuple[float, float, float]


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
    """Which segments (N, 4, map frame) touch the box at `pose`: Liang-Barsky clipping of each
    segment against the box in the robot frame; the segment touches when the clipped parameter
    interval [t0, t1] is not empty."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    px = segments[:, 0] - pose[0]
    py = segments[:, 1] - pose[1]
    qx = segments[:, 2] - pose[0]
    qy = segments[:, 3] - pose[1]
    x1, y1 = c * px + s * py, -s * px + c * py
    x2, y2 = c * qx + s * qy, -s * qx + c * qy
    dx, dy = x2 - x1, y2 - y1
    t0 = np.zeros(len(segments))
    t1 = np.ones(len(segments))
    ok = np.ones(len(segments), dtype=bool)
    for p, q in ((-dx, x1 + half_length), (dx, half_length - x1), (-dy, y1 + half_width), (dy, half_width - y1)):
        parallel = np.abs(p) < 1e-15
        ok &= ~(parallel & (q < 0))
        with np.errstate(divide="ignore", invalid="ignore"):
            r = q / p
        t0 = np.where(~parallel & (p < 0), np.maximum(t0, r), t0)
        t1 = np.where(~parallel & (p > 0), np.minimum(t1, r), t1)
    return ok & (t0 <= t1)


def nearest_distance(xy: tuple[float, float], segments: np.ndarray) -> float:
    if len(segments) == 0:
        return math.inf
    a = segments[:, 0:2]
    ab = segments[:, 2:4] - a
    p = np.asarray(xy)
    t = np.clip(((p - a) * ab).sum(1) / np.maximum((ab**2).sum(1), 1e-18), 0.0, 1.0)
    d = p - (a + t[:, None] * ab)
    return float(np.sqrt((d**2).sum(1).min()))


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

    def set_reference(self, vx: float, vy: float, va: float) -> None:
        if self.speed_cap:
            v, w = self.params.max_v, self.params.max_va
            vx, vy, va = min(max(vx, -v), v), min(max(vy, -v), v), min(max(va, -w), w)
        self.reference = (float(vx), float(vy), float(va))

    def collides(self, pose: Pose, segments: np.ndarray) -> np.ndarray:
        return box_hits(pose, self.half_length, self.half_width, segments)

    def move(self, h: float, segments: np.ndarray, kinds: np.ndarray, time: float) -> Pose:
        """Drive the current reference for h seconds; returns the realised motion (dx, dy, da)
        in the starting robot frame."""
        vx, vy, va = self.reference
        if h <= 0.0 or (vx == 0.0 and vy == 0.0 and va == 0.0):
            return (0.0, 0.0, 0.0)
        speed = math.hypot(vx, vy)
        travel = speed * h + abs(va) * h * self.radius  # bound on any box point's path
        start = self.pose
        if nearest_distance(start[:2], segments) > self.radius + travel:
            step = twist_displacement(vx, vy, va, h)
            self.in_contact = False
            self._arrive(compose(start, step), speed * h)
            return step
        n = max(1, math.ceil(travel / self.params.max_substep))
        sub = twist_displacement(vx, vy, va, h / n)
        pose = start
        done = 0
        for _ in range(n):
            candidate = compose(pose, sub)
            hits = self.collides(candidate, segments)
            if hits.any():
                if not self.in_contact:
                    kind = int(kinds[np.flatnonzero(hits)[0]])
                    self.collisions.append(CollisionEvent(time, pose, KIND_NAMES[kind]))
                self.in_contact = True
                self.reference = (0.0, 0.0, 0.0)
                break
            pose = candidate
            done += 1
        else:
            self.in_contact = False
        self._arrive(pose, speed * h * done / n)
        return relative(start, pose)

    def _arrive(self, pose: Pose, distance: float) -> None:
        self.pose = pose
        self.distance += distance
