"""`pico-studio run --behaviour escape-room|room-finder|hospital[:i,j,k]` in the simulator: build
the simulator from the arguments, run and judge the behaviour (`evaluation.runner.behaviour_run`:
escaped, rooms, cabinets, collisions, and `localisation.pose_error_m` / `heading_error_rad`
as {median, max} when it localises), print the result.
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any

from pico_studio.core.behaviours.registry import DEFAULT_SECONDS, behaviour_name
from pico_studio.evaluation.run_score import summary_line
from pico_studio.evaluation.runner import behaviour_run
from pico_studio.progress import Progress
from pico_studio.sim import Simulator


def run_sim_behaviour(args: Any, cfg: Any) -> dict[str, Any]:
    """The judged result (see `evaluation.runner.run_behaviour`) plus the run's map, seed and
    timing."""
    params = cfg.sim if not args.realtime else replace(cfg.sim, realtime=True)
    sim = Simulator.from_files(args.map, args.sim_config, params, seed=args.seed, map_params=cfg.map.heightmap)
    name = behaviour_name(args.behaviour)
    seconds = DEFAULT_SECONDS[name] if args.seconds is None else args.seconds
    localise = True if getattr(args, "localise", False) else None
    t0 = time.perf_counter()
    with Progress(seconds, f"{name}", "s simulated") as progress:
        result = behaviour_run(args.behaviour, sim, cfg, seconds=seconds, dt=args.dt or 0.05, localise=localise,
                               progress=progress)
    wall = time.perf_counter() - t0
    return {"map": args.map, "seed": sim.seed, "wall_seconds": wall, **result}


def print_behaviour_result(r: dict[str, Any]) -> None:
    print(f"{r['map']}: {r['behaviour']} ended '{r['state']}' after {r['sim_seconds']:g} s simulated "
          f"({r['wall_seconds']:.1f} s wall), collisions {r['collisions']}")
    if r["escaped"]:
        print(f"  escaped after {r['escape_seconds']:.2f} s")
    for k, room in enumerate(r["rooms"]):
        print(f"  room {k + 1}: {room['objects']} object(s) ({room['edges']} edges)")
    if r["cabinets_visited"]:
        print(f"  visited {', '.join(map(str, r['cabinets_visited']))}")
    if "localisation" in r:
        print("  localisation " + summary_line(r["localisation"]))
    for note in r.get("notes", []):
        print(f"  note: {note}")
