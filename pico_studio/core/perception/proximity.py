"""Close proximity (seed 001): per-beam flags for laser points within a circle around the robot.

Points inside the robot's own footprint (a box centred on the laser) are the robot itself
(cables, the frame) and neither count as close nor as walls: the scan stage drops them
(`scan_kernels.scan_points`), so they are never valid.
"""

from __future__ import annotations

import numpy as np

from pico_studio.config.perception_params import ProximityParams


def proximity_flags(ranges: np.ndarray, valid: np.ndarray, params: ProximityParams) -> np.ndarray:
    """(n,) bool per beam: a valid return (so outside the footprint) inside the radius."""
    return valid & (ranges < params.radius)
