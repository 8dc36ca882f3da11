"""Raw readings to what the localiser eats, for use without a perceptor (benchmarks, tests).

With a perceptor the WorldModel already holds the scan points (robot frame) and the pose
in the zero frame (`Localiser.fill`); `LaserData.points` and this helper do the same
from `LaserData` and `OdometryData` directly.
"""

from __future__ import annotations

from pico_studio.core.geometry import Pose, compose
from pico_studio.core.io import OdometryData


def odometry_pose(previous: Pose | None, reading: OdometryData | None) -> Pose | None:
    """The odometry pose after `reading`: absolute readings as they are, deltas composed
    onto the previous pose (the origin before the first)."""
    if reading is None:
        return previous
    pose = (float(reading.x), float(reading.y), float(reading.a))
    if reading.form == "delta":
        return compose(previous if previous is not None else (0.0, 0.0, 0.0), pose)
    return pose
