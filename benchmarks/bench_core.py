"""The fast-core table (issue 12): every target, measured now, with the uncompiled peer.

Runs the other benchmarks' measurements at a modest size and prints one table: the
perceptor step (1000 beams, hospital_2019), each segmenter's segmentation alone, truth
scoring of a frame, the localisation step, `pico-studio run --localise` (perceive + localise
+ score every frame, its real-time factor), re-judging a recorded 2,400-frame run, and the
hospital A* on hospital_2019 and restaurant_2024. Every figure is process CPU time (medians
over repeated runs) but the run's wall factor, simulated time over wall time as `run --json`
reports it; its CPU factor is the same loop timed in this process (`run_localise_row`: the
child's whole CPU time would count its start-up as well); "x py" is the same code with every compiled loop as its plain Python
(`pico_studio.jit.uncompiled`) timed in the same process. "issue" is the figure the issue
was filed with (before this work). The machine's load is printed with the table: on a
machine shared with other jobs, CPU times rise a little (shared caches), wall times a lot.

    python benchmarks/bench_core.py [--quick] [--only run]
"""

from __future__ import annotations

import argparse
import json
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

import bench_localisation
import bench_perception
import bench_planner
import bench_scoring
import bench_segmenters
from timing import load

from pico_studio.config import Config
from pico_studio.core.behaviours import planner
from pico_studio.core.behaviours.registry import make_behaviour
from pico_studio.evaluation.runner import make_perceptor, scored_run
from pico_studio.jit import py_func, uncompiled, warm_up
from pico_studio.sim import Simulator

ROOT = Path(__file__).resolve().parents[1]
HOSPITAL = ROOT / "pico_studio" / "data" / "maps" / "hospital_2019.json"
ROWS = ("perceptor", "segmentation", "scoring", "localisation", "run", "astar")
Row = tuple[str, str, str, str, str]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smaller samples (a minute or two)")
    ap.add_argument("--only", choices=ROWS, help="measure only these rows (a busy machine)")
    args = ap.parse_args()
    q = args.quick
    warm_up()
    print(f"# {load()} (before)")
    rows: list[Row] = []
    notes: list[str] = []
    for name in ROWS:
        if args.only in (None, name):
            got, note = MEASURE[name](q)
            rows += got
            notes += [note] if note else []
    print(f"# {load()} (after)")
    head = ("what", "issue", "now (CPU)", "x py", "target")
    widths = [max(len(r[i]) for r in [head, *rows]) for i in range(5)]
    for r in [head, tuple("-" * w for w in widths), *rows]:
        print("| " + " | ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)) + " |")
    for note in notes:
        print(f"# {note}")


def perceptor_rows(q: bool) -> tuple[list[Row], str]:
    runs = bench_perception.record(4 if q else 10, 20, 0)
    cfg = Config()
    step = statistics.median(bench_perception.time_steps(runs, cfg.perception, 2 if q else 5)["step_cpu"])
    with uncompiled():
        slow = statistics.median(bench_perception.time_steps(runs[:1], cfg.perception, 1)["step_cpu"])
    return [("perceptor step, 1000 beams, hospital_2019", "4.1 ms", f"{step:.3f} ms", f"{slow / step:.1f}x",
             "<= 0.5 ms")], ""


def segmentation_rows(q: bool) -> tuple[list[Row], str]:
    seg = bench_segmenters.measure(4 if q else 10, 20, 2 if q else 5, python_items=10 if q else 20)
    return [("segmentation (split-merge / angle / RANSAC)", "1,036 / 903 / 141 scans/s",
             " / ".join(f"{seg[n]['scans_per_s']:,.0f}" for n in bench_segmenters.SEGMENTERS) + " scans/s",
             " / ".join(f"{seg[n]['python_ms'] / seg[n]['compiled_ms']:.0f}x" for n in bench_segmenters.SEGMENTERS),
             ">= 10,000 scans/s")], ""


def scoring_rows(q: bool) -> tuple[list[Row], str]:
    sc = bench_scoring.measure(30.0 if q else 120.0, 2 if q else 3, 40 if q else 100)
    per = sc["rejudge_s"] / sc["frames"]  # a frame: perceive + score
    return [("truth scoring of a frame (kept truth / live: + truth queries)", "~4 ms",
             f"{sc['score_ms']:.3f} / {sc['score_ms'] + sc['truth_ms']:.3f} ms",
             f"{sc['score_ms_python'] / sc['score_ms']:.1f}x / {sc['truth_ms_python'] / sc['truth_ms']:.1f}x",
             "<= 0.3 ms"),
            ("re-judge a recorded 2,400-frame run", "~30 s", f"{per * 2400:.1f} s ({per * 1000:.2f} ms/frame)",
             "", "<= 2 s")], f"same answers compiled vs uncompiled (scoring + re-judging): {sc['same']}"


def localisation_rows(q: bool) -> tuple[list[Row], str]:
    loc = [bench_localisation.cost(name, seconds=10 if q else 20, repeats=2 if q else 5)
           for name in ("hospital_2019", "restaurant_2024")]
    return [("localisation step (hospital / restaurant)", "4.3 ms",
             " / ".join(f"{c['cpu_ms_per_step_median']:.3f}" for c in loc) + " ms",
             " / ".join(f"{c['compiled_speedup']:.0f}x" for c in loc), "<= 0.5 ms")], \
        f"localisation poses within {max(c['same_poses_as_py_func_within'] for c in loc):.1e} of their Python's"


RUN_ARGS = ("--seed", "3", "--behaviour", "drive:0.2,0,0.3", "--localise", "--json")


def run_localise_loop(seconds: float) -> tuple[float, float, int]:
    """(CPU s, wall s, ticks) of `run --localise`'s loop — what run_cmd times for its
    realtime_factor: the simulator, the localising perceptor and the scorers of RUN_ARGS,
    built first (map, distance field, compiled loops: start-up, not the run's cost)."""
    cfg = Config()
    sim = Simulator.from_files(str(HOSPITAL), None, cfg.sim, seed=3, map_params=cfg.map.heightmap)
    perceptor = make_perceptor(cfg, sim.world.map, sim.sim_config.initial_pose, localise=True)
    behaviour = make_behaviour("drive:0.2,0,0.3", cfg)
    c0, t0 = time.process_time(), time.perf_counter()
    ticks, _ = scored_run(sim, cfg, seconds=seconds, behaviour=behaviour, perceptor=perceptor)
    return time.process_time() - c0, time.perf_counter() - t0, ticks


def run_localise_rows(q: bool) -> tuple[list[Row], str]:
    """`run --localise` as a user runs it (a child process: its realtime_factor, wall clock)
    and its loop timed here in process CPU time (median over repeats). The child's own CPU
    time is reported apart: it also counts the interpreter, imports, map, distance field and
    loading the compiled loops, which a 30 s run's loop (about a second) does not contain."""
    seconds = 30.0 if q else 60.0
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run([sys.executable, "-m", "pico_studio", "run", "--map", str(HOSPITAL),
                          "--seconds", f"{seconds:g}", *RUN_ARGS], capture_output=True, text=True, check=True, cwd=ROOT)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    run = json.loads(out.stdout)
    child_cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    loops = [run_localise_loop(seconds) for _ in range(2 if q else 3)]
    cpu = statistics.median(c for c, _, _ in loops)
    ticks = loops[0][2]
    row = ("run --localise (perceive + localise + score)", "1-6x real time",
           f"{run['realtime_factor']:.1f}x wall, {seconds / cpu:.1f}x CPU ({1000 * cpu / ticks:.2f} ms/frame; "
           f"perceptor {run['perceptor']['ms_per_scan']:.2f} ms/scan)", "", ">= 50x real time")
    return [row], (f"run --localise --seconds {seconds:g}: the child process took {child_cpu:.2f} s CPU in all, "
                   f"{child_cpu - cpu:.2f} s of it start-up (interpreter, imports, map, distance field, compiled "
                   f"loops' cache) outside the loop its realtime_factor times")


def astar_rows(q: bool) -> tuple[list[Row], str]:
    rows: list[Row] = []
    for name in ("hospital_2019", "restaurant_2024"):
        grid, pairs = bench_planner.plans(name)
        fast = bench_planner.time_plans(planner._astar, grid, pairs, 3)
        sub = pairs[:: max(1, len(pairs) // 6)]
        slow = bench_planner.time_plans(py_func(planner._astar), grid, sub, 1)
        ratio = statistics.median(slow) / statistics.median(bench_planner.time_plans(planner._astar, grid, sub, 3))
        rows.append((f"A* {name} (median / worst)", "83 / 528 ms" if name == "hospital_2019" else "",
                     f"{statistics.median(fast):.2f} / {max(fast):.2f} ms", f"{ratio:.0f}x", "<= 5 / 20 ms"))
    return rows, ""


MEASURE = {"perceptor": perceptor_rows, "segmentation": segmentation_rows, "scoring": scoring_rows,
           "localisation": localisation_rows, "run": run_localise_rows, "astar": astar_rows}


if __name__ == "__main__":
    main()
