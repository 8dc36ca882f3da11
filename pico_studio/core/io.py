"""The robot interface, shaped like emc IO, shared by the simulator, recordings and the robot.

`read_laser()` / `read_odometry()` return the new reading, or None when nothing new arrived
since the last call (emc's `readLaserData` returning false). Base references are holonomic
(vx, vy in m/s, va in rad/s) in the robot frame: x forward, y left.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal, Protocol, runtime_checkable

import numpy as np

OdometryForm = Literal["absolute", "delta"]


@dataclass(frozen=True)
class LaserData:
    """One scan: beam i points at `angle_min + i * angle_increment` (robot frame, radians)."""

    range_min: float
    range_max: float
    angle_min: float
    angle_max: float
    angle_increment: float
    timestamp: float
    ranges: np.ndarray  # (n,) float, metres; may hold NaN/inf/0 for no return

    @property
    def angles(self) -> np.ndarray:
        return self.angle_min + np.arange(len(self.ranges)) * self.angle_increment

    @property
    def valid(self) -> np.ndarray:
        """(n,) bool: the beams with a return, i.e. a finite range within [range_min, range_max]."""
        r = np.asarray(self.ranges, dtype=float)
        with np.errstate(invalid="ignore"):
            return np.isfinite(r) & (r >= self.range_min) & (r <= self.range_max)

    @property
    def points(self) -> np.ndarray:
        """(M, 2) robot-frame points of the valid beams, in beam order."""
        ok = self.valid
        r = np.asarray(self.ranges, dtype=float)[ok]
        a = self.angles[ok]
        return np.column_stack([r * np.cos(a), r * np.sin(a)])


@dataclass(frozen=True)
class OdometryData:
    """A pose reading (x, y in m, a in rad).

    `form="absolute"`: the pose in an odometry frame that starts anywhere (PICO era).
    `form="delta"`: the motion since the previous reading, in the previous reading's frame
    (the 2024 interface).
    """

    x: float
    y: float
    a: float
    timestamp: float
    form: OdometryForm = "absolute"


@dataclass(frozen=True)
class BaseReference:
    vx: float
    vy: float
    va: float
    timestamp: float = 0.0


@dataclass(frozen=True)
class Command:
    """What a behaviour decides each control step: a base reference in the robot frame
    (vx, vy in m/s, va in rad/s) and whether to ask for a door to open."""

    vx: float = 0.0
    vy: float = 0.0
    va: float = 0.0
    open_door: bool = False


STOP = Command()


@runtime_checkable
class RobotIO(Protocol):
    """What the perceptor and behaviours see of a robot, simulated, recorded or real."""

    def read_laser(self) -> LaserData | None: ...

    def read_odometry(self) -> OdometryData | None: ...

    def send_base_reference(self, vx: float, vy: float, va: float) -> None: ...

    def open_door(self) -> None: ...

    def ok(self) -> bool: ...

    def now(self) -> float:
        """The source's clock in seconds (simulated time, bag time, or wall time)."""
        ...


@dataclass
class Frame:
    """What one tick of a source delivers: the newest laser and odometry readings."""

    laser: LaserData | None
    odometry: OdometryData | None
    time: float
    truth: dict[str, object] = field(default_factory=dict)  # e.g. {"pose": (x, y, a)} when known
