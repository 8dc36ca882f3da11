"""Truth scoring and re-judging a recorded run, compiled vs its own Python, on hospital_2019.

A run is recorded once, live: the simulator on hospital_2019 from its start area, the
`wander` behaviour, the perceptor, `--seconds` of simulated time at 20 Hz (120 s = 2,400
frames), every frame kept with the truth of that instant (`evaluation.kept_truth`).

- *scoring a frame*: `TruthScorer.score` of a kept world model against its frame's kept
  truth (what `pico-studio run` and the page do per scan), CPU ms per frame (median over the
  frames, `--repeats` times), compiled and uncompiled (`jit.uncompiled`: every compiled loop
  as its Python) in the same process;
- *the truth queries of a frame*: everything scoring asks the simulator's truth for one scan
  (`kept_truth.TruthSnapshot`: visible walls, corners in view, door openings and the doors
  seen — what a live `pico-studio run` pays on top of scoring), CPU ms per frame while
  recording (median), compiled and, on the first `--python-frames` scans, uncompiled;
- *re-judging the run*: the kept frames replayed (`sources.frames.FramesReplay`) through a
  fresh perceptor and scored against the kept truth, as after a slider change: CPU seconds
  for the whole run;
- *same answers*: the re-judged summary (every figure of `pico-studio eval`) compiled and
  uncompiled over the first `--python-frames` frames: equal within 1e-9.

    python benchmarks/bench_scoring.py [--seconds 120] [--repeats 3] [--python-frames 100]
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path
from typing import Any

import numpy as np
from timing import load

from pico_studio.config import Config
from pico_studio.core.behaviours.registry import make_behaviour
from pico_studio.core.perception import Perceptor
from pico_studio.evaluation.kept_truth import TruthKeeper, TruthSnapshot
from pico_studio.evaluation.run_score import TruthScorer
from pico_studio.jit import uncompiled, warm_up
from pico_studio.json_map import load_map
from pico_studio.session import FrameKeeper, Session, SessionFrame
from pico_studio.sim import Simulator
from pico_studio.sources.frames import FramesReplay

MAP = Path(__file__).resolve().parents[1] / "pico_studio" / "data" / "maps" / "hospital_2019.json"


class TimedKeeper(TruthKeeper):
    """A `TruthKeeper` that times each snapshot (the truth queries of a frame), CPU ms; on the
    first `python_frames` scans also uncompiled, the same snapshot again (same answers)."""

    def __init__(self, sim: Simulator, python_frames: int = 0):
        super().__init__(sim)
        self.python_frames = python_frames
        self.ms: list[float] = []
        self.ms_python: list[float] = []
        self.same = True

    def on_frame(self, sf: SessionFrame) -> None:
        if sf.frame.laser is None:
            return
        c0 = time.process_time()
        super().on_frame(sf)
        self.ms.append((time.process_time() - c0) * 1000)
        if len(self.ms_python) < self.python_frames:
            with uncompiled():
                c0 = time.process_time()
                slow = TruthSnapshot(self.sim.truth, self.sim.params.odometry.form)
                self.ms_python.append((time.process_time() - c0) * 1000)
            fast = self.snapshots[sf.index]
            self.same &= all(np.array_equal(getattr(fast, k), getattr(slow, k))
                             for k in ("_visible_walls", "_door_openings", "_visible_doors"))
            self.same &= all(np.array_equal(a, b) for a, b in zip(fast.visible_corners(), slow.visible_corners(), strict=True))


def record(seconds: float, seed: int = 0, python_frames: int = 0) -> tuple[FrameKeeper, TimedKeeper]:
    cfg = Config()
    gmap = load_map(MAP)
    sim = Simulator(gmap, cfg.sim, seed=seed)
    keep, keeper = FrameKeeper(), TimedKeeper(sim, python_frames)
    behaviour = make_behaviour("wander", cfg.behaviour, gmap, initial_pose=sim.truth.pose)
    Session(sim, perceptor=Perceptor(cfg.perception), behaviour=behaviour, observers=[keep, keeper]).run(seconds, 0.05)
    return keep, keeper


def rejudge(keep: FrameKeeper, keeper: TruthKeeper, limit: int | None = None) -> tuple[float, dict[str, Any]]:
    """(CPU s, summary without timings) of perceiving and scoring the kept frames afresh."""
    frames = [sf.frame for sf in keep.frames][:limit]
    replay = FramesReplay(frames)
    scorer = TruthScorer(lambda: keeper.at(replay.index), vertices=keeper.vertices)
    t0 = time.process_time()
    Session(replay, perceptor=Perceptor(Config().perception), observers=[scorer]).run(math.inf)
    cpu = time.process_time() - t0
    out = scorer.summary()
    out.pop("ms_per_scan")
    return cpu, out


def measure(seconds: float, repeats: int, python_frames: int) -> dict[str, Any]:
    """Scoring a frame (compiled / uncompiled ms), re-judging the run (CPU s), same answers."""
    warm_up()
    keep, keeper = record(seconds, python_frames=python_frames)
    scored = [(sf.world_model, keeper.at(sf.index)) for sf in keep.frames
              if sf.frame.laser is not None and sf.world_model is not None]

    def per_frame(items: list) -> float:
        times = []
        for _ in range(repeats):
            for wm, truth in items:
                scorer = TruthScorer(lambda truth=truth: truth, vertices=keeper.vertices)
                c0 = time.process_time()
                scorer.score(wm)
                times.append((time.process_time() - c0) * 1000)
        return float(np.median(times))

    fast = per_frame(scored)
    with uncompiled():
        slow = per_frame(scored[:python_frames])
    cpu, _ = rejudge(keep, keeper)
    _, a = rejudge(keep, keeper, python_frames)
    with uncompiled():
        _, b = rejudge(keep, keeper, python_frames)
    same = all(math.isclose(a[k], b[k], rel_tol=1e-9, abs_tol=1e-12) for k in a) and keeper.same
    return {"frames": len(keep.frames), "scored": len(scored), "score_ms": fast, "score_ms_python": slow,
            "truth_ms": float(np.median(keeper.ms)), "truth_ms_python": float(np.median(keeper.ms_python)),
            "rejudge_s": cpu, "same": same, "compiled": a, "uncompiled": b}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=120.0)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--python-frames", type=int, default=100)
    args = ap.parse_args()
    r = measure(args.seconds, args.repeats, args.python_frames)
    n = r["frames"]
    print(f"hospital_2019, wander: {n} recorded frames ({r['scored']} scans); {load()}")
    print(f"  scoring a frame     {r['score_ms']:8.3f} ms compiled  {r['score_ms_python']:8.3f} ms .py_func  "
          f"({r['score_ms_python'] / r['score_ms']:.1f}x)")
    print(f"  truth queries       {r['truth_ms']:8.3f} ms compiled  {r['truth_ms_python']:8.3f} ms .py_func  "
          f"({r['truth_ms_python'] / r['truth_ms']:.1f}x)  (live scoring of a frame: "
          f"{r['truth_ms'] + r['score_ms']:.3f} ms)")
    print(f"  re-judging the run  {r['rejudge_s']:8.2f} s CPU for {n} frames "
          f"({r['rejudge_s'] / n * 1000:.3f} ms a frame: perceive + score)")
    print(f"  same answers compiled and uncompiled ({args.python_frames} frames, every eval figure, and the truth queries): {r['same']}")
    if not r["same"]:
        raise SystemExit(f"differ: {r['compiled']} vs {r['uncompiled']}")


if __name__ == "__main__":
    main()
