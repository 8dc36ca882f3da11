"""Localisation: the robot's pose in the global map, and the combined map.

    loc = Localiser(cfg.localisation, global_map, initial_pose=None)   # builds the field once
    r = loc.step(points, odom_pose)          # points (M, 2) robot frame, odom (x, y, a)
    r.pose, r.quality, r.lost                # pose in the global map (None until found)
    loc.fill(wm)                             # sets wm.global_pose, localisation_quality,
                                             # lost and combined from wm.points / wm.pose

Pure form, for re-processing recorded frames (as `perceive` is):

    lmap = build_localisation_map(global_map, cfg.localisation)        # once per map
    state = TrackerState.initial(len(lmap.field.segments))
    result, state = localise_world_model(state, wm, lmap, cfg.localisation)  # fills wm

Modules: prior (initial pose), distance_field (the map's field), matcher (scan-to-map
alignment and pose search), tracker (predict / correct / lost flag), combined (the local map
in the global frame, tagged).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from pico_studio.config.localisation_params import LocalisationParams
from pico_studio.core.localisation.combined import CombinedMap, combine
from pico_studio.core.localisation.distance_field import DistanceField
from pico_studio.core.localisation.matcher import Pose
from pico_studio.core.localisation.prior import PosePrior, initial_prior, prior_pose
from pico_studio.core.localisation.tracker import (
    LocalisationMap,
    StepResult,
    TrackerState,
    localise,
)
from pico_studio.json_map.model import GlobalMap

__all__ = [
    "CombinedMap",
    "DistanceField",
    "LocalisationMap",
    "Localiser",
    "PosePrior",
    "StepResult",
    "TrackerState",
    "build_localisation_map",
    "combine",
    "initial_prior",
    "prior_pose",
    "localise",
    "localise_world_model",
]


def build_localisation_map(
    global_map: GlobalMap, params: LocalisationParams, initial_pose: Pose | None = None,
    dfield: DistanceField | None = None,
) -> LocalisationMap:
    """The distance field and prior of `global_map` (the field is the expensive part: pass
    one already built for the same map and field params to reuse it)."""
    if dfield is None:
        dfield = DistanceField.from_map(global_map, params.field)
    return LocalisationMap(dfield, initial_prior(global_map, params.prior, initial_pose),
                           global_map.bounds, len(global_map.walls), global_map.openings())


def localise_world_model(
    state: TrackerState, wm: Any, lmap: LocalisationMap, params: LocalisationParams
) -> tuple[StepResult, TrackerState]:
    """Localise on a WorldModel's scan points and zero-frame pose; set its `global_pose`,
    `localisation_quality`, `lost` and `combined` (and `timings_ms["localisation"]`)."""
    t0 = time.perf_counter()
    zero_pose: Pose = (float(wm.pose[0]), float(wm.pose[1]), float(wm.pose[2]))
    result, state = localise(state, np.asarray(wm.points, dtype=float).reshape(-1, 2), zero_pose,
                             lmap, params)
    wm.global_pose = result.pose
    wm.localisation_quality = result.quality
    wm.lost = result.lost
    wm.combined = None
    if result.pose is not None:
        local = getattr(wm, "local_map", None)
        walls = local.get("walls") if isinstance(local, dict) else getattr(local, "walls", None)
        wm.combined = combine(
            result.pose, zero_pose, np.zeros((0, 4)) if walls is None else walls, lmap.field,
            state.seen_hits, lmap.n_walls, params.combined,
            doors=getattr(wm, "doors", None),
            possible_doors=getattr(wm, "possible_doors", None),
            possible_door_kind=getattr(wm, "possible_door_kind", None),
            map_openings=lmap.openings,
        )
    timings = getattr(wm, "timings_ms", None)
    if isinstance(timings, dict):
        timings["localisation"] = (time.perf_counter() - t0) * 1000.0
    return result, state


class Localiser:
    """Stateful wrapper around `localise`, plus the combined map for a WorldModel."""

    def __init__(self, params: LocalisationParams, global_map: GlobalMap,
                 initial_pose: Pose | None = None, dfield: DistanceField | None = None):
        self.params = params
        self.global_map = global_map
        self.lmap = build_localisation_map(global_map, params, initial_pose, dfield)
        self.state = TrackerState.initial(len(self.lmap.field.segments))
        self.last: StepResult | None = None
        self.last_ms = 0.0

    def reset(self) -> None:
        self.state = TrackerState.initial(len(self.lmap.field.segments))
        self.last = None

    def step(self, points: np.ndarray, odom_pose: Pose) -> StepResult:
        t0 = time.perf_counter()
        self.last, self.state = localise(self.state, points, odom_pose, self.lmap, self.params)
        self.last_ms = (time.perf_counter() - t0) * 1000.0
        return self.last

    def combined(self, zero_pose: Pose, local_walls: np.ndarray, **doors: Any) -> CombinedMap | None:
        """The combined map at the last estimate (None before the first estimate)."""
        if self.last is None or self.last.pose is None:
            return None
        return combine(self.last.pose, zero_pose, local_walls, self.lmap.field,
                       self.state.seen_hits, self.lmap.n_walls, self.params.combined,
                       map_openings=self.lmap.openings, **doors)

    def fill(self, wm: Any) -> Any:
        """Localise on a WorldModel's scan and odometry pose and set its localisation fields."""
        t0 = time.perf_counter()
        self.last, self.state = localise_world_model(self.state, wm, self.lmap, self.params)
        self.last_ms = (time.perf_counter() - t0) * 1000.0
        return wm
