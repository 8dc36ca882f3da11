"""Motion from the laser (seed 002) against the Intel lab's corrected poses, step by step.

For every pair of consecutive scans of `intel-corrected.log.gz`: the true step is the
motion between the two corrected (SLAM) poses; the odometry step the motion between the raw
odometry readings; the laser step the perceptor's estimate from matched corners (predicted
by the odometry step, then fitted). Prints, for the odometry alone and for the laser
estimate, the translation error (m) and rotation error (rad) per step: median, mean, 90th
percentile, and how many steps had a laser estimate.

    python benchmarks/bench_laser_motion.py
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from pico_studio.config import Config, with_value
from pico_studio.core.geometry import relative
from pico_studio.core.perception import Perceptor
from pico_studio.sources import open_carmen

ROOT = Path(__file__).resolve().parents[1]
LOG = ROOT / "tests" / "data" / "recordings" / "intel-corrected.log.gz"


def errors(est: tuple[float, float, float], true: tuple[float, float, float]) -> tuple[float, float]:
    e = relative(true, est)
    return math.hypot(e[0], e[1]), abs(e[2])


def main() -> None:
    replay = open_carmen(LOG)
    cfg = with_value(Config(), "perception.merge.keep_radius", 6.0)
    cfg = with_value(cfg, "perception.locate.jump_distance", 2.0)
    p = Perceptor(cfg.perception)
    prev = None
    odo_err, las_err, both_odo = [], [], []
    steps = 0
    for i in range(replay.frame_count):
        f = replay.frame(i)
        wm = p.step(f.laser, f.odometry)
        truth = f.truth.get("pose")
        odom = (f.odometry.x, f.odometry.y, f.odometry.a) if f.odometry is not None else None
        if prev is not None and truth is not None and odom is not None and prev[0] is not None:
            steps += 1
            true_step = relative(prev[0], truth)
            odo_step = relative(prev[1], odom)
            odo_err.append(errors(odo_step, true_step))
            if wm.laser_motion is not None:
                las_err.append(errors(tuple(wm.laser_motion), true_step))
                both_odo.append(odo_err[-1])
        prev = (truth, odom)
    print(f"Intel lab: {replay.frame_count} scans, {steps} steps; laser estimate on {len(las_err)} steps")
    for name, e in (("odometry, all steps", odo_err), ("odometry, same steps", both_odo), ("laser (corners)", las_err)):
        a = np.array(e)
        if len(a) == 0:
            continue
        print(f"  {name:22s} translation median {np.median(a[:, 0]):.3f} mean {a[:, 0].mean():.3f} "
              f"p90 {np.quantile(a[:, 0], 0.9):.3f} m | rotation median {np.median(a[:, 1]):.4f} "
              f"mean {a[:, 1].mean():.4f} p90 {np.quantile(a[:, 1], 0.9):.4f} rad")


if __name__ == "__main__":
    main()
