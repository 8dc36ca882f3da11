"""The simulated laser: a fan of beams raycast against the world, with noise and a no-return rule.

The laser sits at the robot's origin, looking along x. Each scan is the true distance per beam
plus uniform noise U(-noise, noise) (as the official simulator). A beam that hits nothing
within `range_max` reports, per `no_return`:

- `zero` (default, the official simulator: its range buffer starts at 0): 0 plus the noise,
  clipped at 0, so always below `range_min` and dropped by any perceptor that checks it;
- `inf`: +inf (the ROS `LaserScan` convention for "no return");
- `range_max`: exactly `range_max`.
"""

from __future__ import annotations

import numpy as np

from pico_studio.config.sim_params import (
    NO_RETURN_CHOICES,
    HokuyoLaserParams,
    LaserParams,
    PicoSimLaserParams,
)
from pico_studio.core.io import LaserData
from pico_studio.errors import ConfigError
from pico_studio.sim.raycast import Fan

Pose = tuple[float, float, float]
_NOISE_BLOCK = 64  # scans of noise drawn per random-generator call


class Laser:
    def __init__(self, params: LaserParams, rng: np.random.Generator):
        self.params = params
        if params.profile not in ("pico-sim", "hokuyo"):
            raise ConfigError(f"unknown laser profile {params.profile!r}; one of: pico-sim, hokuyo", field="sim.laser.profile")
        if params.no_return not in NO_RETURN_CHOICES:
            raise ConfigError(f"unknown rule {params.no_return!r}; one of: {', '.join(NO_RETURN_CHOICES)}", field="sim.laser.no_return")
        p: PicoSimLaserParams | HokuyoLaserParams = params.active
        if p.angle_max <= p.angle_min:
            raise ConfigError(f"must be above angle_min ({p.angle_min:g})", field=f"sim.laser.{params.profile.replace('-', '_')}.angle_max")
        if p.range_max <= p.range_min:
            raise ConfigError(f"must be above range_min ({p.range_min:g})", field=f"sim.laser.{params.profile.replace('-', '_')}.range_max")
        self.profile = p
        self.increment = (p.angle_max - p.angle_min) / (p.beams - 1)
        self.fan = Fan(p.angle_min, self.increment, p.beams)
        self.rng = rng
        self.true_ranges = np.full(p.beams, np.inf)  # the last scan without noise (ground truth)
        self._hits: np.ndarray | None = None
        self.last_pose: Pose = (0.0, 0.0, 0.0)  # where the last scan was taken
        self.scans = 0  # scans taken so far (what the truth's per-scan answers are keyed by)
        self._noise_block = np.zeros((0, p.beams))
        self._noise_row = 0

    def scan(self, pose: Pose, segments: np.ndarray, timestamp: float) -> LaserData:
        p = self.profile
        ranges = self.fan.cast(segments, pose)
        none = ranges > p.range_max
        noise = self._next_noise()
        noisy = ranges + noise
        if none.any():
            ranges[none] = np.inf
            if self.params.no_return == "zero":
                noisy[none] = np.maximum(noise[none], 0.0)
            elif self.params.no_return == "inf":
                noisy[none] = np.inf
            else:
                noisy[none] = p.range_max
        self.true_ranges = ranges
        self.last_pose = pose
        self._hits = None
        self.scans += 1
        return LaserData(
            range_min=p.range_min,
            range_max=p.range_max,
            angle_min=p.angle_min,
            angle_max=p.angle_max,
            angle_increment=self.increment,
            timestamp=timestamp,
            # float32 like sensor_msgs/LaserScan: a recorded run then replays bit-identically
            ranges=noisy.astype(np.float32),
        )

    def _next_noise(self) -> np.ndarray:
        """One scan's noise; drawn in blocks of scans (the same stream, fewer calls)."""
        if self._noise_row >= len(self._noise_block):
            p = self.profile
            self._noise_block = self.rng.uniform(-p.noise, p.noise, size=(_NOISE_BLOCK, p.beams))
            self._noise_row = 0
        self._noise_row += 1
        return self._noise_block[self._noise_row - 1]

    @property
    def true_hits(self) -> np.ndarray:
        """Which world segment each beam of the last scan hit, -1 for none (computed on demand)."""
        if self._hits is None:
            self._hits = self.fan.last_hits(self.true_ranges)
            self._hits[~np.isfinite(self.true_ranges)] = -1
        return self._hits
