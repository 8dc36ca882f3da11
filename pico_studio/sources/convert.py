"""Small conversions shared by the bag reader and the live ROS source."""

from __future__ import annotations

import math

from pico_studio.config.sources_params import ReplayParams


def yaw_from_quaternion(x: float, y: float, z: float, w: float) -> float:
    """The rotation about z of a quaternion (REP 103: x forward, y left, z up)."""
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def beam_layout_problem(
    n: int, a0: float, a1: float, inc: float, replay: ReplayParams
) -> tuple[str, str] | None:
    """(field, problem) when a LaserScan's angle fields cannot describe its `n` beams.

    Beam i points at `angle_min + i * angle_increment`, so the last beam should sit at
    `angle_max`: `(angle_max - angle_min) / angle_increment + 1` must be the beam count,
    within `replay.beam_count_tolerance` (drivers round the increment).
    """
    if n == 0:
        return "ranges", "empty"
    if not (math.isfinite(a0) and math.isfinite(a1) and math.isfinite(inc)):
        return "angle_min/angle_max/angle_increment", f"not finite ({a0}, {a1}, {inc})"
    if inc == 0.0 and n > 1:
        return "angle_increment", f"is 0 for {n} beams"
    if replay.check_beam_layout and n > 1:
        expected = (a1 - a0) / inc + 1
        if abs(expected - n) > replay.beam_count_tolerance:
            return (
                "angle_increment",
                f"(angle_max - angle_min) / angle_increment + 1 = {expected:.1f} beams "
                f"({a0:.4f} .. {a1:.4f} by {inc:.6f}) but ranges holds {n}",
            )
    return None
