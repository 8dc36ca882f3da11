"""Wander: a reactive wall-avoiding drive on the raw laser, the robot's default pastime.

Two states:
- DRIVE: go forward at `speed`, steering away from the side with less clearance
  (va = steer_gain * (clear_left - clear_right) / (clear_left + clear_right));
  when the closest range inside the front sector (|angle| <= front_half_angle) drops
  below `stop_distance`, switch to TURN towards the side with more clearance.
- TURN: rotate in place at `turn_rate` until the front sector is clear beyond
  `clear_distance` (hysteresis, so it does not dither at the threshold), then DRIVE.

Clearance of a side = the median valid range of the beams in (front_half_angle, pi/2]
on that side; beams with no return count as `range_max`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from pico_studio.config.ui_params import WanderParams
from pico_studio.core.io import STOP, Command, LaserData, OdometryData

DRIVE = "drive"
TURN = "turn"


@dataclass
class Clearance:
    front: float  # closest range in the front sector, m
    left: float  # median range on the left side, m
    right: float  # median range on the right side, m


def clearance(laser: LaserData, front_half_angle: float) -> Clearance:
    """The laser summarised as front / left / right clearance (see module docstring)."""
    r = np.asarray(laser.ranges, dtype=float)
    bad = ~np.isfinite(r) | (r < laser.range_min) | (r > laser.range_max)
    r = np.where(bad, laser.range_max, r)
    a = laser.angles
    front = r[np.abs(a) <= front_half_angle]
    side = np.abs(a) <= np.pi / 2
    left = r[side & (a > front_half_angle)]
    right = r[side & (a < -front_half_angle)]
    return Clearance(
        front=float(front.min()) if len(front) else laser.range_max,
        left=float(np.median(left)) if len(left) else laser.range_max,
        right=float(np.median(right)) if len(right) else laser.range_max,
    )


class Wander:
    """Call `step(world_model, laser, odometry, now, ok=)` once per control period (the
    behaviour protocol; only the laser is used); it returns the command to send, or None
    when no new scan arrived (the previous reference stands)."""

    name = "wander"
    target = None  # it has no goal and no plan: nothing for the page to draw
    plan = None
    frame = "zero"
    done = False

    def __init__(self, params: WanderParams):
        self.params = params
        self.state = DRIVE
        self._turn_sign = 1.0

    def result(self) -> dict[str, Any]:
        return {"state": self.state}

    def step(
        self, world_model: Any, laser: LaserData | None, odometry: OdometryData | None = None,
        now: float = 0.0, *, ok: bool = True,
    ) -> Command | None:
        p = self.params
        if not ok:
            return STOP
        if laser is None:  # no new scan this tick: keep driving as the last one said
            return None
        if len(laser.ranges) == 0:
            return STOP
        c = clearance(laser, p.front_half_angle)
        if self.state == DRIVE and c.front < p.stop_distance:
            self.state = TURN
            self._turn_sign = 1.0 if c.left >= c.right else -1.0
        elif self.state == TURN and c.front > p.clear_distance:
            self.state = DRIVE
        if self.state == TURN:
            return Command(0.0, 0.0, self._turn_sign * p.turn_rate)
        balance = (c.left - c.right) / max(c.left + c.right, 1e-6)
        # Slow down in proportion to how close the front gets to the stop distance.
        slow = np.clip((c.front - p.stop_distance) / max(p.clear_distance, 1e-6), 0.2, 1.0)
        return Command(float(p.speed * slow), 0.0, float(p.steer_gain * balance))
