"""`pico-studio run --source bag:FILE|carmen:FILE|ros` and `--record FILE.bag`: the parts of
the run command that are about recordings and the live robot (run_cmd.py calls in here).

A replay runs to the end of its file, every frame through the perceptor (or at `--dt`
when given); the live robot runs `--seconds` of wall time. `--record` writes what the
session saw as a ROS 1 bag — for a replay that converts it (CARMEN -> bag, with the
corrected pose on the true-pose topic).
"""

from __future__ import annotations

import argparse
import json
import time
from typing import Any

from pico_studio.config import Config
from pico_studio.errors import UserError
from pico_studio.evaluation.agreement import AgreementObserver
from pico_studio.evaluation.runner import make_perceptor
from pico_studio.progress import Progress
from pico_studio.session import Session
from pico_studio.sources import SourceSpec, open_source
from pico_studio.sources.recorder import BagRecorder
from pico_studio.sources.replay_run import run_replay


def open_recorder(args: argparse.Namespace, cfg: Config) -> BagRecorder | None:
    if not args.record:
        return None
    return BagRecorder(args.record, cfg.sources.topics, compression=cfg.sources.recorder.compression)


def recorded(recorder: BagRecorder | None) -> dict[str, Any] | None:
    if recorder is None:
        return None
    recorder.close()
    return {"file": str(recorder.path), "messages": dict(sorted(recorder.counts.items()))}


def run_source(args: argparse.Namespace, spec: SourceSpec, cfg: Config, behaviour: Any) -> int:
    """Run a replay or the live robot; print the report (one JSON object with --json)."""
    source = open_source(spec, cfg.sources)
    recorder = None
    perceptor = None if args.no_perceptor else make_perceptor(cfg)
    t0 = time.perf_counter()
    try:
        recorder = open_recorder(args, cfg)
        if spec.kind == "ros":
            result = _run_live(args, source, perceptor, behaviour, recorder)
        else:
            agreement = AgreementObserver()  # local_map.agreement, for a replay with true poses
            session = Session(source, perceptor=perceptor, recorder=recorder, observers=[agreement])
            t0_rec, t1_rec = source.time_span
            total = t1_rec - t0_rec if args.seconds is None else min(args.seconds, t1_rec - t0_rec)
            with Progress(total, f"replaying {spec}", "s") as progress:
                result = run_replay(session, source, dt=args.dt, seconds=args.seconds, progress=progress)
            judged = agreement.summary()
            if judged["scans"]:
                result["local_map"] = judged
    finally:
        result_recorded = recorded(recorder)
        close = getattr(source, "close", None)
        if callable(close):  # the live robot: stop the base, leave the master
            close()
    result.update(source=str(spec), wall_seconds=time.perf_counter() - t0, recorded=result_recorded)
    if args.json:
        print(json.dumps(result))
        return 0
    _print_report(result)
    return 0


def _run_live(args: argparse.Namespace, source: Any, perceptor: Any, behaviour: Any, recorder: Any) -> dict[str, Any]:
    source.wait_connected(source.params.ros.connect_timeout)
    live = _LiveStatus(source)
    session = Session(source, perceptor=perceptor, behaviour=behaviour, recorder=recorder, observers=[live])
    dt = args.dt or 0.05
    seconds = 10.0 if args.seconds is None else args.seconds
    end = time.monotonic() + seconds  # the robot's clock is the wall's: run for wall seconds
    if time.monotonic() < end:
        for _ in session.frames(dt=dt):
            if time.monotonic() >= end:
                break
    status = source.status()
    return {
        **live.summary(),
        "status": status.message, "master_up": status.master_up, "warnings": source.warnings[:20],
    }


class _LiveStatus:
    """Counts ticks, scans read and ticks with stale data (an observer of the live run)."""

    name = "live"

    def __init__(self, source: Any):
        self.source = source
        self.ticks = self.scans = self.stale_ticks = 0

    def on_frame(self, sf: Any) -> None:
        self.ticks += 1
        self.scans += sf.frame.laser is not None
        self.stale_ticks += self.source.status().stale

    def summary(self) -> dict[str, Any]:
        return {"ticks": self.ticks, "frames_read": self.scans, "stale_ticks": self.stale_ticks}


def _print_report(r: dict[str, Any]) -> None:
    print(f"{r['source']}: {r['frames_read']} frames read in {r['ticks']} ticks ({r['wall_seconds']:.2f} s)")
    if "frames" in r:
        print(f"  {r['frames']} frames in the file over {r['duration_s']:g} s, beams {r['beams']}, "
              f"{r['odometry_readings']} odometry readings, {r['truth_poses']} true poses; "
              f"{r['frames_dropped']} dropped")
    if "status" in r:
        print(f"  {r['status']}; stale in {r['stale_ticks']} ticks")
    perceptor = r.get("perceptor")
    if perceptor:
        figures = ", ".join(
            f"{k} {v['median']:g} (max {v['max']:g})" for k, v in perceptor.items() if isinstance(v, dict)
        )
        print(f"  perceptor (median per frame): {figures}")
    for w in r.get("warnings", [])[:10]:
        print(f"  warning: {w}")
    if r.get("recorded"):
        print(f"  recorded {r['recorded']['file']}: {r['recorded']['messages']}")


def check_source_args(args: argparse.Namespace, spec: SourceSpec) -> None:
    if spec.kind == "sim" and not args.map:
        raise UserError("the simulator needs a map: --map FILE", field="--map")
    if spec.kind != "sim" and args.map:
        raise UserError(f"--map is for the simulator; {spec} brings its own data", field="--map")
