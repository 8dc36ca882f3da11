"""`pico-studio run`: drive the simulator headless for a while and report what happened.

    pico-studio run --map examples/maps/hospital_2019.json --seconds 30 \
        --behaviour drive:0.3,0,0.2 --seed 3 --json
"""

from __future__ import annotations

import argparse
import json
import math
import time
from dataclasses import replace
from typing import Any

from pico_studio.cli import limits
from pico_studio.cli.behaviour_run import print_behaviour_result, run_sim_behaviour
from pico_studio.cli.plugin_args import add_plugin_argument
from pico_studio.cli.run_sources import (
    check_source_args,
    open_recorder,
    recorded,
    run_source,
)
from pico_studio.config import load_config
from pico_studio.core.behaviours.registry import (
    DEFAULT_SECONDS,
    behaviour_help,
    behaviour_name,
    make_behaviour,
)
from pico_studio.core.localisation.prior import prior_pose
from pico_studio.errors import UserError
from pico_studio.evaluation.run_score import summary_line
from pico_studio.evaluation.runner import make_perceptor, scored_run
from pico_studio.progress import Progress
from pico_studio.session import RecorderObserver, Session
from pico_studio.sim import Simulator
from pico_studio.sources import SOURCE_HELP, parse_source


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("run", help="run the simulator, a recording or the robot headless and report")
    p.add_argument("--source", default="sim", help=SOURCE_HELP + " (default sim)")
    p.add_argument("--map", help="a JSON map or heightmap image (for --source sim)")
    p.add_argument("--record", metavar="FILE.bag", help="record the run as a ROS 1 bag (laser, odometry, base references, true pose)")
    p.add_argument("--no-perceptor", action="store_true", help="only drive, read and record: no perceptor (and no scores), the simulator at full speed")
    p.add_argument("--sim-config", help="the official simulator's config JSON (start pose, moving objects, ...)")
    p.add_argument("--config", help="a pico_studio config YAML (partial files merge over the defaults)")
    p.add_argument("--seed", type=limits.SEED, help="random seed (default: sim.seed of the config)")
    p.add_argument("--seconds", type=limits.SECONDS, action=limits.StepCap, help="seconds to run (default 10; a replay runs to its end)")
    p.add_argument("--dt", type=limits.DT, action=limits.StepCap, help="control period in seconds (default 0.05 = 20 Hz; a replay meets every frame unless given)")
    p.add_argument("--behaviour", default="idle", help=behaviour_help() + " (default idle)")
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
    if behaviour_name(args.behaviour) in DEFAULT_SECONDS:  # the judged reference behaviours
        if spec.kind != "sim":
            return run_source(args, spec, cfg, make_behaviour(args.behaviour, cfg))
        result = run_sim_behaviour(args, cfg)
        if args.json:
            print(json.dumps(result))
        else:
            print_behaviour_result(result)
        return 0
    behaviour = make_behaviour(args.behaviour, cfg)
    if spec.kind != "sim":
        if args.localise:
            raise UserError("needs the simulator (--source sim): a map and the true pose", field="--localise")
        return run_source(args, spec, cfg, behaviour)
    if args.no_perceptor and args.localise:
        raise UserError("localising needs the perceptor; drop --no-perceptor", field="--localise")
    params = cfg.sim if not args.realtime else replace(cfg.sim, realtime=True)
    sim = Simulator.from_files(args.map, args.sim_config, params, seed=args.seed, map_params=cfg.map.heightmap)
    recorder = open_recorder(args, cfg)
    if not args.no_perceptor:
        from pico_studio import jit

        jit.warm_up()  # load the compiled loops from their cache before the clock starts: not the run's cost
    t0 = time.perf_counter()
    scores: dict[str, Any] = {}
    try:
        seconds, dt = 10.0 if args.seconds is None else args.seconds, args.dt or 0.05
        with Progress(seconds, "simulating", "s") as progress:
            if args.no_perceptor:
                steps = Session(sim, behaviour=behaviour, recorder=recorder).run(seconds, dt, progress)
            else:  # the perceptor's figures against the simulator's truth, every scan
                # the localisation prior: the sim config's start pose when it has one, else the
                # map's start area, else where the simulator put the robot (the origin by the
                # official simulator's default)
                localise = args.localise and cfg.localisation.enabled
                prior = prior_pose(sim.sim_config.initial_pose, sim.world.map, cfg.localisation.prior,
                                   tuple(sim.truth.pose))  # type: ignore[arg-type]
                perceptor = make_perceptor(cfg, sim.world.map, prior, localise=localise)
                observers = [RecorderObserver(recorder)] if recorder is not None else []
                steps, scores = scored_run(sim, cfg, seconds=seconds, dt=dt, behaviour=behaviour,
                                           perceptor=perceptor, observers=observers, progress=progress)
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
        "perceptor": scores.get("perceptor"),
    }
    if "localisation" in scores:
        result["localisation"] = scores["localisation"]
    if args.json:
        print(json.dumps(result))
        return 0
    x, y, a = sim.truth.pose
    print(f"{args.map}: {result['sim_seconds']:g} s simulated in {wall:.3f} s ({steps} steps)")
    print(f"  true pose ({x:.3f}, {y:.3f}, {a:.3f}), odometry ({odom[0]:.3f}, {odom[1]:.3f}, {odom[2]:.3f})")
    print(f"  distance {sim.truth.distance:.3f} m, collisions {sim.truth.collisions}")
    if record:
        print(f"  recorded {record['file']}: {record['messages']}")
    if result["perceptor"] is not None:
        r = result["perceptor"]
        print(f"  perceptor over {r['frames']} scans: walls P {r['wall_precision']:.3f} R {r['wall_recall']:.3f}, "
              f"doors P {r['door_precision']:.3f} R {r['door_recall']:.3f}, corners P {r['corner_precision']:.3f} "
              f"R {r['corner_recall']:.3f}, convexity {r['convexity_accuracy']:.3f}, "
              f"pose error {r['pose_error_m']:.3f} m, {r['ms_per_scan']:.2f} ms/scan")
    if "localisation" in result:
        print("  localisation " + summary_line(result["localisation"]))
    return 0
