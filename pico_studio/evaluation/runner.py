"""Running what is judged: the eval method (random free poses), behaviour runs, plain scored
runs and recordings, one scenario or a whole set, every one through `Session.frames`.

    result = evaluate_scenario(scenario, cfg)      # ScenarioResult(name, summary, metrics, ...)
    total = evaluate_scenarios(load_scenarios("smoke.yaml"), cfg, workers=2)
    total.metrics["perception_score"]              # the mean over the scenarios that have it

The CLI (`eval`, `run --behaviour`) calls the same functions (`evaluate_poses`,
`run_behaviour`), so a scenario and a command line with the same inputs give the same figures.
"""

from __future__ import annotations

import itertools
import math
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pico_studio.config import Config
from pico_studio.core.behaviours.registry import (
    DEFAULT_SECONDS,
    Drive,
    behaviour_name,
    make_behaviour,
)
from pico_studio.core.localisation import DistanceField, Localiser
from pico_studio.core.localisation.stage import LocalisingPerceptor
from pico_studio.core.perception import Perceptor
from pico_studio.errors import UserError
from pico_studio.evaluation.frame_score import Tolerances
from pico_studio.evaluation.judges import CabinetsVisited, EscapeJudge, RoomsCounted
from pico_studio.evaluation.metrics import flatten
from pico_studio.evaluation.poses import world_free_poses
from pico_studio.evaluation.run_score import PoseErrorScorer, PoseScore, RunScore, TruthScorer
from pico_studio.evaluation.scenarios import Scenario, ScenarioSet
from pico_studio.evaluation.worlds import make_world
from pico_studio.json_map import GlobalMap, load_map
from pico_studio.json_map.convert import as_heightmap
from pico_studio.json_map.openings import vertex_graph
from pico_studio.progress import Progress, ProgressObserver
from pico_studio.session import Session
from pico_studio.sim import Simulator
from pico_studio.sim.sim_config import SimConfigFile, load_sim_config

Pose = tuple[float, float, float]


def make_perceptor(cfg: Config, global_map: GlobalMap | None = None, pose: Pose | None = None, *,
                   localise: bool = False, field: Any = None) -> Any:
    """The perceptor, localising on `global_map` from `pose` when asked (the caller checks
    `cfg.localisation.enabled` where the user may switch it off: the hospital cannot)."""
    perceptor: Any = Perceptor(cfg.perception)
    if not localise or global_map is None:
        return perceptor
    return LocalisingPerceptor(perceptor, Localiser(cfg.localisation, global_map, pose, field))


def is_localising(perceptor: Any) -> bool:
    return isinstance(perceptor, LocalisingPerceptor)


# ----- the eval method ------------------------------------------------------------------------


def evaluate_poses(gmap: GlobalMap, cfg: Config, sim_config: SimConfigFile | None = None, *, seed: int = 0,
                   poses: int = 50, frames: int = 20, turn: float = 0.4, clearance: float = 0.4,
                   localise: bool = True, tol: Tolerances | None = None, progress: Progress | None = None,
                   file: str | None = None) -> dict[str, Any]:
    """At each of `poses` random free poses a fresh perceptor watches the simulated robot turn
    on the spot for `frames` scans; the last world model is scored, the scores summed over
    all poses (`RunScore.summary()` keys, plus "poses" and "localisation" when localised)."""
    if poses < 1:
        raise UserError(f"must be at least 1, got {poses}", field="--poses")
    if frames < 1:
        raise UserError(f"must be at least 1, got {frames}", field="--frames")
    if not math.isfinite(turn) or not math.isfinite(clearance) or clearance < 0:
        raise UserError("must be finite numbers (clearance >= 0)", field="--turn/--clearance")
    first = Simulator(gmap, cfg.sim, sim_config, seed=seed)
    world = first.world
    vertices = vertex_graph(world.static).points
    rng = np.random.default_rng(seed)
    # closed doors count as walls here: the poses are those reachable from the start
    starts = world_free_poses(world, first.truth.pose[:2], poses, clearance, rng, gmap.bounds)
    if len(starts) < poses:
        raise UserError(f"found only {len(starts)} free poses with {clearance} m clearance", file=file)
    run = RunScore()
    localisation = PoseScore()
    localising = localise and cfg.localisation.enabled
    dfield = DistanceField.from_map(gmap, cfg.localisation.field) if localising else None
    for k, pose in enumerate(starts):
        if progress is not None:
            progress.set(k)
        sim = Simulator(gmap, cfg.sim, sim_config, seed=seed + 1 + k, initial_pose=pose)
        # localised from the start pose as a sim config gives it
        perceptor = make_perceptor(cfg, gmap, pose, localise=localising, field=dfield)
        scorer = TruthScorer(sim, tol=tol, vertices=vertices, run=run, last_only=True)
        observers: list[Any] = [scorer]
        if localising:
            observers.append(PoseErrorScorer(score=localisation))
        session = Session(sim, perceptor=perceptor, behaviour=Drive(0.0, 0.0, turn), observers=observers)
        for _ in itertools.islice(session.frames(dt=1.0 / sim.laser.profile.rate_hz), frames):
            pass
        scorer.finish()
    out: dict[str, Any] = {"poses": run.count, "frames_per_pose": frames}
    out.update(run.summary())
    if localising:
        out["localisation"] = localisation.summary()
    return out


def evaluate_map(map_path: str, cfg: Config | None = None, *, sim_config: str | None = None, seed: int = 0,
                 poses: int = 50, frames: int = 20, turn: float = 0.4, clearance: float = 0.4,
                 tol: Tolerances | None = None, progress: Progress | None = None,
                 heightmap: bool = False) -> dict[str, Any]:
    """`pico-studio eval --map`: the eval method on a map file (read with `cfg.map`; with
    `heightmap`, as a heightmap image of it shows it: `as_heightmap`), localised when
    `cfg.localisation.enabled`; the summary (see `evaluate_poses`) with the map and seed."""
    cfg = cfg or Config()
    gmap = load_map(map_path, cfg.map)
    if heightmap:
        gmap = as_heightmap(gmap, cfg.map)
    sc = load_sim_config(sim_config) if sim_config is not None else None
    r = evaluate_poses(gmap, cfg, sc, seed=seed, poses=poses, frames=frames, turn=turn, clearance=clearance,
                       localise=True, tol=tol, progress=progress, file=map_path)
    return {"map": map_path, "seed": seed, **({"heightmap": True} if heightmap else {}), **r}


# ----- behaviour runs -------------------------------------------------------------------------


def run_behaviour(sim: Any, behaviour: Any, *, seconds: float, dt: float = 0.05, perceptor: Any = None,
                  progress: Progress | None = None, observers: list[Any] | None = None,
                  expected_rooms: list[int] | None = None) -> dict[str, Any]:
    """Run `behaviour` in `sim` until it is done or `seconds` pass; the judged result: its
    outcome (state, escaped, rooms, cabinets), the collisions, and the localisation error
    when `perceptor` localises."""
    start = sim.now()
    judges: list[Any] = [EscapeJudge(sim.world.map, start=start, pose=sim.truth.pose),
                         CabinetsVisited(behaviour), RoomsCounted(behaviour, expected_rooms)]
    watch: list[Any] = list(judges)
    pose_error = PoseErrorScorer() if is_localising(perceptor) else None
    if pose_error is not None:
        watch.append(pose_error)
    if progress is not None:
        watch.append(ProgressObserver(progress, start))
    session = Session(sim, perceptor=perceptor, behaviour=behaviour, observers=watch + list(observers or []))
    ticks = 0
    for _ in session.frames(until=start + seconds, dt=dt):
        ticks += 1
        if behaviour.done:
            break
    sim.send_base_reference(0.0, 0.0, 0.0)
    out = behaviour.result()
    judged: dict[str, Any] = {}
    for judge in judges:
        judged.update(judge.summary())
    out.pop("rooms", None)
    out.pop("cabinets_visited", None)
    result = {
        "behaviour": behaviour.name,
        "state": out.pop("state"),
        **judged,
        "collisions": sim.truth.collisions,
        "sim_seconds": round(sim.now() - start, 6),
        "ticks": ticks,
        "true_pose": [float(v) for v in sim.truth.pose],
        "distance_m": float(sim.truth.distance) if math.isfinite(sim.truth.distance) else None,
        **out,
    }
    if pose_error is not None:
        result["localisation"] = pose_error.summary()
    return result


def behaviour_run(spec: str, sim: Any, cfg: Config, *, seconds: float | None = None, dt: float = 0.05,
                  localise: bool | None = None, progress: Progress | None = None,
                  expected_rooms: list[int] | None = None) -> dict[str, Any]:
    """The behaviour `spec` built and run in `sim` (see `run_behaviour`). The perceptor runs
    only for what reads its world model (the hospital's global pose; the escape room when
    told to take the perceptor's entrance) or when `localise` asks; it localises for the
    hospital (or when `localise`)."""
    # the start pose the simulator was given (config, start area or its chosen free place):
    # what a user placing the robot knows; localisation refines it from there
    start = tuple(float(v) for v in sim.truth.pose)
    name = behaviour_name(spec)
    behaviour = make_behaviour(spec, cfg, sim.world.map, start)  # type: ignore[arg-type]
    localising = (name == "hospital") if localise is None else localise
    needs_wm = localising or name == "hospital" or (
        name == "escape-room" and cfg.behaviour.escape_room.entrance_source == "world_model")
    perceptor = make_perceptor(cfg, sim.world.map, start, localise=localising) if needs_wm else None  # type: ignore[arg-type]
    if seconds is None:
        seconds = DEFAULT_SECONDS.get(name, 10.0)
    return run_behaviour(sim, behaviour, seconds=seconds, dt=dt, perceptor=perceptor, progress=progress,
                         expected_rooms=expected_rooms)


def scored_run(sim: Any, cfg: Config, *, seconds: float, dt: float = 0.05, behaviour: Any = None,
               localise: bool = False, perceptor: Any = None, observers: list[Any] | None = None,
               progress: Progress | None = None) -> tuple[int, dict[str, Any]]:
    """Run `seconds` with the perceptor scored against the truth every scan (and the
    localisation when it localises): (ticks, {"perceptor": ..., "localisation": ...})."""
    if perceptor is None:
        perceptor = make_perceptor(cfg, sim.world.map, tuple(sim.truth.pose), localise=localise)
    scorer = TruthScorer(sim)
    watch: list[Any] = [scorer]
    pose_error = PoseErrorScorer() if is_localising(perceptor) else None
    if pose_error is not None:
        watch.append(pose_error)
    if progress is not None:
        watch.append(ProgressObserver(progress, sim.now()))
    session = Session(sim, perceptor=perceptor, behaviour=behaviour, observers=watch + list(observers or []))
    ticks = sum(1 for _ in session.frames(until=sim.now() + seconds, dt=dt))
    out: dict[str, Any] = {"perceptor": scorer.summary()}
    if pose_error is not None:
        out["localisation"] = pose_error.summary()
    return ticks, out


# ----- scenarios ------------------------------------------------------------------------------


@dataclass
class ScenarioResult:
    name: str
    summary: dict[str, Any]
    metrics: dict[str, float]
    frames: int
    seconds_wall: float


@dataclass
class SetResult:
    per_scenario: dict[str, ScenarioResult] = field(default_factory=dict)
    metrics: dict[str, float] = field(default_factory=dict)  # mean over the scenarios having each
    frames: int = 0

    def as_dict(self) -> dict[str, Any]:
        """JSON-able: the mean metrics and every scenario's summary and metrics."""
        return {
            "metrics": self.metrics,
            "frames": self.frames,
            "scenarios": {n: {"metrics": r.metrics, "summary": r.summary, "frames": r.frames,
                              "seconds_wall": r.seconds_wall} for n, r in self.per_scenario.items()},
        }


def evaluate_scenario(s: Scenario, cfg: Config, *, progress: Progress | None = None) -> ScenarioResult:
    """Run and judge one scenario (see `scenarios.py` for the methods)."""
    t0 = time.perf_counter()
    if s.recording is not None:
        summary = _recording(s, cfg, progress)
        frames = int(summary.get("frames_read", 0))
    else:
        gmap, start, expected, sc = _world(s, cfg)
        if s.poses is not None:
            summary = evaluate_poses(gmap, cfg, sc, seed=s.seed, poses=s.poses, frames=s.frames, turn=s.turn,
                                     clearance=s.clearance, localise=s.localise, progress=progress,
                                     file=s.map or s.world)
            frames = s.poses * s.frames
        else:
            sim = Simulator(gmap, cfg.sim, sc, seed=s.seed, initial_pose=start)
            if s.behaviour is not None and behaviour_name(s.behaviour) in DEFAULT_SECONDS:  # judged by outcome
                summary = behaviour_run(s.behaviour, sim, cfg, seconds=s.seconds, dt=s.dt,
                                        localise=s.localise or None, progress=progress, expected_rooms=expected)
                frames = int(summary["ticks"])
            else:
                b = make_behaviour(s.behaviour or "idle", cfg, gmap, start)
                frames, summary = scored_run(sim, cfg, seconds=10.0 if s.seconds is None else s.seconds, dt=s.dt,
                                             behaviour=b, localise=s.localise and cfg.localisation.enabled,
                                             progress=progress)
    metrics = flatten(summary)
    return ScenarioResult(s.name, summary, metrics, frames, time.perf_counter() - t0)


def _world(s: Scenario, cfg: Config) -> tuple[GlobalMap, Pose | None, list[int] | None, SimConfigFile | None]:
    """The scenario's map, the start pose it brings (a generated world's), the expected room
    contents (a room-finder world's) and the simulator config: the scenario's, else the one a
    furnished world brings (its people)."""
    sc = load_sim_config(s.sim_config) if s.sim_config is not None else None
    if s.world is not None:
        w = make_world(s.world)
        w.map.opening_params = cfg.map.openings
        expected = [int(r["objects"]) for r in w.rooms] if w.rooms else None  # type: ignore[call-overload]
        gmap = as_heightmap(w.map, cfg.map) if s.heightmap else w.map
        return gmap, w.start, expected, sc if sc is not None else w.sim_config
    assert s.map is not None
    gmap = load_map(s.map, cfg.map)
    return (as_heightmap(gmap, cfg.map) if s.heightmap else gmap), None, None, sc


def _recording(s: Scenario, cfg: Config, progress: Progress | None) -> dict[str, Any]:
    """Replay the recording through the perceptor (localising on the map when asked); the
    replay report, with the localisation error against the recorded truth."""
    from pico_studio.sources import open_source
    from pico_studio.sources.replay_run import run_replay

    assert s.recording is not None
    replay = open_source(s.recording, cfg.sources)
    gmap = load_map(s.map, cfg.map) if s.map is not None else None
    pose = replay.truth_pose() if s.localise else None
    perceptor = make_perceptor(cfg, gmap, pose, localise=s.localise and cfg.localisation.enabled)
    pose_error = PoseErrorScorer() if is_localising(perceptor) else None
    session = Session(replay, perceptor=perceptor, observers=[pose_error] if pose_error is not None else [])
    report = run_replay(session, replay, seconds=s.seconds, progress=progress)
    if pose_error is not None:
        report["localisation"] = pose_error.summary()
    return report


def evaluate_scenarios(ss: ScenarioSet, cfg: Config, *, workers: int = 1,
                       progress: Progress | None = None) -> SetResult:
    """Every scenario of the set (in `workers` processes when > 1); the mean of each metric
    over the scenarios that report it."""
    out = SetResult()
    results: list[ScenarioResult] = []
    if workers > 1 and len(ss.scenarios) > 1:
        import multiprocessing

        from pico_studio import plugins

        ctx = multiprocessing.get_context("spawn")  # no forked numba / thread state
        # each worker loads the plugins this process has (a config may select their stages)
        with ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=plugins.load_plugins,
                                 initargs=(plugins.specs(),)) as pool:
            futures = [pool.submit(evaluate_scenario, s, cfg) for s in ss.scenarios]
            for k, f in enumerate(futures):
                results.append(f.result())
                if progress is not None:
                    progress.set(k + 1)
    else:
        for k, s in enumerate(ss.scenarios):
            results.append(evaluate_scenario(s, cfg))
            if progress is not None:
                progress.set(k + 1)
    for r in results:
        out.per_scenario[r.name] = r
        out.frames += r.frames
    out.metrics = mean_metrics([r.metrics for r in results])
    return out


def mean_metrics(rows: list[dict[str, float]]) -> dict[str, float]:
    """Each metric's mean over the rows that have it."""
    names = sorted({k for row in rows for k in row})
    return {k: float(np.mean([row[k] for row in rows if k in row])) for k in names}

