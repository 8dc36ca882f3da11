"""Truth scoring and re-judging a recorded run, compiled vs its own Python, on hospital_2019.

A run is recorded once: the simulator at `--poses` random free poses of hospital_2019
(seeded), the robot turning slowly at each, `--frames` scans per pose (12 x 200 = 2,400
frames: a 2-minute run), and per frame the scan, the odometry and the truth the scoring
needs (true pose, solid segments, visible walls, corners in view, openings, doors in view).

- *scoring a frame*: `score_arrays` of a perceived world model against its frame's truth,
  CPU ms per frame (median over frames and `--repeats`), compiled and uncompiled
  (`jit.uncompiled`, every compiled loop as its Python) in the same process;
- *re-judging the run*: perceive every frame afresh (a new perceptor per pose) and score it,
  as after a slider change: CPU seconds for the whole run;
- *same answers*: the run's summary (every figure of `pico-studio eval`) compiled and
  uncompiled on the first `--python-frames` frames: equal within 1e-9.

    python benchmarks/bench_scoring.py [--poses 12] [--frames 200] [--repeats 3]
"""

from __future__ import annotations

import argparse
import math
import time
from typing import Any

import numpy as np
from timing import load

from pico_studio.config import Config
from pico_studio.core.geometry import transform_points, transform_segments
from pico_studio.core.io import Command
from pico_studio.core.perception import Perceptor
from pico_studio.evaluation import frame_score
from pico_studio.evaluation.poses import random_free_poses
from pico_studio.jit import uncompiled, warm_up
from pico_studio.json_map import load_map
from pico_studio.session import Session
from pico_studio.sim import Simulator

MAP = __import__("pathlib").Path(__file__).resolve().parents[1] / "pico_studio" / "data" / "maps" / "hospital_2019.json"


def record(poses: int, frames: int, seed: int = 0) -> list[list[dict[str, Any]]]:
    """Per pose, its frames: scan, odometry, and the truth of that instant."""
    cfg = Config()
    gmap = load_map(MAP)
    first = Simulator(gmap, cfg.sim, seed=seed)
    starts = random_free_poses(first.world.segments(), first.truth.pose[:2], poses, 0.4,
                               np.random.default_rng(seed), gmap.bounds)
    runs = []
    for k, pose in enumerate(starts):
        sim = Simulator(gmap, cfg.sim, seed=seed + k, initial_pose=pose)
        session = Session(sim, behaviour=lambda f, wm: Command(0.05, 0.0, 0.4), history=1)
        vertices = frame_score._static_vertices(sim)
        seq = []
        for _ in range(frames):
            session.tick(0.05)
            t = sim.truth
            vc = t.visible_corners()
            seq.append({"laser": session.last_laser, "odom": session.last_odometry, "pose": tuple(t.pose),
                        "solid": t.segments(), "visible_walls": t.visible_walls(), "vertices": vertices,
                        "corners": vc.points, "convex": vc.convex, "openings": t.door_openings(),
                        "visible_doors": t.visible_doors()})
        runs.append(seq)
    return runs


def score(wm: Any, f: dict[str, Any]) -> frame_score.FrameScore:
    """One world model against its frame's recorded truth (score_frame's arithmetic)."""
    z = frame_score.zero_to_map(wm, f["pose"])
    return frame_score.score_arrays(
        walls=transform_segments(np.asarray(wm.local_map.walls, dtype=float), z),
        endpoint_property=np.asarray(wm.local_map.endpoint_property),
        corners=transform_points(np.asarray(wm.corners, dtype=float).reshape(-1, 2), z),
        corner_convex=np.asarray(wm.corner_convex, dtype=bool),
        doors=transform_segments(np.asarray(wm.doors, dtype=float).reshape(-1, 4), z),
        solid=f["solid"], visible_walls=f["visible_walls"], true_vertices=f["vertices"],
        visible_corners=f["corners"], visible_convex=f["convex"], openings=f["openings"],
        visible_doors=f["visible_doors"])


def rejudge(runs: list[list[dict[str, Any]]], limit: int | None = None) -> tuple[float, dict[str, Any]]:
    """(CPU s, summary) of perceiving and scoring every frame afresh."""
    params = Config().perception
    total = frame_score.RunScore()
    n = 0
    t0 = time.process_time()
    for seq in runs:
        p = Perceptor(params)
        for f in seq:
            if limit is not None and n >= limit:
                break
            total.add(score(p.step(f["laser"], f["odom"]), f))
            n += 1
    cpu = time.process_time() - t0
    out = total.summary()
    out.pop("ms_per_scan")
    return cpu, out


def measure(poses: int, frames: int, repeats: int, python_frames: int) -> dict[str, Any]:
    """Scoring a frame (compiled / uncompiled ms), re-judging the run (CPU s), same answers."""
    warm_up()
    runs = record(poses, frames)
    params = Config().perception
    pairs = []  # world models once, then the scoring alone
    for seq in runs:
        p = Perceptor(params)
        pairs += [(p.step(f["laser"], f["odom"]), f) for f in seq]

    def per_frame(items: list) -> float:
        times = []
        for _ in range(repeats):
            for wm, f in items:
                c0 = time.process_time()
                score(wm, f)
                times.append((time.process_time() - c0) * 1000)
        return float(np.median(times))

    fast = per_frame(pairs)
    with uncompiled():
        slow = per_frame(pairs[:python_frames])
    cpu, _ = rejudge(runs)
    _, a = rejudge(runs, python_frames)
    with uncompiled():
        _, b = rejudge(runs, python_frames)
    same = all(math.isclose(a[k], b[k], rel_tol=1e-9, abs_tol=1e-12) for k in a)
    return {"frames": len(pairs), "score_ms": fast, "score_ms_python": slow, "rejudge_s": cpu,
            "same": same, "compiled": a, "uncompiled": b}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--poses", type=int, default=12)
    ap.add_argument("--frames", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--python-frames", type=int, default=100)
    args = ap.parse_args()
    r = measure(args.poses, args.frames, args.repeats, args.python_frames)
    n = r["frames"]
    print(f"hospital_2019: {n} recorded frames; {load()}")
    print(f"  scoring a frame     {r['score_ms']:8.3f} ms compiled  {r['score_ms_python']:8.3f} ms .py_func  "
          f"({r['score_ms_python'] / r['score_ms']:.1f}x)")
    print(f"  re-judging the run  {r['rejudge_s']:8.2f} s CPU for {n} frames "
          f"({r['rejudge_s'] / n * 1000:.3f} ms a frame: perceive + score)")
    print(f"  same answers compiled and uncompiled ({args.python_frames} frames, every eval figure): {r['same']}")
    if not r["same"]:
        raise SystemExit(f"differ: {r['compiled']} vs {r['uncompiled']}")


if __name__ == "__main__":
    main()
