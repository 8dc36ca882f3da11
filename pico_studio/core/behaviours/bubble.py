"""bubbleRobot (seed 003): when anything is closer than the bubble, stop, back away further
than the bubble, then hand control back so the behaviour re-evaluates.

The bubble is a clearance around the robot's box (not its centre), so a narrow hallway where
the walls pass 0.2 m beside the robot does not trigger it. Backing away is straight away from
the nearest laser point's closest part of the box (the base is holonomic), for `radius + backoff_extra - clearance`,
measured on odometry.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config.behaviour_params import BubbleParams, CommonParams
from pico_studio.core.behaviours.base import Command, Pose, Scan


def box_clearance(points: np.ndarray, length: float, width: float) -> np.ndarray:
    """Distance of each robot-frame point (M, 2) to the robot's box (0 inside)."""
    dx = np.maximum(np.abs(points[:, 0]) - length / 2, 0.0)
    dy = np.maximum(np.abs(points[:, 1]) - width / 2, 0.0)
    return np.hypot(dx, dy)


class Bubble:
    """Stateful guard: `check()` returns a back-away command while active, else None."""

    def __init__(self, params: BubbleParams, common: CommonParams):
        self.p = params
        self.common = common
        self.active = False
        self.triggers = 0
        self._from: Pose | None = None
        self._direction = np.zeros(2)  # unit vector in the robot frame at trigger time
        self._distance = 0.0

    def nearest(self, scan: Scan) -> tuple[float, np.ndarray | None]:
        sel = np.abs(np.arctan2(scan.points[:, 1], scan.points[:, 0])) <= self.p.fov
        pts = scan.points[sel]
        if len(pts) == 0:
            return math.inf, None
        c = box_clearance(pts, self.common.footprint_length, self.common.footprint_width)
        i = int(np.argmin(c))
        return float(c[i]), pts[i]

    def check(self, scan: Scan, pose: Pose) -> Command | None:
        if self.active:
            assert self._from is not None
            moved = math.hypot(pose[0] - self._from[0], pose[1] - self._from[1])
            if moved >= self._distance:
                self.active = False
                return None
            v = self._direction * self.p.speed
            # the direction was fixed in the robot frame at trigger time; undo any rotation since
            da = pose[2] - self._from[2]
            c, s = math.cos(-da), math.sin(-da)
            return Command(vx=c * v[0] - s * v[1], vy=s * v[0] + c * v[1], va=0.0)
        clearance, point = self.nearest(scan)
        if point is None or clearance >= self.p.radius:
            return None
        self.active = True
        self.triggers += 1
        self._from = pose
        # away from the box's point nearest to the obstacle (straight back from a wall ahead)
        L, W = self.common.footprint_length / 2, self.common.footprint_width / 2
        out = np.sign(point) * np.maximum(np.abs(point) - np.array([L, W]), 0.0)
        if float(np.hypot(*out)) < 1e-9:
            out = point
        norm = float(np.hypot(*out))
        self._direction = -out / norm if norm > 1e-9 else np.array([-1.0, 0.0])
        self._distance = self.p.radius + self.p.backoff_extra - clearance
        return Command()  # stop this step; the back-away starts on the next
