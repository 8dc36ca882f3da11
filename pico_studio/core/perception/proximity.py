"""Close proximity (seed 001): per-beam flags for laser points within a circle around the robot.

Points inside the robot's own footprint (a box centred on the laser) are the robot itself
(cables, the frame) and neither count as close nor as walls.
"""

from __future__ import annotations

import numpy as np

from pico_studio.config.perception_params import ProximityParams


def in_footprint(xy: np.ndarray, params: ProximityParams) -> np.ndarray:
    """(n,) bool: which points (n, 2) lie inside the footprint box."""
    return (np.abs(xy[:, 0]) <= params.footprint_length / 2) & (
        np.abs(xy[:, 1]) <= params.footprint_width / 2
    )


def proximity_flags(ranges: np.ndarray, valid: np.ndarray, params: ProximityParams) -> np.ndarray:
    """(n,) bool per beam: a valid return (so outside the footprint) inside the radius."""
    return valid & (ranges < params.radius)
