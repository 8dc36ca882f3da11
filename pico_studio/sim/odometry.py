"""Wheel odometry: the true motion integrated in a frame that starts anywhere, exact or not.

The odometry pose starts at the configured (or seeded) offset and is moved by every realised
base motion (dx, dy, da) in the robot frame. Uncertain odometry scales each component by its
own wheel gain 1 + U(-e, e), re-drawn every `gain_period` seconds (the official simulator's
model): after travelling a distance D, the position error is at most e * D plus the effect of
the heading error, which is at most e times the total turned angle.

Readings come in two forms: `absolute` (the pose in the odometry frame, PICO era) or `delta`
(the motion since the previously *returned* reading, in that reading's frame, 2024 interface),
so that summing deltas never loses motion however often the reader polls.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config.sim_params import OdometryParams
from pico_studio.core.geometry import Pose, compose, relative
from pico_studio.core.io import OdometryData


class Odometry:
    def __init__(self, params: OdometryParams, rng: np.random.Generator, uncertain: bool | None = None):
        self.params = params
        self.rng = rng
        self.uncertain = params.uncertain if uncertain is None else uncertain
        if params.random_offset:
            x, y = rng.uniform(-100.0, 100.0, size=2)
            a = rng.uniform(-math.pi, math.pi)
            self.pose: Pose = (float(x), float(y), float(a))
        else:
            self.pose = (params.offset_x, params.offset_y, params.offset_a)
        self.gains = np.ones(3)
        if self.uncertain:
            self.redraw_gains()
        self._start = self.pose
        self._last_delivered: Pose | None = None

    def redraw_gains(self) -> None:
        e = self.params.gain_error
        self.gains = 1.0 + self.rng.uniform(-e, e, size=3)

    def integrate(self, motion: Pose) -> None:
        if self.uncertain:
            motion = (motion[0] * self.gains[0], motion[1] * self.gains[1], motion[2] * self.gains[2])
        self.pose = compose(self.pose, motion)

    def snapshot(self, timestamp: float) -> OdometryData:
        """The absolute reading now (what the sensor latches at its rate)."""
        x, y, a = self.pose
        return OdometryData(x, y, a, timestamp, "absolute")

    def deliver(self, reading: OdometryData) -> OdometryData:
        """A latched reading as the reader gets it, in the configured form: a delta is the
        motion since the previously delivered reading (the first one since the start)."""
        if self.params.form == "absolute":
            return reading
        pose = (reading.x, reading.y, reading.a)
        prev = self._last_delivered if self._last_delivered is not None else self._start
        self._last_delivered = pose
        dx, dy, da = relative(prev, pose)
        return OdometryData(dx, dy, da, reading.timestamp, "delta")
