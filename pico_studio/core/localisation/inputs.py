"""Raw readings to what the localiser eats, for use without a perceptor (benchmarks, tests).

With a perceptor the WorldModel already holds the scan points (robot frame) and the pose
in the zero frame (`Localiser.fill`); these helpers do the same from `LaserData` and
`OdometryData` directly.
"""

from __future__ import annotations

import numpy as np

from pico_studio.core.geometry import compose
from pico_studio.core.io import LaserData, OdometryData

Pose = tuple[float, float, float]


def laser_points(laser: LaserData) -> np.ndarray:
    """(M, 2) robot-frame points of the beams with a valid range (finite, within limits)."""
    r = np.asarray(laser.ranges, dtype=float)
    a = laser.angles
    ok = np.isfinite(r) & (r >= laser.range_min) & (r <= laser.range_max)
    return np.column_stack([r[ok] * np.cos(a[ok]), r[ok] * np.sin(a[ok])])


def odometry_pose(previous: Pose | None, reading: OdometryData | None) -> Pose | None:
    """The odometry pose after `reading`: absolute readings as they are, deltas composed
    onto the previous pose (the origin before the first)."""
    if reading is None:
        return previous
    pose = (float(reading.x), float(reading.y), float(reading.a))
    if reading.form == "delta":
        return compose(previous if previous is not None else (0.0, 0.0, 0.0), pose)
    return pose
