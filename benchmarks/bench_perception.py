"""Perceptor speed on simulated 1000-beam scans of hospital_2019: per stage and the whole step.

Scans: the simulator at random free poses (seeded), the robot turning slowly at each, so the
local map is realistic. Each recorded sequence is then perceived `--repeats` times; the
figure per stage is the median over all steps of all repeats. Segmentation alone (scan
stage + segmenter + refit, CPU time) is timed per segmenter and reported as scans per second,
with the same uncompiled (every kernel's `.py_func`) on the first 20 scans as its peer. A second
peer for split-and-merge is OpenCV's `cv2.approxPolyDP` (Douglas-Peucker in C++) per
cluster done naively (the production split did until it became a compiled loop of the same
arithmetic, see segment_split_merge.py), timed in the same process; the whole step is also
timed uncompiled (every compiled loop as its plain Python, `pico_studio.jit.uncompiled`). `step_cpu` is the step's process CPU time: on a machine shared with
other jobs the wall-clock step also counts the time the process waited for a core.

    python benchmarks/bench_perception.py [--poses 10] [--frames 20] [--repeats 5]

A speed-up must not change results: `--save-models F` writes the world models of the
recorded scans (all three segmenters) to F, and `--same-as F` checks them against such a file
(every number within 1e-9), e.g. saved before a change and checked after it.
"""

from __future__ import annotations

import argparse
import itertools
import math
import pickle
import statistics
import time
from pathlib import Path

import cv2
import numpy as np
from timing import load

from pico_studio.config import Config, with_value
from pico_studio.core.behaviours.registry import Drive
from pico_studio.core.perception import STAGES, Perceptor
from pico_studio.core.perception.scan import process_scan
from pico_studio.core.perception.segment import finish_pieces, segment_scan
from pico_studio.evaluation.poses import random_free_poses
from pico_studio.jit import uncompiled
from pico_studio.json_map import load_map
from pico_studio.session import Session
from pico_studio.sim import Simulator

ROOT = Path(__file__).resolve().parents[1]
MAP = ROOT / "pico_studio" / "data" / "maps" / "hospital_2019.json"


def record(poses: int, frames: int, seed: int) -> list[list[tuple]]:
    cfg = Config()
    gmap = load_map(MAP)
    first = Simulator(gmap, cfg.sim, seed=seed)
    starts = random_free_poses(first.world.segments(), first.truth.pose[:2], poses, 0.4,
                               np.random.default_rng(seed), gmap.bounds)
    runs = []
    for k, pose in enumerate(starts):
        sim = Simulator(gmap, cfg.sim, seed=seed + k, initial_pose=pose)
        session = Session(sim, behaviour=Drive(0.05, 0.0, 0.4))
        seq = [(session.last_laser, session.last_odometry)
               for _ in itertools.islice(session.frames(dt=0.05), frames)]
        runs.append(seq)
    return runs


def time_steps(runs: list[list[tuple]], params, repeats: int) -> dict[str, list[float]]:
    out: dict[str, list[float]] = {s: [] for s in (*STAGES, "step", "step_cpu")}
    for _ in range(repeats):
        for seq in runs:
            p = Perceptor(params)
            for laser, odom in seq:
                c0 = time.process_time()
                t0 = time.perf_counter()
                wm = p.step(laser, odom)
                out["step"].append((time.perf_counter() - t0) * 1000)
                out["step_cpu"].append((time.process_time() - c0) * 1000)
                for s in STAGES:
                    out[s].append(wm.timings_ms.get(s, 0.0))
    return out


def time_segmentation(scans: list, params, repeats: int) -> float:
    """Median CPU ms per scan of scan processing + segmentation + refit."""
    times = []
    for _ in range(repeats):
        for laser in scans:
            t0 = time.process_time()
            scan, _ = process_scan(laser, params.scan, params.proximity)
            segment_scan(scan, params)
            times.append((time.process_time() - t0) * 1000)
    return statistics.median(times)


def time_opencv_peer(scans: list, params, repeats: int) -> float:
    """The same split done by cv2.approxPolyDP per cluster (vertex indices recovered)."""
    eps = params.split_merge.split_distance
    times = []
    for _ in range(repeats):
        for laser in scans:
            t0 = time.process_time()
            scan, _ = process_scan(laser, params.scan, params.proximity)
            pts32 = scan.points.astype(np.float32)
            pieces = []
            for a, b in scan.clusters.tolist():
                if b - a < 2:
                    continue
                chunk = pts32[a:b]
                v = cv2.approxPolyDP(chunk.reshape(-1, 1, 2), eps, False).reshape(-1, 2)
                idx = a + np.flatnonzero(np.isin(chunk.view(np.complex64).ravel(), v.view(np.complex64).ravel()))
                pieces += list(zip(idx[:-1].tolist(), idx[1:].tolist(), strict=True))
            finish_pieces(scan, np.array(pieces, dtype=np.int64).reshape(-1, 2), params)
            times.append((time.process_time() - t0) * 1000)
    return statistics.median(times)


def world_models(runs: list[list[tuple]]) -> list[dict]:
    """The world model of every recorded scan, per segmenter, as plain data (no timings)."""
    out = []
    for name in ("split_merge", "angle", "ransac"):
        params = with_value(Config(), "perception.scan.segmenter", name).perception
        for seq in runs:
            p = Perceptor(params)
            for laser, odom in seq:
                d = p.step(laser, odom).to_dict()
                d.pop("timings_ms")
                out.append(d)
    return out


def first_difference(a, b, path: str = "", tol: float = 1e-9) -> str | None:  # noqa: ANN001
    """Where two plain-data world models differ (beyond `tol` for floats), or None."""
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            return f"{path}: keys {sorted(set(a) ^ set(b))}"
        return next((d for k in a if (d := first_difference(a[k], b[k], f"{path}.{k}", tol))), None)
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return f"{path}: length {len(a)} vs {len(b)}"
        return next((d for i, (x, y) in enumerate(zip(a, b, strict=True)) if (d := first_difference(x, y, f"{path}[{i}]", tol))), None)
    if isinstance(a, float) and isinstance(b, float):
        same = (math.isnan(a) and math.isnan(b)) or a == b or abs(a - b) <= tol
        return None if same else f"{path}: {a!r} vs {b!r}"
    return None if a == b else f"{path}: {a!r} vs {b!r}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--poses", type=int, default=10)
    ap.add_argument("--frames", type=int, default=20)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--save-models", type=Path, help="write the world models to this file and stop")
    ap.add_argument("--same-as", type=Path, help="check the world models against a --save-models file and stop")
    args = ap.parse_args()
    runs = record(args.poses, args.frames, args.seed)
    if args.save_models or args.same_as:
        models = world_models(runs)
        if args.save_models:
            args.save_models.write_bytes(pickle.dumps(models))
            print(f"{len(models)} world models written to {args.save_models}")
            return
        ref = pickle.loads(args.same_as.read_bytes())  # a file this script wrote
        diff = first_difference(ref, models, "models")
        print(f"{len(models)} world models: " + ("the same (within 1e-9)" if diff is None else f"DIFFER at {diff}"))
        raise SystemExit(0 if diff is None else 1)
    n = sum(len(r) for r in runs)
    beams = len(runs[0][0][0].ranges)
    print(f"hospital_2019: {n} simulated scans of {beams} beams, {args.repeats} repeats; {load()}")
    cfg = Config()
    timings = time_steps(runs, cfg.perception, args.repeats)
    print("\nsplit_merge (default), median ms per scan per stage:")
    for s in (*STAGES, "step", "step_cpu"):
        print(f"  {s:13s} {statistics.median(timings[s]):8.3f} ms")
    step = statistics.median(timings["step_cpu"])
    print(f"  whole step (process CPU time, robust to other jobs on the machine): {1000 / step:.0f} scans/s "
          f"({1000 / step / 20:.0f}x the 20 Hz loop); wall-clock 'step' includes time the process waited")
    with uncompiled():  # the peer: the same step with every compiled loop as plain Python
        slow = statistics.median(time_steps(runs[:2], cfg.perception, 1)["step_cpu"])
    print(f"  the same step uncompiled (.py_func of every kernel, {sum(len(r) for r in runs[:2])} scans): "
          f"{slow:.3f} ms ({slow / step:.1f}x the compiled step)")
    scans = [laser for seq in runs for laser, _ in seq]
    print("\nsegmentation alone (filter, resample, cluster, segment, refit):")
    for name in ("split_merge", "angle", "ransac"):
        params = with_value(cfg, "perception.scan.segmenter", name).perception
        ms = time_segmentation(scans, params, args.repeats)
        with uncompiled():
            slow = time_segmentation(scans[:20], params, 1)
        print(f"  {name:12s} {ms:7.3f} ms  {1000 / ms:7.0f} scans/s   uncompiled {slow:7.3f} ms ({slow / ms:.0f}x)")
    ours = time_segmentation(scans, cfg.perception, args.repeats)
    peer = time_opencv_peer(scans, cfg.perception, args.repeats)
    print(f"  split_merge vs cv2.approxPolyDP per cluster: {ours:.3f} ms vs {peer:.3f} ms "
          f"(ratio {peer / ours:.2f})")


if __name__ == "__main__":
    main()
