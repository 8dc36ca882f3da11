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
from pico_studio.jit import kernel, njit

DRIVE = "drive"
TURN = "turn"


@dataclass
class Clearance:
    front: float  # closest range in the front sector, m
    left: float  # median range on the left side, m
    right: float  # median range on the right side, m


def clearance(laser: LaserData, front_half_angle: float) -> Clearance:
    """The laser summarised as front / left / right clearance (see module docstring): one
    compiled pass over the beams, `_clearance` (`clearance_numpy` is its numpy form)."""
    r = np.ascontiguousarray(laser.ranges, dtype=np.float64)
    front, left, right = _clearance(r, float(laser.angle_min), float(laser.angle_increment),
                                    float(laser.range_min), float(laser.range_max), float(front_half_angle))
    return Clearance(front=front, left=left, right=right)


def clearance_numpy(laser: LaserData, front_half_angle: float) -> Clearance:
    """`clearance` in numpy (the reference the tests compare the compiled loop with)."""
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


def _clearance_example() -> tuple:
    return np.array([1.0, np.inf, 2.0, 0.01, 3.0]), -1.5, 0.75, 0.05, 10.0, 0.4


@kernel(_clearance_example)
def _clearance(ranges: np.ndarray, angle_min: float, increment: float, range_min: float, range_max: float,
               front_half_angle: float) -> tuple[float, float, float]:
    """(front, left, right): the closest range with |angle| <= front_half_angle and the
    median ranges with front_half_angle < +-angle <= pi/2 (a beam with no valid return counts
    as range_max; no beam in a sector: range_max). Beam i looks at angle_min + i increment."""
    n = ranges.shape[0]
    left = np.empty(n)
    right = np.empty(n)
    n_left = n_right = 0
    front = np.inf
    for i in range(n):
        r = ranges[i]
        if not np.isfinite(r) or r < range_min or r > range_max:
            r = range_max
        a = angle_min + i * increment
        if abs(a) <= front_half_angle:
            front = min(front, r)
        if abs(a) <= np.pi / 2:
            if a > front_half_angle:
                left[n_left] = r
                n_left += 1
            elif a < -front_half_angle:
                right[n_right] = r
                n_right += 1
    return (front if front < np.inf else range_max, _median(left[:n_left], range_max),
            _median(right[:n_right], range_max))


@njit
def _median(values: np.ndarray, empty: float) -> float:
    """np.median: the middle value once sorted, the mean of the two middle ones for an even
    count (`empty` for none)."""
    n = values.shape[0]
    if n == 0:
        return empty
    v = np.sort(values)
    if n % 2:
        return v[n // 2]
    return (v[n // 2 - 1] + v[n // 2]) / 2


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
        slow = min(max((c.front - p.stop_distance) / max(p.clear_distance, 1e-6), 0.2), 1.0)  # a clip
        return Command(float(p.speed * slow), 0.0, float(p.steer_gain * balance))
