"""`pico-studio eval`: score the perceptor against the simulator's truth at random free poses.

    pico-studio eval --map examples/maps/hospital_2019.json --poses 50 --seed 0 --json

At each of K random free poses (reachable from the simulator's start pose with `--clearance`
from everything) a fresh perceptor watches the simulated robot turn slowly on the spot for
`--frames` scans (so its local map can form); the last frame is scored
(`pico_studio.sim.scoring`) and the scores are summed over all poses.
"""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

import cv2
import numpy as np

from pico_studio.cli.plugin_args import add_plugin_argument
from pico_studio.config import load_config
from pico_studio.core.geometry import compose, invert
from pico_studio.core.io import Command
from pico_studio.core.localisation import DistanceField, Localiser
from pico_studio.core.localisation.score import PoseScore, summary_line
from pico_studio.core.localisation.stage import LocalisingPerceptor
from pico_studio.core.perception import Perceptor
from pico_studio.errors import UserError
from pico_studio.json_map import load_map
from pico_studio.progress import Progress
from pico_studio.session import Session
from pico_studio.sim import Simulator
from pico_studio.sim.map_features import vertex_graph
from pico_studio.sim.scoring import RunScore, Tolerances, score_frame
from pico_studio.sim.sim_config import load_sim_config


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
    add_plugin_argument(p)
    p.set_defaults(func=_eval)


def random_free_poses(segments: np.ndarray, start: tuple[float, float], k: int, clearance: float,
                      rng: np.random.Generator, bounds: tuple[float, float, float, float],
                      resolution: float = 0.05) -> list[tuple[float, float, float]]:
    """K poses the robot could drive to from `start`: every segment is drawn into a grid
    grown by `clearance`, the free cells connected to the start cell are flood-filled, and K
    of them are drawn (a random point in the cell, a random heading). So poses lie inside the
    building, outside objects and thick walls, whatever way the map draws its walls."""
    x0, y0, x1, y1 = bounds
    x0, y0 = x0 - 2 * clearance, y0 - 2 * clearance
    w = int(math.ceil((x1 + 2 * clearance - x0) / resolution)) + 1
    h = int(math.ceil((y1 + 2 * clearance - y0) / resolution)) + 1
    grid = np.zeros((h + 2, w + 2), np.uint8)  # floodFill's mask needs a 1-cell border
    cells = np.round((segments.reshape(-1, 2) - (x0, y0)) / resolution).astype(np.int32).reshape(-1, 2, 2)
    img = np.zeros((h, w), np.uint8)
    thick = max(1, int(math.ceil(2 * clearance / resolution)))
    cv2.polylines(img, list(cells), False, 255, thick)
    grid[1:-1, 1:-1] = img
    sx, sy = (int(round((start[0] - x0) / resolution)), int(round((start[1] - y0) / resolution)))
    if not (0 <= sx < w and 0 <= sy < h):
        return []
    if img[sy, sx]:  # the start itself is tight: begin at the nearest free cell
        fy, fx = np.nonzero(img == 0)
        if len(fx) == 0:
            return []
        n = int(np.argmin((fx - sx) ** 2 + (fy - sy) ** 2))
        sx, sy = int(fx[n]), int(fy[n])
    filled = np.zeros((h, w), np.uint8)
    cv2.floodFill(filled, grid, (sx, sy), 1, flags=4)
    ys, xs = np.nonzero(filled)
    if len(xs) == 0:
        return []
    pick = rng.choice(len(xs), size=k, replace=len(xs) < k)
    jitter = rng.uniform(-0.5, 0.5, size=(k, 2)) * resolution
    out = []
    for (cx, cy), (jx, jy) in zip(zip(xs[pick], ys[pick], strict=True), jitter, strict=True):
        out.append((float(x0 + cx * resolution + jx), float(y0 + cy * resolution + jy),
                    float(rng.uniform(-math.pi, math.pi))))
    return out


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
    gmap = load_map(map_path)
    sc = load_sim_config(sim_config) if sim_config is not None else None
    first = Simulator(gmap, cfg.sim, sc, seed=seed)
    world = first.world
    vertices = vertex_graph(world.static).points
    rng = np.random.default_rng(seed)
    # closed doors count as walls here: the poses are those reachable from the start
    starts = random_free_poses(world.segments(), first.truth.pose[:2], poses, clearance, rng, gmap.bounds)
    if len(starts) < poses:
        raise UserError(f"found only {len(starts)} free poses with {clearance} m clearance", file=map_path)
    run = RunScore()
    localisation = PoseScore()
    dfield = DistanceField.from_map(gmap, cfg.localisation.field) if cfg.localisation.enabled else None
    with Progress(len(starts), "eval", "poses") as progress:
        for k, pose in enumerate(starts):
            progress.set(k)
            sim = Simulator(gmap, cfg.sim, sc, seed=seed + 1 + k, initial_pose=pose)
            perceptor: Any = Perceptor(cfg.perception)
            if dfield is not None:  # localised from the start pose as a sim config gives it
                perceptor = LocalisingPerceptor(perceptor, Localiser(cfg.localisation, gmap, pose, dfield),
                                                truth=lambda sim=sim: sim.truth.pose)
                perceptor.score = localisation
            session = Session(sim, perceptor=perceptor, behaviour=lambda f, wm: Command(0.0, 0.0, turn), history=1)
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
