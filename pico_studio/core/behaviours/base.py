"""What every behaviour shares: the `Command` it returns, the `Behaviour` protocol, and a base
class that tracks odometry, stops on stale data or `ok() == False`, and gives up on time.

A behaviour is a small state machine stepped at the control rate:

    cmd = behaviour.step(world_model, laser, odometry, now, ok=io.ok())
    io.send_base_reference(cmd.vx, cmd.vy, cmd.va); cmd.open_door and io.open_door()

`laser` / `odometry` are the readings new since the last step (None when nothing new arrived,
as emc's `read*` returning false). The UI reads `state`, `target`, `plan` (and `frame`:
"odom" = the odometry frame of the readings, "global" = the global map) after each step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

import numpy as np

from pico_studio.config.behaviour_params import CommonParams
from pico_studio.core.geometry import compose
from pico_studio.core.io import STOP, Command, LaserData, OdometryData

Pose = tuple[float, float, float]


@runtime_checkable
class Behaviour(Protocol):
    name: str

    @property
    def state(self) -> str: ...

    @property
    def target(self) -> tuple[float, float] | None: ...

    @property
    def plan(self) -> np.ndarray: ...

    @property
    def frame(self) -> str: ...

    @property
    def done(self) -> bool: ...

    def step(self, world_model: Any, laser: LaserData | None, odometry: OdometryData | None,
             now: float, *, ok: bool = True) -> Command: ...

    def result(self) -> dict[str, Any]: ...


@dataclass
class Scan:
    """The newest laser scan as the behaviours use it: valid beams only, robot frame."""

    angles: np.ndarray
    ranges: np.ndarray  # inf where no valid return
    points: np.ndarray  # (M, 2) of the valid beams

    @classmethod
    def from_laser(cls, laser: LaserData, max_range: float | None = None) -> Scan:
        r = np.asarray(laser.ranges, dtype=float)
        valid = laser.valid
        if max_range is not None:
            valid &= r <= max_range
        ranges = np.where(valid, r, np.inf)
        angles = laser.angles
        pts = np.column_stack([ranges[valid] * np.cos(angles[valid]), ranges[valid] * np.sin(angles[valid])])
        return cls(angles=angles, ranges=ranges, points=pts)

    def index_of(self, angle: float) -> int:
        inc = (self.angles[-1] - self.angles[0]) / max(len(self.angles) - 1, 1)
        return int(np.clip(round((angle - self.angles[0]) / inc), 0, len(self.angles) - 1))

    def range_at(self, angle: float, half_window: int = 2) -> float:
        """Median of the valid ranges of the few beams around `angle` (inf when none)."""
        i = self.index_of(angle)
        w = self.ranges[max(0, i - half_window): i + half_window + 1]
        w = w[np.isfinite(w)]
        return float(np.median(w)) if len(w) else math.inf

    def min_in(self, lo: float, hi: float) -> float:
        sel = (self.angles >= lo) & (self.angles <= hi)
        r = self.ranges[sel]
        return float(r.min()) if len(r) else math.inf


@dataclass
class Outcome:
    """What a run produced, for `pico-studio run --json` and the benchmark."""

    rooms: list[dict[str, Any]] = field(default_factory=list)
    cabinets_visited: list[int] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


class BehaviourBase:
    """Odometry tracking, stale-data and `ok()` stops, time limit; subclasses write `_step`."""

    name = "behaviour"

    def __init__(self, common: CommonParams):
        self.common = common
        self._state = "start"
        self._target: tuple[float, float] | None = None
        self._plan = np.zeros((0, 2))
        self.pose: Pose | None = None  # odometry pose (frame of the readings)
        self.scan: Scan | None = None
        self.world_model: Any = None
        self.outcome = Outcome()
        self._start_time: float | None = None
        self._last_laser = -math.inf
        self._last_odom = -math.inf
        self._odom_delta_pose: Pose = (0.0, 0.0, 0.0)
        self.halted_reason = ""  # why the base is being held still, when it is

    # ---- what the UI reads ----
    @property
    def state(self) -> str:
        return self._state

    @property
    def target(self) -> tuple[float, float] | None:
        return self._target

    @property
    def plan(self) -> np.ndarray:
        return self._plan

    @property
    def frame(self) -> str:
        return "odom"

    @property
    def done(self) -> bool:
        return self._state in ("done", "gave up")

    def result(self) -> dict[str, Any]:
        return {
            "state": self._state,
            "rooms": list(self.outcome.rooms),
            "cabinets_visited": list(self.outcome.cabinets_visited),
            "notes": list(self.outcome.notes),
        }

    # ---- the loop ----
    def step(self, world_model: Any, laser: LaserData | None, odometry: OdometryData | None,
             now: float, *, ok: bool = True) -> Command:
        if self._start_time is None:
            self._start_time = now
        if laser is not None:
            self.scan = Scan.from_laser(laser)
            self._last_laser = now
        if odometry is not None:
            self._update_pose(odometry)
            self._last_odom = now
        self.world_model = world_model
        if self.done:
            return STOP
        if not ok:
            self.halted_reason = "robot not ok"
            return STOP
        if self.scan is None or self.pose is None:
            self.halted_reason = "waiting for laser and odometry"
            return STOP
        stale = now - min(self._last_laser, self._last_odom)
        if stale > self.common.stale_timeout:
            self.halted_reason = f"data stale for {stale:.2f} s"
            return STOP
        if now - self._start_time > self.common.time_limit:
            self.give_up(f"time limit of {self.common.time_limit:g} s reached")
            return STOP
        self.halted_reason = ""
        return self._step(now)

    def _step(self, now: float) -> Command:  # pragma: no cover - abstract
        raise NotImplementedError

    def _update_pose(self, odo: OdometryData) -> None:
        if odo.form == "delta":
            self._odom_delta_pose = compose(self._odom_delta_pose, (odo.x, odo.y, odo.a))
            self.pose = self._odom_delta_pose
        else:
            self.pose = (float(odo.x), float(odo.y), float(odo.a))

    def give_up(self, why: str) -> None:
        self._state = "gave up"
        self.outcome.notes.append(why)

    def finish(self) -> None:
        self._state = "done"

    @property
    def dt(self) -> float:
        return 1.0 / self.common.rate


def clamp(v: float, limit: float) -> float:
    return max(-limit, min(limit, v))


def turn_rate(error: float, fast: float, slow: float, slow_angle: float) -> float:
    """Seed 000's turn: full speed until the last `slow_angle`, then slow, signed by `error`.

    The fast part is also capped so one 20 Hz step cannot jump past the slow zone's start.
    """
    mag = abs(error)
    rate = fast if mag > slow_angle else min(slow, mag * 20.0)
    return math.copysign(rate, error)


def wall_angle(scan: Scan, centre: float, delta: float) -> float | None:
    """Direction (robot frame) of the wall hit by the two beams at `centre +- delta`, taken
    along increasing beam angle; None when either beam has no return."""
    r1, r2 = scan.range_at(centre - delta), scan.range_at(centre + delta)
    if not (math.isfinite(r1) and math.isfinite(r2)):
        return None
    a1, a2 = centre - delta, centre + delta
    p1 = (r1 * math.cos(a1), r1 * math.sin(a1))
    p2 = (r2 * math.cos(a2), r2 * math.sin(a2))
    return math.atan2(p2[1] - p1[1], p2[0] - p1[0])
