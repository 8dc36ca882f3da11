"""`pico-studio eval`: score the perceptor against the simulator's truth at random free poses,
or score a whole scenario set.

    pico-studio eval --map examples/maps/hospital_2019.json --poses 50 --seed 0 --json
    pico-studio eval --scenarios pico_studio/data/scenarios/smoke.yaml --workers 2 --json

At each of K random free poses (reachable from the simulator's start pose with `--clearance`
from everything) a fresh perceptor watches the simulated robot turn slowly on the spot for
`--frames` scans (so its local map can form); the last frame is scored and the scores are
summed over all poses (`pico_studio.evaluation.runner.evaluate_map`). A scenario set runs
each scenario (`evaluation.runner.evaluate_scenarios`) and prints each one's metrics and
their mean. This module only parses and prints.
"""

from __future__ import annotations

import argparse
import json

from pico_studio.cli import limits
from pico_studio.cli.plugin_args import add_plugin_argument
from pico_studio.config import load_config
from pico_studio.errors import UserError
from pico_studio.evaluation.metrics import DEFAULT_OBJECTIVE, METRICS
from pico_studio.evaluation.run_score import summary_line
from pico_studio.evaluation.runner import evaluate_map, evaluate_scenarios
from pico_studio.evaluation.scenarios import load_scenarios
from pico_studio.progress import Progress


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("eval", help="score the perceptor against the simulator's truth (a map or a scenario set)")
    p.add_argument("--map", help="a JSON map or heightmap image")
    p.add_argument("--scenarios", metavar="FILE.yaml", help="a scenario-set YAML file: score every scenario and the mean")
    p.add_argument("--only", metavar="NAME", action="append", help="with --scenarios: just this scenario (repeatable)")
    p.add_argument("--workers", type=limits.WORKERS, default=1, help="with --scenarios: scenarios run in this many processes (default 1)")
    p.add_argument("--sim-config", help="the official simulator's config JSON")
    p.add_argument("--config", help="a pico_studio config YAML (perception, localisation, map and sim sections)")
    p.add_argument("--seed", type=limits.SEED, default=0, help="seed of the poses and the simulator (default 0)")
    p.add_argument("--poses", type=limits.COUNT, default=50, help="random free poses to score (default 50)")
    p.add_argument("--frames", type=limits.COUNT, default=20, help="scans per pose (default 20, 1 s)")
    p.add_argument("--turn", type=limits.TURN, default=0.4, help="turn rate at each pose, rad/s (default 0.4)")
    p.add_argument("--clearance", type=limits.CLEARANCE, default=0.4, help="free space around each pose, m (default 0.4)")
    p.add_argument("--heightmap", action="store_true",
                   help="with --map: score it as a heightmap image shows it (drawn and read back first)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    add_plugin_argument(p)
    p.set_defaults(func=_eval)


def _eval(args: argparse.Namespace) -> int:
    if args.scenarios is not None:
        return _eval_set(args)
    if args.map is None:
        raise UserError("give a map (--map FILE) or a scenario set (--scenarios FILE.yaml)", field="--map")
    with Progress(args.poses, "eval", "poses") as progress:
        result = evaluate_map(args.map, load_config(args.config), sim_config=args.sim_config, seed=args.seed,
                              poses=args.poses, frames=args.frames, turn=args.turn, clearance=args.clearance,
                              progress=progress, heightmap=args.heightmap)
    if args.json:
        print(json.dumps(result))
        return 0
    r = result
    seen = " as a heightmap" if args.heightmap else ""
    print(f"{args.map}{seen}: {r['poses']} poses x {r['frames_per_pose']} scans, seed {r['seed']}")
    print(f"  walls    precision {r['wall_precision']:.3f}  recall {r['wall_recall']:.3f}  "
          f"end-point error {r['endpoint_error_m']:.3f} m")
    print(f"  corners  precision {r['corner_precision']:.3f}  recall {r['corner_recall']:.3f}  "
          f"convex/concave accuracy {r['convexity_accuracy']:.3f}")
    print(f"  doors    precision {r['door_precision']:.3f}  recall {r['door_recall']:.3f}  "
          f"({r['doors_detected']} found, {r['doors_visible']} visible)")
    print(f"  pose     error {r['pose_error_m']:.4f} m, {r['pose_error_rad']:.4f} rad")
    print(f"  speed    {r['ms_per_scan']:.3f} ms per scan (median)")
    if "localisation" in r:
        print(f"  localise {summary_line(r['localisation'])}")
    return 0


def _eval_set(args: argparse.Namespace) -> int:
    if args.map is not None:
        raise UserError("a scenario set names its own maps; drop --map", field="--map")
    if args.heightmap:
        raise UserError("a scenario set says per scenario (heightmap: true); drop --heightmap", field="--heightmap")
    cfg = load_config(args.config)
    ss = load_scenarios(args.scenarios)
    if args.only:
        ss = ss.select(args.only)
    with Progress(len(ss), f"eval {ss.name}", "scenarios") as progress:
        result = evaluate_scenarios(ss, cfg, workers=args.workers, progress=progress)
    if args.json:
        print(json.dumps({"scenarios_file": str(ss.path), "set": ss.name, "objective": DEFAULT_OBJECTIVE,
                          **result.as_dict()}))
        return 0
    print(f"{ss.path}: {len(ss)} scenarios, {result.frames} frames")
    names = [m for m in METRICS if any(m in r.metrics for r in result.per_scenario.values())]
    for name, r in result.per_scenario.items():
        figures = ", ".join(f"{m} {r.metrics[m]:.3f}" for m in names if m in r.metrics)
        print(f"  {name} ({r.seconds_wall:.1f} s): {figures}")
    print("  mean: " + ", ".join(f"{m} {result.metrics[m]:.3f}" for m in names if m in result.metrics))
    return 0
