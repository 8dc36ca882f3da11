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

from pico_studio.core.config.sim_params import HokuyoLaserParams, LaserParams, PicoSimLaserParams
from pico_studio.core.geometry import invert, transform_segments
from pico_studio.core.io import LaserData
from pico_studio.errors import ConfigError
from pico_studio.sim.raycast import Fan

Pose = tuple[float, float, float]


class Laser:
    def __init__(self, params: LaserParams, rng: np.random.Generator):
        self.params = params
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
        self.true_hits = np.full(p.beams, -1)  # which world segment each beam hit, -1 for none

    def scan(self, pose: Pose, segments: np.ndarray, timestamp: float) -> LaserData:
        p = self.profile
        local = transform_segments(segments, invert(pose))
        ranges, hits = self.fan.cast(local, with_hits=True)
        assert hits is not None
        none = ~(ranges <= p.range_max)
        hits[none] = -1
        self.true_ranges, self.true_hits = ranges, hits
        noise = self.rng.uniform(-p.noise, p.noise, size=p.beams)
        noisy = ranges + noise
        if self.params.no_return == "zero":
            noisy[none] = np.maximum(noise[none], 0.0)
        elif self.params.no_return == "inf":
            noisy[none] = np.inf
        else:
            noisy[none] = p.range_max
        return LaserData(
            range_min=p.range_min,
            range_max=p.range_max,
            angle_min=p.angle_min,
            angle_max=p.angle_max,
            angle_increment=self.increment,
            timestamp=timestamp,
            ranges=noisy,
        )

