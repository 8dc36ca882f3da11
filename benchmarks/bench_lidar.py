"""Laser raycasting speed: pico_studio against ir-sim 2.12.0's `lidar2d`, in one process.

The same world (hospital_2019: its walls and cabinets), the same 200 random free poses
(seeded), 1000 beams over -2..+2 rad up to 10 m. Prints the median time per scan of each,
scans per second, the ratio, and how well the two agree. Then times a 20 Hz `run` of the
simulator alone (a driving behaviour, laser and odometry on) against real time.

    pip install -e '.[bench]'          # ir-sim==2.12.0, only for this benchmark
    python benchmarks/bench_lidar.py [--poses 200] [--repeats 5]
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from pico_studio.json_map import load_json_map
from pico_studio.session import Action, Session
from pico_studio.sim import Simulator

ROOT = Path(__file__).resolve().parents[1]
MAP = ROOT / "pico_studio" / "data" / "maps" / "hospital_2019.json"
BEAMS, ANGLE_RANGE, RANGE_MAX = 1000, 4.0, 10.0


def random_free_poses(sim: Simulator, n: int, seed: int) -> list[tuple[float, float, float]]:
    rng = np.random.default_rng(seed)
    x0, y0, x1, y1 = sim.world.map.bounds
    segs = sim.world.segments()
    out: list[tuple[float, float, float]] = []
    while len(out) < n:
        p = (float(rng.uniform(x0, x1)), float(rng.uniform(y0, y1)), float(rng.uniform(-math.pi, math.pi)))
        if not sim.base.collides(p, segs).any() and sim.world.enclosed(p[:2]):
            out.append(p)
    return out


def time_each(fn, poses, repeats: int) -> float:
    """Median seconds per call over every pose and repeat."""
    times = []
    for _ in range(repeats):
        for p in poses:
            t = time.perf_counter()
            fn(p)
            times.append(time.perf_counter() - t)
    return statistics.median(times)


def bench_pico(sim: Simulator, poses, repeats: int) -> tuple[float, np.ndarray]:
    segs = sim.world.segments()
    fn = lambda p: sim.laser.scan(p, segs, 0.0)  # noqa: E731 - the full scan: raycast, noise, no-return rule
    fn(poses[0])
    ranges = []
    for p in poses:
        sim.laser.scan(p, segs, 0.0)
        ranges.append(sim.laser.true_ranges.copy())
    return time_each(fn, poses, repeats), np.array(ranges)


def irsim_lidar(global_map):
    """ir-sim's own lidar2d sensor on a headless env holding the same walls and cabinets."""
    import irsim
    import yaml

    obstacles = [
        {"shape": {"name": "linestring", "vertices": [[float(s[0]), float(s[1])], [float(s[2]), float(s[3])]]}, "state": [0, 0, 0]}
        for s in global_map.wall_segments
    ] + [{"shape": {"name": "polygon", "vertices": v.tolist()}, "state": [0, 0, 0]} for v in global_map.object_polygons]
    x0, y0, x1, y1 = global_map.bounds
    world = {
        "world": {"height": y1 - y0 + 1, "width": x1 - x0 + 1, "step_time": 0.05},
        "robot": [{
            "kinematics": {"name": "omni"}, "shape": {"name": "circle", "radius": 0.05}, "state": [1.0, 1.0, 0.0],
            "sensors": [{"type": "lidar2d", "range_min": 0.0, "range_max": RANGE_MAX, "angle_range": ANGLE_RANGE, "number": BEAMS}],
        }],
        "obstacle": obstacles,
    }
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        yaml.safe_dump(world, f)
    env = irsim.make(f.name, headless=True, log_level="ERROR")
    return env, env.robot.sensors[0]


def bench_irsim(lidar, poses, repeats: int) -> tuple[float, np.ndarray]:
    fn = lambda p: lidar.step(np.array([[p[0]], [p[1]], [p[2]]]))  # noqa: E731
    fn(poses[0])
    ranges = []
    for p in poses:
        fn(p)
        ranges.append(np.array(lidar.get_scan()["ranges"], dtype=float))
    return time_each(fn, poses, repeats), np.array(ranges)


def bench_run(seconds: float, repeats: int) -> float:
    """Median realtime factor of a 20 Hz session (drive and turn) on the hospital map."""
    factors = []
    for _ in range(repeats):
        sim = Simulator(load_json_map(MAP), seed=1)
        session = Session(sim, behaviour=lambda frame, wm: Action(0.3, 0.0, 0.25), history=1)
        t = time.perf_counter()
        session.run(seconds, 0.05)
        factors.append(sim.now() / (time.perf_counter() - t))
    return statistics.median(factors)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--poses", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--run-seconds", type=float, default=120.0)
    args = ap.parse_args()

    m = load_json_map(MAP)
    sim = Simulator(m, seed=0)
    poses = random_free_poses(sim, args.poses, seed=2024)
    print(f"world: {MAP.name}, {len(sim.world.segments())} segments (walls + cabinet edges); "
          f"{len(poses)} random free poses; {BEAMS} beams, {ANGLE_RANGE} rad, {RANGE_MAX} m")

    t_pico, r_pico = bench_pico(sim, poses, args.repeats)
    print(f"pico_studio : {t_pico * 1e3:8.4f} ms/scan  {1 / t_pico:10.0f} scans/s")
    try:
        env, lidar = irsim_lidar(m)
    except ImportError:
        print("ir-sim is not installed: pip install 'ir-sim==2.12.0'  (or: pip install -e '.[bench]')")
        t_ir = None
    else:
        t_ir, r_ir = bench_irsim(lidar, poses, args.repeats)
        print(f"ir-sim 2.12 : {t_ir * 1e3:8.4f} ms/scan  {1 / t_ir:10.0f} scans/s")
        print(f"ratio       : pico_studio is {t_ir / t_pico:.1f}x faster than ir-sim lidar2d")
        both = (r_pico <= RANGE_MAX) & (r_ir < RANGE_MAX)
        diff = np.abs(r_pico[both] - r_ir[both])
        agree = np.mean(diff < 1e-6)
        print(f"agreement   : {agree * 100:.2f}% of {both.sum()} beams hit by both within 1e-6 m "
              f"(max difference {diff.max():.2e} m)")
        env.end(0) if hasattr(env, "end") else None

    factor = bench_run(args.run_seconds, 3)
    print(f"run         : a 20 Hz session (laser 20 Hz, odometry 50 Hz, driving) goes {factor:.0f}x faster than real time")
    return 0


if __name__ == "__main__":
    sys.exit(main())
