"""`pico-studio compare A.yaml B.yaml`: two configs judged on the same sensor data.

    pico-studio compare defaults tuned.yaml --map examples/maps/hospital_2019.json --seconds 60
    pico-studio compare a.yaml b.yaml --source bag:tests/data/pico_real.bag --json
    pico-studio compare a.yaml b.yaml --scenarios examples/scenarios/smoke.yaml \\
        --fail-on doors.f1,walls.recall --tolerance 0.01      # exit 1 when B is worse

The drive is recorded once (with A's simulator and behaviour settings) and both configs
re-judge the same frames (`evaluation.compare`); exit 1 when B is worse than A by more than
`--tolerance` on a `--fail-on` metric, 2 on bad input.
"""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

from pico_studio.cli import limits
from pico_studio.cli.plugin_args import add_plugin_argument
from pico_studio.config import Config, load_config
from pico_studio.errors import UserError
from pico_studio.evaluation.compare import (
    Comparison,
    compare_runs,
    recording_run,
    scenario_runs,
    sim_run,
)
from pico_studio.evaluation.scenarios import load_scenarios
from pico_studio.sources import parse_source


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("compare", help="judge two configs on the same sensor data; exit 1 when B regresses")
    p.add_argument("a", metavar="A.yaml", help="config A (a partial YAML over the defaults; 'defaults' for none)")
    p.add_argument("b", metavar="B.yaml", help="config B, compared against A")
    add_plugin_argument(p)
    p.add_argument("--map", help="a JSON map or heightmap image: the simulator's (or, with --source, to localise on)")
    p.add_argument("--sim-config", help="the official simulator's config JSON (start pose, moving objects, ...)")
    p.add_argument("--source", default="sim", help="sim (default, needs --map), bag:FILE or carmen:FILE")
    p.add_argument("--scenarios", metavar="FILE", help="a scenario-set YAML (as eval --scenarios)")
    p.add_argument("--seconds", type=limits.SECONDS, action=limits.StepCap, help="seconds to drive (default 30; a recording: to its end)")
    p.add_argument("--dt", type=limits.DT, action=limits.StepCap, default=0.05, help="control period of the drive, s (default 0.05)")
    p.add_argument("--seed", type=limits.SEED, help="random seed of the simulator (default: sim.seed of A)")
    p.add_argument("--behaviour", default="wander", help="what drives the simulated robot (default wander)")
    p.add_argument("--localise", action="store_true", help="localise on the map; compare the pose errors too")
    p.add_argument("--fail-on", metavar="METRIC[,...]", default="",
                   help="exit 1 when B is worse than A on any of these (e.g. doors.f1,perception_score)")
    p.add_argument("--tolerance", type=limits.TOLERANCE, default=0.0, help="how much worse still passes (default 0)")
    p.add_argument("--workers", type=limits.WORKERS, default=2,
                   help="processes: 1 judges A then B here; 2 judges A and B at once (default 2); 4: A and B "
                        "each perceived in one process and localised + scored in another")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=_compare)


def _config(path: str) -> Config:
    return Config() if path == "defaults" else load_config(path)


def _compare(args: argparse.Namespace) -> int:
    if args.seconds is not None and not (math.isfinite(args.seconds) and args.seconds > 0):
        raise UserError(f"must be a positive number, got {args.seconds}", field="--seconds")
    if not (math.isfinite(args.dt) and 0 < args.dt <= 1.0):
        raise UserError(f"must be a number in (0, 1], got {args.dt}", field="--dt")
    if not (math.isfinite(args.tolerance) and args.tolerance >= 0):
        raise UserError(f"must be a non-negative number, got {args.tolerance}", field="--tolerance")
    fail_on = [m.strip() for m in args.fail_on.split(",") if m.strip()]
    cfg_a, cfg_b = _config(args.a), _config(args.b)
    comparison = _run(args, cfg_a, cfg_b)
    out = comparison.as_dict(fail_on, args.tolerance)  # an unknown --fail-on name is refused here
    if args.json:
        print(json.dumps(out))
    else:
        _print(args, comparison, out)
    return 1 if out["regressed"] else 0


def _run(args: argparse.Namespace, cfg_a: Config, cfg_b: Config) -> Comparison:
    spec = parse_source(args.source)
    if args.scenarios is not None:
        if spec.kind != "sim" or args.map is not None:
            raise UserError("give either --scenarios or --map / --source", field="--scenarios")
        runs, extra = scenario_runs(load_scenarios(args.scenarios), cfg_a, cfg_b, seconds=args.seconds, seed=args.seed)
        return compare_runs(runs, cfg_a, cfg_b, workers=args.workers, extra=extra)
    if spec.kind == "sim":
        if args.map is None:
            raise UserError("the simulator needs a map (or give --source bag:FILE|carmen:FILE, or --scenarios)",
                            field="--map")
        run = sim_run(args.map, cfg_a, sim_config=args.sim_config, seed=args.seed,
                      seconds=30.0 if args.seconds is None else args.seconds, dt=args.dt,
                      behaviour=args.behaviour, localise=args.localise)
    elif spec.kind in ("bag", "carmen"):
        if args.sim_config is not None:
            raise UserError("only for the simulator (--source sim)", field="--sim-config")
        run = recording_run(str(spec), cfg_a, seconds=args.seconds, map_path=args.map)
    else:
        raise UserError("compare needs recorded data: the simulator, bag:FILE or carmen:FILE", field="--source")
    return compare_runs([run], cfg_a, cfg_b, workers=args.workers)


def _fmt(v: Any) -> str:
    return f"{v:.4f}" if isinstance(v, float) else str(v)


def _print(args: argparse.Namespace, c: Comparison, out: dict[str, Any]) -> None:
    print(f"A = {args.a}, B = {args.b}: {out['frames']} frames judged by both")
    rows = out["metrics"]
    if rows:
        width = max(len(n) for n in rows)
        print(f"  {'metric':<{width}}  {'A':>9}  {'B':>9}  {'B - A':>9}")
        for name, r in rows.items():
            mark = "  worse" if name in out["regressed"] else ""
            print(f"  {name:<{width}}  {_fmt(r['a']):>9}  {_fmt(r['b']):>9}  {r['delta']:>+9.4f}{mark}")
    d = out["diff"]
    print(f"  B's world model at the end vs A's: walls +{d['walls_added']} -{d['walls_lost']}, "
          f"corners +{d['corners_added']} -{d['corners_lost']}, doors +{d['doors_added']} -{d['doors_lost']}; "
          f"{out['frames_differing']} frame(s) differ")
    ms = out["ms_per_scan"]
    if ms.get("a") is not None and ms.get("b") is not None:
        print(f"  perceptor time per scan: A {ms['a']:.2f} ms, B {ms['b']:.2f} ms (not compared)")
    for note in out["notes"]:
        print(f"  note: {note}")
    if out["regressed"]:
        print(f"  B is worse on: {', '.join(out['regressed'])} (tolerance {args.tolerance:g})")
