"""Driving the simulator for the localisation tests: a waypoint follower on the true pose
(a test harness, not a behaviour), a kick, and a loop that localises every scan."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pico_studio.core.geometry import compose, point_segment_distance, relative, wrap_angle
from pico_studio.core.localisation import Localiser
from pico_studio.core.localisation.inputs import odometry_pose
from pico_studio.sim import Simulator

DT = 0.05


def follow(waypoints: list[tuple[float, float]], speed: float = 0.4):
    """A callable pose -> (vx, vy, va) driving through the waypoints in a loop."""
    k = [0]

    def command(pose: tuple[float, float, float]) -> tuple[float, float, float]:
        wx, wy = waypoints[k[0] % len(waypoints)]
        if math.hypot(wx - pose[0], wy - pose[1]) < 0.1:
            k[0] += 1
            wx, wy = waypoints[k[0] % len(waypoints)]
        local = relative(pose, (wx, wy, 0.0))
        dist = math.hypot(local[0], local[1])
        v = min(speed, dist) / max(dist, 1e-9)
        turn = float(wrap_angle(math.atan2(wy - pose[1], wx - pose[0]) - pose[2]))
        if abs(turn) > 0.5:  # turn on the spot first
            v = 0.0
        return local[0] * v, local[1] * v, float(np.clip(2.0 * turn, -1.0, 1.0))

    return command


def kick(sim: Simulator, distance: float = 0.5, turn: float = math.radians(20)) -> tuple[float, float, float]:
    """Move the true pose `distance` in the first free direction and turn it by `turn`."""
    pose = sim.truth.pose
    segs = sim.world.segments()
    for a in np.arange(16) * (2 * math.pi / 16):
        cand = (pose[0] + distance * math.cos(a), pose[1] + distance * math.sin(a),
                float(wrap_angle(pose[2] + turn)))
        if point_segment_distance(np.array([cand[:2]]), segs).min() > 0.3:
            sim.base.pose = cand
            return cand
    raise AssertionError("no free place to kick the robot to")


@dataclass
class Driver:
    """Steps the simulator at 20 Hz, localising every scan and recording the errors."""

    sim: Simulator
    loc: Localiser
    odom: tuple[float, float, float] | None = None
    times: list[float] = field(default_factory=list)
    errors: list[tuple[float, float]] = field(default_factory=list)  # (m, rad); nan before a fix
    lost: list[bool] = field(default_factory=list)
    dead_reckoning: list[float] = field(default_factory=list)  # odometry alone from the true start, m
    _start: tuple | None = None

    def drive(self, seconds: float, command=None) -> None:
        sim = self.sim
        if self._start is None:
            self._start = (sim.truth.pose, sim.truth.odometry_pose)
        for _ in range(int(round(seconds / DT))):
            if command is not None:
                sim.send_base_reference(*command(sim.truth.pose))
            sim.advance(DT)
            laser = sim.read_laser()
            self.odom = odometry_pose(self.odom, sim.read_odometry())
            if laser is None or self.odom is None:
                continue
            r = self.loc.step(laser.points, self.odom)
            t = sim.truth.pose
            dr = compose(self._start[0], relative(self._start[1], sim.truth.odometry_pose))
            self.dead_reckoning.append(math.hypot(dr[0] - t[0], dr[1] - t[1]))
            self.times.append(sim.now())
            self.lost.append(r.lost)
            if r.pose is None:
                self.errors.append((math.nan, math.nan))
            else:
                self.errors.append((math.hypot(r.pose[0] - t[0], r.pose[1] - t[1]),
                                    abs(float(wrap_angle(r.pose[2] - t[2])))))
