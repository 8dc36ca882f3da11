"""Run one of the reference behaviours in the simulator and score it against the truth.

    result = run_behaviour(sim, behaviour, seconds=120)
    result["escaped"], result["escape_seconds"], result["rooms"], result["collisions"]

`escaped`: the robot's true centre crossed one of the map's `finish` segments, or, for a map
without one, left the bounding box of all walls by at least `ESCAPE_MARGIN`. The run ends
when the behaviour is done (or gave up), the time is up, or the source stops.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from pico_studio.core.localisation import Localiser
from pico_studio.core.localisation.stage import LocalisingPerceptor
from pico_studio.core.perception import Perceptor
from pico_studio.json_map import GlobalMap
from pico_studio.progress import Progress
from pico_studio.session import Session

ESCAPE_MARGIN = 0.3  # m beyond the walls' bounding box counts as out (issue 7)


def _crosses(p: tuple[float, float], q: tuple[float, float], segments: np.ndarray) -> bool:
    """Does the move p -> q cross any segment (N, 4)?"""
    if len(segments) == 0:
        return False
    a, b = segments[:, 0:2], segments[:, 2:4]

    def orient(u: np.ndarray, v: np.ndarray, w: np.ndarray) -> np.ndarray:
        return (v[..., 0] - u[..., 0]) * (w[..., 1] - u[..., 1]) - (v[..., 1] - u[..., 1]) * (w[..., 0] - u[..., 0])

    P, Q = np.array(p)[None, :], np.array(q)[None, :]
    d1, d2 = orient(a, b, P), orient(a, b, Q)
    d3, d4 = orient(P, Q, a), orient(P, Q, b)
    return bool(np.any((d1 * d2 <= 0) & (d3 * d4 < 0)))


class EscapeJudge:
    """Watches the true pose and says when (if ever) the robot got out."""

    def __init__(self, global_map: GlobalMap):
        self.finish = global_map.finish_segments
        walls = global_map.wall_segments.reshape(-1, 2)
        self.box = (*walls.min(axis=0), *walls.max(axis=0))
        self.escaped_at: float | None = None
        self._last: tuple[float, float] | None = None

    def update(self, xy: tuple[float, float], t: float) -> None:
        if self.escaped_at is None:
            if len(self.finish):
                if self._last is not None and _crosses(self._last, xy, self.finish):
                    self.escaped_at = t
            else:
                x0, y0, x1, y1 = self.box
                outside = max(x0 - xy[0], xy[0] - x1, y0 - xy[1], xy[1] - y1)
                if outside >= ESCAPE_MARGIN:
                    self.escaped_at = t
        self._last = xy


def run_behaviour(sim: Any, behaviour: Any, *, seconds: float, dt: float = 0.05,
                  perceptor: Any = None, progress: Progress | None = None) -> dict[str, Any]:
    """Tick a session until the behaviour is done or `seconds` pass; the scored result."""
    behaviour.ok_check = sim.ok
    session = Session(sim, perceptor=perceptor, behaviour=behaviour, history=1)
    judge = EscapeJudge(sim.world.map)
    start = sim.now()
    judge.update(tuple(sim.truth.pose[:2]), 0.0)
    ticks = 0
    while sim.ok() and sim.now() - start < seconds - 1e-9 and not behaviour.done:
        session.tick(dt)
        ticks += 1
        judge.update(tuple(sim.truth.pose[:2]), sim.now() - start)
        if progress is not None:
            progress.set(sim.now() - start)
    sim.send_base_reference(0.0, 0.0, 0.0)
    out = behaviour.result()
    escaped = judge.escaped_at is not None
    return {
        "behaviour": behaviour.name,
        "state": out.pop("state"),
        "escaped": escaped,
        "escape_seconds": judge.escaped_at if escaped else None,
        "rooms": out.pop("rooms"),
        "cabinets_visited": out.pop("cabinets_visited"),
        "collisions": sim.truth.collisions,
        "sim_seconds": round(sim.now() - start, 6),
        "ticks": ticks,
        "true_pose": [float(v) for v in sim.truth.pose],
        "distance_m": float(sim.truth.distance) if math.isfinite(sim.truth.distance) else None,
        **out,
    }


def make_perception(cfg: Any, global_map: GlobalMap, initial_pose: Any, *, localise: bool) -> Any:
    """The perceptor, with localisation on the global map when the behaviour needs a global pose."""
    perceptor = Perceptor(cfg.perception)
    if not localise:
        return perceptor
    return LocalisingPerceptor(perceptor, Localiser(cfg.localisation, global_map, initial_pose))


def run_sim_behaviour(args: Any, cfg: Any) -> dict[str, Any]:
    """`pico-studio run --behaviour escape-room|room-finder|hospital[:i,j,k]` in the simulator:
    the scored result (see `run_behaviour`) plus the run's map, seed and timing."""
    import time
    from dataclasses import replace

    from pico_studio.core.behaviours.registry import DEFAULT_SECONDS, behaviour_name, make_behaviour
    from pico_studio.sim import Simulator

    params = cfg.sim if not args.realtime else replace(cfg.sim, realtime=True)
    sim = Simulator.from_files(args.map, args.sim_config, params, seed=args.seed)
    # the start pose the simulator was given (config, start area or its chosen free place):
    # what a user placing the robot knows; localisation refines it from there
    start = tuple(float(v) for v in sim.truth.pose)
    name = behaviour_name(args.behaviour)
    behaviour = make_behaviour(args.behaviour, cfg.behaviour, sim.world.map, start)
    # the perceptor runs only for what reads its world model: the hospital's global pose, the
    # escape room when told to take the perceptor's entrance (the rest work on the raw scan)
    needs_wm = name == "hospital" or (name == "escape-room" and cfg.behaviour.escape_room.entrance_source == "world_model")
    perceptor = make_perception(cfg, sim.world.map, start, localise=name == "hospital") if needs_wm else None
    seconds = DEFAULT_SECONDS[name] if args.seconds is None else args.seconds
    t0 = time.perf_counter()
    with Progress(seconds, f"{name}", "s simulated") as progress:
        result = run_behaviour(sim, behaviour, seconds=seconds, dt=args.dt or 0.05, perceptor=perceptor,
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
    for note in r.get("notes", []):
        print(f"  note: {note}")
