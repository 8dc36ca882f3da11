"""Small built scenes for the clutter rules: walls as segments, a ray-cast laser, a robot.

Everything in metres, the laser at the robot's centre (no footprint)."""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np

from pico_studio.config import Config
from pico_studio.core.behaviours.registry import make_behaviour
from pico_studio.core.io import LaserData, OdometryData
from pico_studio.core.localisation.prior import prior_pose
from pico_studio.core.perception.identify import View
from pico_studio.core.perception.identify_kernels import ray_hits
from pico_studio.core.perception.merge import LocalMapState
from pico_studio.core.world_model import WorldModel
from pico_studio.evaluation.frame_score import as_pose, zero_to_map

# the generated furnished worlds live with the evaluation (scenario sets use them by name)
from pico_studio.evaluation.furnished_worlds import cafe_world, clutter_world, ward_world
from pico_studio.evaluation.runner import make_perceptor
from pico_studio.session import Session
from pico_studio.sim import Simulator

Pose = tuple[float, float, float]


def cast(walls: np.ndarray, pose: Pose, n: int = 720, fov: float = 2 * math.pi, max_range: float = 10.0) -> LaserData:
    """A scan of `walls` (W, 4) from `pose`: beam i at -fov/2 + i fov/n (robot frame)."""
    inc = fov / n
    rel = -fov / 2 + np.arange(n) * inc
    ang = rel + pose[2]
    d = np.column_stack([np.cos(ang), np.sin(ang)])
    a, e = walls[:, 0:2], walls[:, 2:4] - walls[:, 0:2]
    ao = a[None] - np.array(pose[:2])
    den = d[:, None, 0] * e[None, :, 1] - d[:, None, 1] * e[None, :, 0]
    safe = np.where(np.abs(den) > 1e-12, den, 1.0)
    t = (ao[..., 0] * e[None, :, 1] - ao[..., 1] * e[None, :, 0]) / safe
    u = (ao[..., 0] * d[:, None, 1] - ao[..., 1] * d[:, None, 0]) / safe
    t = np.where((np.abs(den) > 1e-12) & (t > 1e-9) & (u >= 0) & (u <= 1), t, np.inf).min(axis=1)
    ranges = np.where(t <= max_range, t, np.inf)
    return LaserData(0.01, max_range, float(rel[0]), float(rel[-1]), inc, 0.0, ranges)


def laser_view(solid: list[list[float]] | np.ndarray, robot: tuple[float, float], heading: float) -> View:
    """identify's `View` of a laser at `robot` facing `heading` (801 beams over +-2 rad) cast
    against `solid` walls, nothing within 8 m beyond them."""
    angles = np.linspace(-2.0, 2.0, 801)
    direction = np.stack([np.cos(angles + heading), np.sin(angles + heading)], axis=1)
    none = np.full(len(angles), -1, dtype=np.int64)
    ranges, _ = ray_hits(np.tile(robot, (len(angles), 1)), direction, np.array(solid, dtype=float), none, none)
    hit = np.isfinite(ranges) & (ranges < 8.0)
    return View(np.where(hit, ranges, 0.0), angles, hit, (robot[0], robot[1], heading))


def has_gap(gaps: np.ndarray, gap: list[float], tol: float) -> bool:
    """Is `gap` (x0, y0, x1, y1) one of `gaps` (N, 4), either way round, each end within `tol`
    (in x and in y)?"""
    a = np.asarray(gap, dtype=float).reshape(2, 2)
    return any(min(np.abs(a - d).max(), np.abs(a - d[::-1]).max()) < tol
               for d in np.asarray(gaps, dtype=float).reshape(-1, 2, 2))


def box(cx: float, cy: float, w: float, h: float | None = None) -> np.ndarray:
    """(4, 4) the sides of an axis-aligned box centred at (cx, cy)."""
    h = w if h is None else h
    x0, x1, y0, y1 = cx - w / 2, cx + w / 2, cy - h / 2, cy + h / 2
    return np.array([[x0, y0, x1, y0], [x1, y0, x1, y1], [x1, y1, x0, y1], [x0, y1, x0, y0]], dtype=float)


def local_state(walls: list[list[float]], hits: list[float]) -> LocalMapState:
    """A local map of `walls` seen `hits` times each, nothing connected, at step 100."""
    n = len(walls)
    return LocalMapState(np.array(walls, dtype=float), np.array(hits, dtype=float), np.zeros(n, dtype=np.int64),
                         np.zeros(n, dtype=np.int64), np.zeros((n, 2), dtype=bool), np.zeros((n, 2)),
                         np.full((n, 2), -1, dtype=np.int64), 100)


def room(w: float = 6.0, h: float = 4.0) -> np.ndarray:
    """(4, 4) a w x h room with a corner at the origin."""
    return box(w / 2, h / 2, w, h)


def odometry(pose: Pose, t: float) -> OdometryData:
    return OdometryData(pose[0], pose[1], pose[2], t)


MAPS = Path(__file__).resolve().parents[1] / "examples" / "maps"


def wander(name: str, frames: int, cfg: Config | None = None) -> tuple[WorldModel, np.ndarray]:
    """`frames` scans (20 Hz) of `wander` through examples/maps/NAME (its NAME_sim.json beside
    it), localised: the last world model and its zero frame's pose in the map (`zero_to_map`)."""
    cfg = cfg or Config()
    stem = name.rsplit(".", 1)[0]
    sim = Simulator.from_files(str(MAPS / name), str(MAPS / f"{stem}_sim.json"), cfg.sim, seed=0,
                               map_params=cfg.map.heightmap)
    prior = prior_pose(sim.sim_config.initial_pose, sim.world.map, cfg.localisation.prior, tuple(sim.truth.pose))
    per = make_perceptor(cfg, sim.world.map, prior, localise=True)
    wm = None
    for f in itertools.islice(Session(sim, perceptor=per, behaviour=make_behaviour("wander", cfg)).frames(dt=0.05),
                              frames):
        wm = f.world_model
    assert wm is not None
    return wm, np.asarray(zero_to_map(wm, as_pose(sim.truth.pose)), dtype=float)

__all__ = ["MAPS", "Pose", "box", "cafe_world", "cast", "clutter_world", "laser_view", "odometry", "room", "wander",
           "ward_world"]
