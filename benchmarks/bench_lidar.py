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
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from pico_studio.core.io import Command
from pico_studio.json_map import load_json_map
from pico_studio.session import Session
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


def time_interleaved(fns: dict, poses, repeats: int) -> dict[str, dict[str, float]]:
    """Per peer, seconds per call: the median wall time over every pose and repeat, the best
    repeat's median, and the median CPU time of this process, all threads (what a call costs
    however much of the shared machine other jobs take: a long call is preempted more often,
    so under load the wall-time ratio flatters the faster peer and the CPU-time ratio is the
    fair one). The peers take turns, one pass over all poses each."""
    wall: dict[str, list[list[float]]] = {k: [] for k in fns}
    cpu: dict[str, list[float]] = {k: [] for k in fns}
    for _ in range(repeats):
        for k, fn in fns.items():
            run = []
            for p in poses:
                c, t = time.process_time(), time.perf_counter()
                fn(p)
                run.append(time.perf_counter() - t)
                cpu[k].append(time.process_time() - c)
            wall[k].append(run)
    return {
        k: {
            "median": statistics.median([x for r in v for x in r]),
            "best": min(statistics.median(r) for r in v),
            "cpu": statistics.median(cpu[k]),
        }
        for k, v in wall.items()
    }


def pico_scanner(sim: Simulator):
    segs = sim.world.segments()
    return lambda p: sim.laser.scan(p, segs, 0.0)  # the full scan: raycast, noise, no-return rule


def pico_ranges(sim: Simulator, poses) -> np.ndarray:
    segs = sim.world.segments()
    out = []
    for p in poses:
        sim.laser.scan(p, segs, 0.0)
        out.append(sim.laser.true_ranges.copy())
    return np.array(out)


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


def irsim_scanner(lidar):
    return lambda p: lidar.step(np.array([[p[0]], [p[1]], [p[2]]]))


def irsim_ranges(lidar, poses) -> np.ndarray:
    step = irsim_scanner(lidar)
    out = []
    for p in poses:
        step(p)
        out.append(np.array(lidar.get_scan()["ranges"], dtype=float))
    return np.array(out)


class Wander:
    """A small reactive behaviour on the laser: ahead while the front is clear, else turn."""

    def __init__(self) -> None:
        self.front: np.ndarray | None = None

    def command(self, scan) -> tuple[float, float, float]:
        if self.front is None:
            self.front = np.abs(scan.angles) < 0.6
        front = scan.ranges[self.front]
        clear = front[front > scan.range_min].min(initial=np.inf) > 0.6
        return (0.4, 0.0, 0.0) if clear else (0.0, 0.0, 1.0)

    def step(self, world_model, laser, odometry, now, *, ok=True) -> Command:  # the behaviour protocol
        return Command() if laser is None else Command(*self.command(laser))


def bench_run(seconds: float, repeats: int) -> dict[str, tuple[float, float]]:
    """Median realtime factors (simulated s per wall s, and per CPU s of this process) at
    20 Hz on the hospital map, the reactive behaviour driving: the simulator alone (advance,
    read laser and odometry, send the command) and the same through a `Session` (as
    `pico-studio run` does)."""
    out: dict[str, tuple[float, float]] = {}
    for mode in ("simulator alone", "session (run)"):
        wall, cpu = [], []
        for _ in range(repeats):
            sim = Simulator(load_json_map(MAP), seed=1)
            wander = Wander()
            c, t = time.process_time(), time.perf_counter()
            if mode == "simulator alone":
                for _ in range(round(seconds * 20)):
                    sim.advance(0.05)
                    scan, _odom = sim.read_laser(), sim.read_odometry()
                    sim.send_base_reference(*wander.command(scan))
            else:
                Session(sim, behaviour=wander).run(seconds, 0.05)
            wall.append(sim.now() / (time.perf_counter() - t))
            cpu.append(sim.now() / (time.process_time() - c))
        out[mode] = (statistics.median(wall), statistics.median(cpu))
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--poses", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--run-seconds", type=float, default=120.0)
    args = ap.parse_args()

    m = load_json_map(MAP)
    sim = Simulator(m, seed=0)
    poses = random_free_poses(sim, args.poses, seed=2024)
    print(f"world: {MAP.name}, {len(sim.world.segments())} segments (walls + cabinet edges); "
          f"{len(poses)} random free poses; {BEAMS} beams, {ANGLE_RANGE} rad, {RANGE_MAX} m")

    fns = {"pico_studio": pico_scanner(sim)}
    try:
        env, lidar = irsim_lidar(m)
    except ImportError:
        print("ir-sim is not installed: pip install 'ir-sim==2.12.0'  (or: pip install -e '.[bench]')")
        lidar = None
    else:
        fns["ir-sim 2.12"] = irsim_scanner(lidar)
    for fn in fns.values():
        fn(poses[0])  # warm up
    res = time_interleaved(fns, poses, args.repeats)
    for name, r in res.items():
        print(f"{name:12s}: {r['median'] * 1e3:8.4f} ms/scan {1 / r['median']:7.0f} scans/s (median wall time); "
              f"best repeat {1 / r['best']:.0f} scans/s; CPU time {r['cpu'] * 1e3:.4f} ms = {1 / r['cpu']:.0f} scans/s")
    if lidar is not None:
        ratio = res["ir-sim 2.12"]["median"] / res["pico_studio"]["median"]
        ratio_cpu = res["ir-sim 2.12"]["cpu"] / res["pico_studio"]["cpu"]
        print(f"ratio       : pico_studio is {ratio:.1f}x faster than ir-sim lidar2d (median wall time; "
              f"{ratio_cpu:.1f}x in CPU time)")
        r_pico, r_ir = pico_ranges(sim, poses), irsim_ranges(lidar, poses)
        both = (r_pico <= RANGE_MAX) & (r_ir < RANGE_MAX)
        diff = np.abs(r_pico[both] - r_ir[both])
        print(f"agreement   : {np.mean(diff < 1e-6) * 100:.2f}% of {both.sum()} beams hit by both agree "
              f"within 1e-6 m (max difference {diff.max():.2e} m)")

    for mode, (factor, factor_cpu) in bench_run(args.run_seconds, 3).items():
        print(f"20 Hz run   : {mode} (laser 20 Hz, odometry 50 Hz, a reactive behaviour): "
              f"{factor:.0f}x faster than real time ({factor_cpu:.0f}x per CPU second)")
    print(f"machine     : {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f} at the end (shared with other jobs)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
