"""Scans for the localisation tests built straight from map geometry (no simulator needed).

Points are sampled on the map's segments within the laser's range and field of view around
a true pose and expressed in the robot frame with uniform noise, like the simulated laser's
±1 cm. Occlusion is ignored: every sampled point is still on the map, which is all the
estimator's unit tests need; the end-to-end tests use the simulator.
"""

from __future__ import annotations

import numpy as np

from pico_studio.core.geometry import invert, transform_points


def scan_from_segments(
    segments: np.ndarray,
    pose: tuple[float, float, float],
    rng: np.random.Generator,
    *,
    n: int = 700,
    max_range: float = 6.0,
    half_fov: float = 2.0,
    noise: float = 0.01,
) -> np.ndarray:
    lengths = np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1])
    owner = np.repeat(np.arange(len(segments)), np.ceil(lengths / 0.02).astype(int))
    t = rng.random(len(owner))
    a, b = segments[owner, 0:2], segments[owner, 2:4]
    local = transform_points(a + t[:, None] * (b - a), invert(pose))
    keep = (np.hypot(local[:, 0], local[:, 1]) < max_range)
    keep &= np.abs(np.arctan2(local[:, 1], local[:, 0])) < half_fov
    local = local[keep]
    local = local[rng.choice(len(local), min(n, len(local)), replace=False)]
    return local + rng.uniform(-noise, noise, local.shape)
