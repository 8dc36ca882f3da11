"""`pico-studio eval`: score the perceptor against the simulator's truth at random free poses.

    pico-studio eval --map examples/maps/hospital_2019.json --poses 50 --seed 0 --json

At each of K random free poses (inside the walls, outside every object, `--clearance` from
everything) a fresh perceptor watches the simulated robot turn slowly on the spot for
`--frames` scans (so its local map can form); the last frame is scored
(`pico_studio.sim.scoring`) and the scores are summed over all poses.
"""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

import numpy as np

from pico_studio.core.config import load_config
from pico_studio.core.geometry import compose, invert, point_segment_distance
from pico_studio.core.localisation import DistanceField, Localiser
from pico_studio.core.localisation.score import PoseScore, summary_line
from pico_studio.core.localisation.stage import LocalisingPerceptor
from pico_studio.core.perception import Perceptor
from pico_studio.errors import UserError
from pico_studio.session import Action, Session
from pico_studio.sim import Simulator
from pico_studio.sim.map_features import vertex_graph
from pico_studio.sim.raycast import cast_rays
from pico_studio.sim.scoring import RunScore, Tolerances, score_frame
from pico_studio.sim.sim_config import load_sim_config
from pico_studio.sim.simulator import load_any_map


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("eval", help="score the perceptor against the simulator's truth")
    p.add_argument("--map", required=True, help="a JSON map or heightmap image")
    p.add_argument("--sim-config", help="the official simulator's config JSON")
    p.add_argument("--config", help="a pico_studio config YAML (perception and sim sections)")
    p.add_argument("--seed", type=int, default=0, help="seed of the poses and the simulator (default 0)")
    p.add_argument("--poses", type=int, default=50, help="random free poses to score (default 50)")
    p.add_argument("--frames", type=int, default=20, help="scans per pose (default 20, 1 s)")
    p.add_argument("--turn", type=float, default=0.4, help="turn rate at each pose, rad/s (default 0.4)")
    p.add_argument("--clearance", type=float, default=0.4, help="free space around each pose, m (default 0.4)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=_eval)


def random_free_poses(segments: np.ndarray, objects: np.ndarray, k: int, clearance: float,
                      rng: np.random.Generator, bounds: tuple[float, float, float, float]) -> list[tuple[float, float, float]]:
    """K poses inside the walls (rays in every direction hit something; an odd number of
    segments crossed towards +x), outside objects, at least `clearance` from every segment."""
    x0, y0, x1, y1 = bounds
    out: list[tuple[float, float, float]] = []
    fans = np.arange(16) * (2 * math.pi / 16)
    for _ in range(2000 * max(k, 1)):
        if len(out) >= k:
            break
        xy = rng.uniform((x0, y0), (x1, y1))
        if point_segment_distance(xy[None, :], segments).min() < clearance:
            continue
        if not np.isfinite(cast_rays((xy[0], xy[1]), fans, segments)).all():
            continue
        if _crossings(xy, segments) % 2 == 0:  # inside a thick wall's block or outside
            continue
        if len(objects) and _crossings(xy, objects) % 2 == 1:  # inside a cabinet or table
            continue
        out.append((float(xy[0]), float(xy[1]), float(rng.uniform(-math.pi, math.pi))))
    return out


def _crossings(xy: np.ndarray, segments: np.ndarray) -> int:
    """How many segments a ray from xy towards +x crosses."""
    (ax, ay), (bx, by) = segments[:, 0:2].T, segments[:, 2:4].T
    straddle = (ay > xy[1]) != (by > xy[1])
    with np.errstate(divide="ignore", invalid="ignore"):
        x = ax + (xy[1] - ay) * (bx - ax) / (by - ay)
    return int((straddle & (x > xy[0])).sum())


def evaluate(map_path: str, *, sim_config: str | None = None, config: str | None = None, seed: int = 0,
             poses: int = 50, frames: int = 20, turn: float = 0.4, clearance: float = 0.4,
             tol: Tolerances | None = None) -> dict[str, Any]:
    """Run the evaluation; the summary dict (see `RunScore.summary`)."""
    if poses < 1:
        raise UserError(f"must be at least 1, got {poses}", field="--poses")
    if frames < 1:
        raise UserError(f"must be at least 1, got {frames}", field="--frames")
    if not math.isfinite(turn) or not math.isfinite(clearance) or clearance < 0:
        raise UserError("must be finite numbers (clearance >= 0)", field="--turn/--clearance")
    cfg = load_config(config)
    gmap = load_any_map(map_path)
    sc = load_sim_config(sim_config) if sim_config is not None else None
    first = Simulator(gmap, cfg.sim, sc, seed=seed)
    world = first.world
    vertices = vertex_graph(world.static).points
    rng = np.random.default_rng(seed)
    objects = world.objects if len(world.objects) else np.zeros((0, 4))
    starts = random_free_poses(world.static, objects, poses, clearance, rng, gmap.bounds)
    if len(starts) < poses:
        raise UserError(f"found only {len(starts)} free poses with {clearance} m clearance", file=map_path)
    run = RunScore()
    localisation = PoseScore()
    dfield = DistanceField.from_map(gmap, cfg.localisation.field) if cfg.localisation.enabled else None
    for k, pose in enumerate(starts):
        sim = Simulator(gmap, cfg.sim, sc, seed=seed + 1 + k, initial_pose=pose)
        perceptor: Any = Perceptor(cfg.perception)
        if dfield is not None:  # localised from the start pose as a sim config gives it
            perceptor = LocalisingPerceptor(perceptor, Localiser(cfg.localisation, gmap, pose, dfield),
                                            truth=lambda sim=sim: sim.truth.pose)
            perceptor.score = localisation
        session = Session(sim, perceptor=perceptor, behaviour=lambda f, wm: Action(0.0, 0.0, turn), history=1)
        wm = None
        for _ in range(frames):
            session.tick(1.0 / sim.laser.profile.rate_hz)
            if session.world_model is not None and session.world_model is not wm:
                wm = session.world_model
                run.ms_per_scan.append(wm.timings_ms.get("total", 0.0))
        if wm is None:
            continue
        true_zero = None
        if wm.zero_pose is not None and cfg.sim.odometry.form == "absolute":
            map_from_odom = compose(sim.truth.pose, invert(sim.truth.odometry_pose))
            true_zero = compose(map_from_odom, tuple(wm.zero_pose))
        run.add(score_frame(wm, sim.truth, tol or Tolerances(), true_zero=true_zero, true_vertices=vertices))
    out = {"map": map_path, "seed": seed, "poses": len(run.frames), "frames_per_pose": frames}
    out.update(run.summary())
    if dfield is not None:
        out["localisation"] = localisation.summary()
    return out


def _eval(args: argparse.Namespace) -> int:
    result = evaluate(args.map, sim_config=args.sim_config, config=args.config, seed=args.seed,
                      poses=args.poses, frames=args.frames, turn=args.turn, clearance=args.clearance)
    if args.json:
        print(json.dumps(result))
        return 0
    r = result
    print(f"{args.map}: {r['poses']} poses x {r['frames_per_pose']} scans, seed {r['seed']}")
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
