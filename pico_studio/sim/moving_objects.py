"""Moving boxes from the simulator config, with the official simulator's rules.

An object waits at `init_pose` until the robot comes within `trigger_radius` of its centre,
then drives straight towards `final_pose` at `velocity` (keeping its heading). It pauses while
the robot is within its half-diagonal plus a margin (centre to centre) and resumes when the
robot has moved away. On arrival it stops for good, or, with `repeat`, shuttles back and forth.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.sim.sim_config import MovingObjectSpec


class MovingObject:
    def __init__(self, spec: MovingObjectSpec, *, pause_margin: float, arrive_tolerance: float):
        self.spec = spec
        self.pos = np.array(spec.init_pose[:2], dtype=float)
        self.heading = float(spec.init_pose[2])
        self.target = np.array(spec.final_pose[:2], dtype=float)
        self.origin = self.pos.copy()
        self.safety_radius = math.hypot(spec.length / 2, spec.width / 2) + pause_margin
        self.arrive_tolerance = arrive_tolerance
        self.triggered = False
        self.paused = False
        self.finished = False

    @property
    def moving(self) -> bool:
        return self.triggered and not self.paused and not self.finished

    def update(self, dt: float, robot_xy: tuple[float, float]) -> None:
        dist = math.hypot(robot_xy[0] - self.pos[0], robot_xy[1] - self.pos[1])
        if not self.triggered and dist < self.spec.trigger_radius:
            self.triggered = True
        if not self.triggered or self.finished:
            return
        self.paused = dist < self.safety_radius
        if self.paused:
            return
        to_go = self.target - self.pos
        remaining = float(np.hypot(*to_go))
        step = self.spec.velocity * dt
        self.pos = self.target.copy() if step >= remaining else self.pos + to_go * (step / remaining)
        if float(np.hypot(*(self.target - self.pos))) <= self.arrive_tolerance:
            self.pos = self.target.copy()
            if self.spec.repeat:
                self.origin, self.target = self.target, self.origin.copy()
            else:
                self.finished = True

    def corners(self) -> np.ndarray:
        """The box's corners (4, 2), counter-clockwise, map frame."""
        c, s = math.cos(self.heading), math.sin(self.heading)
        hl, hw = self.spec.length / 2, self.spec.width / 2
        local = np.array([[hl, hw], [-hl, hw], [-hl, -hw], [hl, -hw]])
        return local @ np.array([[c, s], [-s, c]]) + self.pos

    def segments(self) -> np.ndarray:
        v = self.corners()
        return np.hstack([v, np.roll(v, -1, axis=0)])
