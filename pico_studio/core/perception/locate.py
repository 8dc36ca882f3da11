"""Init / Locate (seed 001): the first odometry reading is the zero pose, later ones relative to it.

Absolute odometry (PICO era) is a pose in a frame that starts anywhere: *Init* stores the
first reading Z as the zero pose and *Locate* returns pose = Z^-1 (x) odom. Delta odometry
(2024 interface) is the motion since the previous reading in that reading's frame: the zero
frame is where the robot was at the first reading and pose = pose (x) delta.

A step longer than `jump_distance + jump_speed * dt` or turning more than `jump_angle +
jump_turn_rate * dt` (dt: seconds since the previous reading; after wrapping, so a heading
going from +pi to -pi is a small step) is a jump: a log at one scan every few seconds moves
more than a metre between readings for real — a glitch or a reset of the
odometry frame. It is warned about and the zero pose re-anchored so the pose stays where it
was: the local map survives.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from pico_studio.config.perception_params import LocateParams
from pico_studio.core.geometry import compose, invert, relative
from pico_studio.core.io import OdometryData

Pose = tuple[float, float, float]


@dataclass(frozen=True)
class LocateState:
    zero_pose: Pose | None = None  # the odometry reading taken as zero (absolute form)
    pose: Pose = (0.0, 0.0, 0.0)  # in the zero frame
    started: bool = False
    stamp: float | None = None  # timestamp of the previous reading
    absolute: bool = True  # the odometry's form: absolute poses (else deltas)

    def corrected(self, pose: Pose) -> LocateState:
        """The state with the pose replaced (a correction from the laser). For absolute
        odometry the zero is re-anchored (the last reading is Z (x) old pose; the new zero
        Z' = reading (x) pose^-1) so the next reading continues from `pose`."""
        if not self.absolute or self.zero_pose is None:
            return replace(self, pose=pose)
        reading = compose(self.zero_pose, self.pose)
        return replace(self, zero_pose=compose(reading, invert(pose)), pose=pose)


def locate(
    state: LocateState, odom: OdometryData | None, params: LocateParams
) -> tuple[LocateState, Pose | None, list[str]]:
    """New state, the motion since the previous pose (None when unknown) and warnings."""
    if odom is None:
        return state, None, []
    reading = (float(odom.x), float(odom.y), float(odom.a))
    if not all(math.isfinite(v) for v in reading):
        return state, None, [f"odometry reading {reading} is not finite: ignored"]
    stamp = float(odom.timestamp) if math.isfinite(float(odom.timestamp)) else state.stamp
    dt = 0.0 if stamp is None or state.stamp is None else max(stamp - state.stamp, 0.0)
    if odom.form == "delta":
        if not state.started:  # motion before the zero pose was taken
            return LocateState((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), True, stamp, False), None, []
        step = reading
        if _is_jump(step, dt, params):
            return replace(state, stamp=stamp), None, [_jump_text(step) + ": ignored"]
        return LocateState(state.zero_pose, compose(state.pose, step), True, stamp, False), step, []
    if not state.started or state.zero_pose is None:
        return LocateState(reading, (0.0, 0.0, 0.0), True, stamp), None, []
    pose = relative(state.zero_pose, reading)
    step = relative(state.pose, pose)
    if _is_jump(step, dt, params):
        # keep the pose where it was: the new zero Z' satisfies Z'^-1 (x) reading = old pose
        zero = compose(reading, invert(state.pose))
        return LocateState(zero, state.pose, True, stamp), None, [_jump_text(step) + ": re-anchored"]
    return LocateState(state.zero_pose, pose, True, stamp), step, []


def _is_jump(step: Pose, dt: float, params: LocateParams) -> bool:
    return (math.hypot(step[0], step[1]) > params.jump_distance + params.jump_speed * dt
            or abs(step[2]) > params.jump_angle + params.jump_turn_rate * dt)


def _jump_text(step: Pose) -> str:
    return f"odometry jump of {math.hypot(step[0], step[1]):.3g} m, {step[2]:.3g} rad"
