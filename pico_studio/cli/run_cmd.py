"""`pico-studio run`: drive the simulator headless for a while and report what happened.

    pico-studio run --map examples/maps/hospital_2019.json --seconds 30 \
        --behaviour drive:0.3,0,0.2 --seed 3 --json
"""

from __future__ import annotations

import argparse
import json
import math
import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

from pico_studio.cli.behaviour_run import print_behaviour_result, run_sim_behaviour
from pico_studio.cli.plugin_args import add_plugin_argument
from pico_studio.cli.run_sources import (
    check_source_args,
    make_perceptor,
    open_recorder,
    recorded,
    run_source,
)
from pico_studio.config import load_config
from pico_studio.core.behaviours.registry import BEHAVIOURS as CORE_BEHAVIOURS
from pico_studio.core.behaviours.registry import is_behaviour
from pico_studio.core.behaviours.registry import make_behaviour as make_core_behaviour
from pico_studio.core.io import Command
from pico_studio.errors import UserError
from pico_studio.progress import Progress
from pico_studio.session import Session
from pico_studio.sim import Simulator
from pico_studio.sim.scoring import run_scored
from pico_studio.sources import SOURCE_HELP, parse_source

# name -> factory(argument text after "name:", or "") -> behaviour callable; others add theirs
BEHAVIOURS: dict[str, Callable[[str], Callable[..., Any]]] = {}


def _idle(arg: str) -> Callable[..., Any]:
    if arg:
        raise UserError("idle takes no argument", field="--behaviour")
    return lambda frame, wm: None


def _drive(arg: str) -> Callable[..., Any]:
    parts = arg.split(",")
    try:
        vx, vy, va = (float(p) for p in parts)
    except ValueError:
        raise UserError(f"drive needs three numbers drive:VX,VY,VA, got {arg!r}", field="--behaviour") from None
    if not all(math.isfinite(v) for v in (vx, vy, va)):
        raise UserError(f"drive needs finite numbers, got {arg!r}", field="--behaviour")
    action = Command(vx, vy, va)
    return lambda frame, wm: action


BEHAVIOURS["idle"] = _idle
BEHAVIOURS["drive"] = _drive


def make_behaviour(spec: str) -> Callable[..., Any]:
    name, _, arg = spec.partition(":")
    if name not in BEHAVIOURS:
        known = sorted(BEHAVIOURS) + list(CORE_BEHAVIOURS)
        raise UserError(f"unknown behaviour {name!r}; known: {', '.join(known)}", field="--behaviour")
    return BEHAVIOURS[name](arg)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("run", help="run the simulator, a recording or the robot headless and report")
    p.add_argument("--source", default="sim", help=SOURCE_HELP + " (default sim)")
    p.add_argument("--map", help="a JSON map or heightmap image (for --source sim)")
    p.add_argument("--record", metavar="FILE.bag", help="record the run as a ROS 1 bag (laser, odometry, base references, true pose)")
    p.add_argument("--no-perceptor", action="store_true", help="only drive, read and record: no perceptor (and no scores), the simulator at full speed")
    p.add_argument("--sim-config", help="the official simulator's config JSON (start pose, moving objects, ...)")
    p.add_argument("--config", help="a pico_studio config YAML (partial files merge over the defaults)")
    p.add_argument("--seed", type=int, help="random seed (default: sim.seed of the config)")
    p.add_argument("--seconds", type=float, help="seconds to run (default 10; a replay runs to its end)")
    p.add_argument("--dt", type=float, help="control period in seconds (default 0.05 = 20 Hz; a replay meets every frame unless given)")
    p.add_argument("--behaviour", default="idle", help="idle | drive:VX,VY,VA | escape-room | room-finder | hospital[:I,J,K] (default idle)")
    p.add_argument("--realtime", action="store_true", help="pace to wall-clock time")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--localise", action="store_true",
                   help="run the perceptor and localisation on the map; report the pose error against the truth")
    add_plugin_argument(p)
    p.set_defaults(func=_run)


def _run(args: argparse.Namespace) -> int:
    if args.seconds is not None and not (math.isfinite(args.seconds) and args.seconds >= 0):
        raise UserError(f"must be a finite, non-negative number, got {args.seconds}", field="--seconds")
    if args.dt is not None and not (math.isfinite(args.dt) and args.dt > 0):
        raise UserError(f"must be a positive number, got {args.dt}", field="--dt")
    spec = parse_source(args.source)
    check_source_args(args, spec)
    cfg = load_config(args.config)
    if is_behaviour(args.behaviour):  # the reference behaviours (core/behaviours/registry.py)
        if spec.kind != "sim":
            return run_source(args, spec, cfg, make_core_behaviour(args.behaviour, cfg.behaviour))
        result = run_sim_behaviour(args, cfg)
        if args.json:
            print(json.dumps(result))
        else:
            print_behaviour_result(result)
        return 0
    behaviour = make_behaviour(args.behaviour)
    if spec.kind != "sim":
        if args.localise:
            raise UserError("needs the simulator (--source sim): a map and the true pose", field="--localise")
        return run_source(args, spec, cfg, behaviour)
    if args.no_perceptor and args.localise:
        raise UserError("localising needs the perceptor; drop --no-perceptor", field="--localise")
    params = cfg.sim if not args.realtime else replace(cfg.sim, realtime=True)
    sim = Simulator.from_files(args.map, args.sim_config, params, seed=args.seed, map_params=cfg.map.heightmap)
    recorder = open_recorder(args, cfg)
    perceptor = None if args.no_perceptor else make_perceptor(cfg)
    localising = _localising(cfg, sim, perceptor) if args.localise and cfg.localisation.enabled else None
    session = Session(sim, perceptor=localising or perceptor, behaviour=behaviour, recorder=recorder, history=1)
    t0 = time.perf_counter()
    scores = None
    try:
        seconds, dt = 10.0 if args.seconds is None else args.seconds, args.dt or 0.05
        with Progress(seconds, "simulating", "s") as progress:
            if perceptor is None:
                steps = session.run(seconds, dt, progress)
            else:  # the perceptor's figures against the simulator's truth, every scan
                steps, scores = run_scored(session, sim, seconds, dt, progress=progress)
    finally:
        record = recorded(recorder)
    wall = time.perf_counter() - t0
    odom = sim.odometry.pose
    result = {
        "map": args.map,
        "seed": sim.seed,
        "sim_seconds": round(sim.now(), 9),
        "wall_seconds": wall,
        "steps": steps,
        "realtime_factor": sim.now() / wall if wall > 0 else None,
        "collisions": sim.truth.collisions,
        "distance_m": sim.truth.distance,
        "true_pose": list(sim.truth.pose),
        "odom_pose": list(odom),
        "recorded": record,
        "perceptor": scores.summary() if scores is not None else None,
    }
    if localising is not None:
        result["localisation"] = localising.score.summary()
    if args.json:
        print(json.dumps(result))
        return 0
    x, y, a = sim.truth.pose
    print(f"{args.map}: {result['sim_seconds']:g} s simulated in {wall:.3f} s ({steps} steps)")
    print(f"  true pose ({x:.3f}, {y:.3f}, {a:.3f}), odometry ({odom[0]:.3f}, {odom[1]:.3f}, {odom[2]:.3f})")
    print(f"  distance {sim.truth.distance:.3f} m, collisions {sim.truth.collisions}")
    if record:
        print(f"  recorded {record['file']}: {record['messages']}")
    if scores is not None:
        r = result["perceptor"]
        print(f"  perceptor over {r['frames']} scans: walls P {r['wall_precision']:.3f} R {r['wall_recall']:.3f}, "
              f"doors P {r['door_precision']:.3f} R {r['door_recall']:.3f}, corners P {r['corner_precision']:.3f} "
              f"R {r['corner_recall']:.3f}, convexity {r['convexity_accuracy']:.3f}, "
              f"pose error {r['pose_error_m']:.3f} m, {r['ms_per_scan']:.2f} ms/scan")
    if localising is not None:
        from pico_studio.core.localisation.score import summary_line

        print("  localisation " + summary_line(result["localisation"]))
    return 0


def _localising(cfg: Any, sim: Simulator, perceptor: Any) -> Any:
    """The perceptor with localisation on the simulator's map, scored against its truth; the
    prior is the sim config's start pose when it has one, else the map's start area."""
    from pico_studio.core.localisation import Localiser
    from pico_studio.core.localisation.stage import LocalisingPerceptor

    localiser = Localiser(cfg.localisation, sim.world.map, sim.sim_config.initial_pose)
    return LocalisingPerceptor(perceptor, localiser, truth=lambda: sim.truth.pose)

