"""The perceptor: laser + odometry -> world model, a pure function of the previous state.

    state = PerceptorState.initial()
    wm, state = perceive(state, laser, odometry, cfg.perception)   # pure
    p = Perceptor(cfg.perception); wm = p.step(laser, odometry)       # thin stateful wrapper

Stages, in order (each its own module): locate -> scan (filter, resample, cluster) ->
proximity -> segment (+ least-squares refit) -> corners (spike, vector) -> laser motion ->
objects (small free-standing clusters tracked; moving ones held out) -> scan match (the
pose corrected against the local map) -> merge (local map) -> identify (corners, doors; doors found from
several places remembered: door_memory) -> entrance -> rooms. Per-stage wall-clock
times land in `WorldModel.timings_ms`.

Bad input (empty, all-NaN or all-inf scans, mismatched angle fields, odometry jumps) yields a
valid, possibly empty world model with a warning, never an exception: this runs inside the
robot's loop. The inputs and the previous state are never modified.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np

from pico_studio.config.perception_params import PerceptionParams
from pico_studio.core.geometry import compose
from pico_studio.core.io import LaserData, OdometryData
from pico_studio.core.perception.corners import spike_corners, vector_corners
from pico_studio.core.perception.door_memory import DoorMemory, remember
from pico_studio.core.perception.entrance import Estimate, entrance_in_scan, median_entrance
from pico_studio.core.perception.identify import View, identify
from pico_studio.core.perception.laser_motion import laser_motion
from pico_studio.core.perception.locate import LocateState, locate
from pico_studio.core.perception.merge import LocalMapState, drop_near, merge, scan_passes
from pico_studio.core.perception.objects import ObjectsState, track_objects
from pico_studio.core.perception.plugin_hooks import perceive_with_plugins
from pico_studio.core.perception.proximity import proximity_flags
from pico_studio.core.perception.rooms import rooms
from pico_studio.core.perception.scan import ScanPoints, process_scan
from pico_studio.core.perception.scan_match import match_scan
from pico_studio.core.perception.segment import Segments, segment_scan
from pico_studio.core.world_model import LocalMap, WorldModel

STAGES = ("locate", "scan", "proximity", "segment", "corners", "laser_motion", "objects", "scan_match", "merge",
          "identify", "entrance", "rooms")


@dataclass(frozen=True)
class PerceptorState:
    locate: LocateState
    local_map: LocalMapState
    entrance_history: tuple[Estimate, ...] = ()
    side_range: float | None = None
    corners: np.ndarray | None = None  # the previous scan's corners, robot frame then
    time: float = 0.0
    objects: ObjectsState = ObjectsState()
    door_evidence: np.ndarray | None = None  # identify's T-openings on short walls, counted over scans
    door_memory: DoorMemory = DoorMemory()  # doors found from several places (door_memory)

    @staticmethod
    def initial() -> PerceptorState:
        return PerceptorState(LocateState(), LocalMapState.empty())


def perceive(
    state: PerceptorState, laser: LaserData | None, odom: OdometryData | None, params: PerceptionParams
) -> tuple[WorldModel, PerceptorState]:
    try:  # the built-in stages below, unless plugins are selected (`plugin_hooks`)
        return perceive_with_plugins(state, laser, odom, params, _perceive)
    except Exception as e:  # a bug must not stop the robot: report it, keep the old state
        wm = WorldModel(time=state.time, pose=state.locate.pose, zero_pose=state.locate.zero_pose)
        wm.warnings.append(f"perceptor failed on this frame ({type(e).__name__}: {e}); state kept")
        return wm, state


def _perceive(
    state: PerceptorState, laser: LaserData | None, odom: OdometryData | None, params: PerceptionParams
) -> tuple[WorldModel, PerceptorState]:
    timings: dict[str, float] = {}
    warnings: list[str] = []
    clock = time.perf_counter()

    def lap(name: str) -> None:
        nonlocal clock
        now = time.perf_counter()
        timings[name] = (now - clock) * 1000.0
        clock = now

    loc, step, w = locate(state.locate, odom, params.locate)
    warnings += w
    lap("locate")
    stamp = state.time
    if laser is not None and np.isfinite(laser.timestamp):
        stamp = float(laser.timestamp)
    elif odom is not None and np.isfinite(odom.timestamp):
        stamp = float(odom.timestamp)
    if laser is None:
        new_state = replace(state, locate=loc, time=stamp)
        wm = _model(new_state, stamp, timings, warnings)
        return wm, new_state

    scan, w = process_scan(laser, params.scan, params.proximity)
    warnings += w
    lap("scan")
    prox = proximity_flags(scan.ranges, scan.valid, params.proximity)
    lap("proximity")
    segs = segment_scan(scan, params)
    lap("segment")
    spikes = spike_corners(scan, params.corners)
    vec, inner = vector_corners(scan, params.corners, params.scan.min_spacing)
    lap("corners")
    corners_now = np.vstack([spikes, vec])
    motion, matches = (None, 0)
    if state.corners is not None:
        motion, matches = laser_motion(state.corners, corners_now, step, params.laser_motion)
    if odom is None and motion is not None and params.locate.laser_motion_without_odometry:
        loc = replace(loc, pose=compose(loc.pose, motion))
    lap("laser_motion")
    objs, objects_state = track_objects(state.objects, scan, loc.pose, params.objects)
    lap("objects")
    fit = None
    if params.scan_match.enabled and len(state.local_map.walls):
        firm = state.local_map.hits >= params.scan_match.min_wall_hits
        points = scan.points
        if objs.held.any():  # not the points of objects being tracked
            points = points[~np.repeat(objs.held, scan.clusters[:, 1] - scan.clusters[:, 0])]
        fit = match_scan(points, state.local_map.walls[firm], loc.pose, step, params.scan_match)
        if fit.accepted:
            loc = loc.corrected(fit.pose)
    lap("scan_match")
    local_before = state.local_map
    if len(objs.vanished_at):  # what a moving object left where it stood (walls older than it stay, unless seen through)
        local_before = drop_near(local_before, objs.vanished_at, params.objects.max_size, objs.vanished_age,
                                 ~scan_passes(local_before.walls, loc.pose, scan, params.merge))
    free = segs
    if objs.held.any():  # the walls of objects being tracked stay out of the local map
        kept = ~objs.held[segs.cluster]
        free = Segments(segs.segments[kept], segs.index[kept], segs.cluster[kept], segs.end_kind[kept],
                        segs.rms[kept], segs.covariance[kept])
    local = merge(local_before, free, loc.pose, scan, params.merge, stamp)
    lap("merge")
    idx, conn = local.shown_walls(params.merge)
    view = View(scan.ranges, scan.angles, scan.valid, loc.pose, _tracked_beams(scan, objs.held))
    ident = identify(local.walls[idx], conn, local.seen_end[idx], loc.pose[:2], params.identify, view,
                     state.door_evidence, None if local.viewpoint is None else local.viewpoint[idx])
    doors, door_kind, door_memory = remember(state.door_memory, ident.doors, ident.door_kind, local.walls[idx], conn,
                                             view, loc.pose[:2], params.identify)
    lap("identify")
    est = entrance_in_scan(segs.segments, params.entrance)
    history = state.entrance_history
    if est is not None:
        history = (history + (est,))[-params.entrance.median_scans :]
    entrance, hallway = median_entrance(history)
    lap("entrance")
    room, side = rooms(scan.ranges, scan.angles, scan.valid, state.side_range, params.rooms)
    lap("rooms")

    new_state = PerceptorState(loc, local, history, side, corners_now, stamp, objects_state, ident.evidence,
                               door_memory)
    dynamic_points = scan.points[np.repeat(objs.dynamic, scan.clusters[:, 1] - scan.clusters[:, 0])] \
        if objs.dynamic.any() else np.zeros((0, 2))
    wm = WorldModel(  # every field given: no default made only to be replaced
        time=stamp, pose=loc.pose, zero_pose=loc.zero_pose, points=scan.all_points, beam_valid=scan.valid,
        proximity=prox, too_close=bool(prox.any()), current_map=segs.segments,
        current_map_covariance=segs.covariance, current_map_rms=segs.rms, spike_corners=spikes, vector_corners=vec,
        vector_corner_inner=inner, local_map=LocalMap(local.walls[idx], ident.endpoint_property),
        corners=ident.corners, corner_convex=ident.corner_convex, doors=doors, door_kind=door_kind,
        door_remembered=np.arange(len(doors)) >= len(ident.doors),
        object_walls=ident.object_wall, objects=objs.static_boxes, dynamic_obstacles=objs.dynamic_boxes,
        dynamic_points=dynamic_points, possible_doors=ident.possible_doors,
        possible_door_kind=ident.possible_door_kind, entrance=entrance, hallway=hallway, room=room,
        laser_motion=motion, laser_motion_matches=matches,
        pose_correction_quality=0.0 if fit is None else fit.quality,
        pose_corrected=False if fit is None else fit.accepted,
        global_pose=None, localisation_quality=0.0, lost=False, combined=None, extras={},
        timings_ms=timings, warnings=warnings,
    )
    timings["total"] = sum(timings.values())
    return wm, new_state


def _model(state: PerceptorState, stamp: float, timings: dict[str, float], warnings: list[str]) -> WorldModel:
    return WorldModel(
        time=stamp, pose=state.locate.pose, zero_pose=state.locate.zero_pose,
        timings_ms=timings, warnings=warnings,
    )


class Perceptor:
    """The stateful wrapper: keeps the state between steps; `reset()` starts afresh."""

    def __init__(self, params: PerceptionParams):
        self.params = params
        self.state = PerceptorState.initial()
        self.last: WorldModel | None = None

    def step(self, laser: LaserData | None, odometry: OdometryData | None) -> WorldModel:
        wm, self.state = perceive(self.state, laser, odometry, self.params)
        self.last = wm
        return wm

    def reset(self) -> None:
        self.state = PerceptorState.initial()
        self.last = None


def _tracked_beams(scan: ScanPoints, held: np.ndarray) -> np.ndarray | None:
    """(n,) bool: the beams of the clusters `held` (objects being tracked), from each one's first
    kept point's beam to its last; None when none is held."""
    if not held.any():
        return None
    out = np.zeros(len(scan.ranges), dtype=bool)
    for start, end in scan.clusters[held]:
        out[scan.beam[start] : scan.beam[end - 1] + 1] = True
    return out
