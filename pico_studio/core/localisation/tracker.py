"""Tracking the robot's pose in the global map, step by step, with a lost flag.

Every step:
1. *initialise* (first steps): search the prior's box and heading range for the pose that
   explains the scan best;
2. *predict*: move the last estimate by the odometry increment since the last step;
3. *correct*: align the scan to the map (matcher.refine) from the prediction; a correction
   larger than `max_correction` / `max_correction_angle` in one step is not believed (a
   kidnapped robot, a wrong local minimum) and the prediction is kept;
4. *quality* = fraction of beams explained by the map at the estimate. A step is bad below
   `quality_lost`. It is good at or above `quality_found` (`quality_confirm` for a pose only
   a widened search found) with walls that pin the position down (`min_constraint`: a
   corridor alone does not) and hardly a beam through a map wall (`max_through_walls`: an
   unmapped box makes beams short, a wrong pose sends them through). `lost` is raised after
   `lost_after` bad steps in a row and cleared after `found_after` good ones (hysteresis); a
   pose that only a widened search found must moreover stay good while the robot travels
   `confirm_distance`: one scan of a dead end fits any dead end of a wrong map;
5. *recover*: while lost, search a box around the estimate with any heading, at once and then
   every `every_steps` x (failed searches + 1) steps (at most `max_every_steps`); the box
   widens after every failed search (up to the whole map). A search result is taken only
   when it would be a good step, so a wrong map stays lost.

`localise` is a pure function of (state, scan, odometry) like the perceptor, so a recorded
frame can be re-processed with other parameters; `Localiser` (the package's __init__) is
the thin stateful wrapper.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from pico_studio.config.localisation_params import LocalisationParams
from pico_studio.core.geometry import compose, relative, transform_points, wrap_angle
from pico_studio.core.localisation.distance_field import DistanceField
from pico_studio.core.localisation.match_kernels import seen_hits_kernel
from pico_studio.core.localisation.matcher import (
    Match,
    Pose,
    beams_through_walls,
    refine,
    search,
    usable_points,
)
from pico_studio.core.localisation.prior import PosePrior


@dataclass(frozen=True)
class LocalisationMap:
    """What localisation needs of the global map, built once: its distance field and prior."""

    field: DistanceField
    prior: PosePrior
    bounds: tuple[float, float, float, float]
    n_walls: int  # the first n_walls segments of the field are the map's walls, in order
    openings: np.ndarray  # (K, 4) the map's door openings (GlobalMap.openings), what confirms a door


@dataclass(frozen=True)
class TrackerState:
    pose: Pose | None = None  # estimate in the global map; None until initialised
    odom: Pose | None = None  # odometry pose (zero frame) at the last step
    quality: float = 0.0
    lost: bool = True  # nothing is known before the first good steps
    bad_steps: int = 0
    good_steps: int = 0
    failed_searches: int = 0
    steps_since_search: int = 0
    good_from: Pose | None = None  # odometry pose where the current run of good steps began
    confirm: bool = False  # clearing lost waits for `confirm_distance` of good travel
    seen_hits: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))

    @classmethod
    def initial(cls, n_segments: int) -> TrackerState:
        return cls(seen_hits=np.zeros(n_segments, dtype=np.int64))


@dataclass(frozen=True)
class StepResult:
    pose: Pose | None
    quality: float
    lost: bool
    searched: bool  # a pose search ran this step (initialisation or recovery)
    corrected: bool  # the scan correction was accepted this step


def localise(
    state: TrackerState,
    points: np.ndarray,
    odom: Pose,
    lmap: LocalisationMap,
    params: LocalisationParams,
) -> tuple[StepResult, TrackerState]:
    """One step: `points` (M, 2) laser points in the robot frame, `odom` the odometry pose."""
    pts = usable_points(points, params.matcher.max_range)
    tp = params.tracker

    # 1. initialise from the prior, retrying (wider) until a good match is found
    if state.pose is None:
        if state.failed_searches and state.steps_since_search + 1 < _search_wait(state, params):
            new = replace(state, odom=odom, steps_since_search=state.steps_since_search + 1)
            return StepResult(None, state.quality, True, False, False), new
        if len(pts) < 3:  # nothing to search with: not a failed search
            return StepResult(None, 0.0, True, False, False), replace(state, odom=odom, quality=0.0)
        match = _search_prior(lmap, pts, params, state.failed_searches)
        if match is None or not _good(match, pts, lmap, params, strict=state.failed_searches > 0):
            new = replace(state, odom=odom, quality=match.quality if match else 0.0,
                          failed_searches=state.failed_searches + 1, steps_since_search=0)
            return StepResult(None, new.quality, True, True, False), new
        state = replace(state, pose=match.pose, odom=odom, failed_searches=0,
                        confirm=state.failed_searches > 0)
        return _finish(state, pts, match, lmap, params, searched=True, corrected=True)

    # 2. predict with the odometry increment
    assert state.odom is not None
    predicted = compose(state.pose, relative(state.odom, odom))

    # 3. correct by aligning the scan, unless the correction is implausibly large
    best, corrected = Match(predicted, 0.0, 0, False), False
    if len(pts) >= 3:
        m = refine(lmap.field, pts, predicted, params.matcher)
        jump = math.hypot(m.pose[0] - predicted[0], m.pose[1] - predicted[1])
        turn = abs(float(wrap_angle(m.pose[2] - predicted[2])))
        if jump <= tp.max_correction and turn <= tp.max_correction_angle:
            best, corrected = m, True
        else:
            best = Match(predicted, _quality(lmap, pts, predicted, params), 0, False)

    # 5. recover: while lost, search around the estimate every few steps
    searched = False
    if state.lost and len(pts) >= 3 and state.steps_since_search + 1 >= _search_wait(state, params):
        searched = True
        radius = params.search.lost_radius + params.search.lost_growth * state.failed_searches
        found = _search_around(lmap, pts, best.pose, radius, params)
        strict = state.failed_searches > 0
        if found is not None and _good(found, pts, lmap, params, strict) and found.quality > best.quality:
            best, corrected = found, True
            state = replace(state, failed_searches=0, confirm=state.failed_searches > 0)
        else:
            state = replace(state, failed_searches=state.failed_searches + 1)
    state = replace(state, pose=best.pose, odom=odom,
                    steps_since_search=0 if searched else state.steps_since_search + 1)
    return _finish(state, pts, best, lmap, params, searched=searched, corrected=corrected)


def _finish(
    state: TrackerState,
    pts: np.ndarray,
    match: Match,
    lmap: LocalisationMap,
    params: LocalisationParams,
    *,
    searched: bool,
    corrected: bool,
) -> tuple[StepResult, TrackerState]:
    """4. quality hysteresis and the seen-wall counts."""
    tp = params.tracker
    pose, q = match.pose, match.quality
    bad_steps = state.bad_steps + 1 if q < tp.quality_lost else 0
    good = state.lost and _good(match, pts, lmap, params, strict=state.confirm)  # only while lost
    good_steps = state.good_steps + 1 if good else 0
    good_from = (state.good_from if state.good_steps > 0 else state.odom) if good else None
    travelled = 0.0
    if good_from is not None and state.odom is not None:
        travelled = math.hypot(state.odom[0] - good_from[0], state.odom[1] - good_from[1])
    lost, confirm = state.lost, state.confirm
    if not lost and bad_steps >= tp.lost_after:
        lost = True
    elif lost and good_steps >= tp.found_after and (not confirm or travelled >= tp.confirm_distance):
        lost, confirm = False, False
    failed = state.failed_searches
    since_search = state.steps_since_search
    if lost and not state.lost:
        failed = 0  # a fresh loss starts with the narrow search, at once
        since_search = params.search.every_steps

    hits = state.seen_hits
    if not lost and len(pts):  # the explained points' nearest walls
        f = lmap.field
        hits = seen_hits_kernel(f.field, f.segment_index, f.x0, f.y0, f.resolution, pts, float(pose[0]),
                                float(pose[1]), float(pose[2]), float(params.matcher.inlier_distance), hits)

    new = replace(state, quality=q, lost=lost, bad_steps=bad_steps, good_steps=good_steps,
                  failed_searches=failed, steps_since_search=since_search, good_from=good_from,
                  confirm=confirm, seen_hits=hits)
    return StepResult(pose, q, lost, searched, corrected), new


def _search_wait(state: TrackerState, params: LocalisationParams) -> int:
    """Steps between two searches while lost: longer after every failed one, up to a cap."""
    sp = params.search
    return min(sp.every_steps * (1 + state.failed_searches), max(sp.every_steps, sp.max_every_steps))


def _good(match: Match, pts: np.ndarray, lmap: LocalisationMap, params: LocalisationParams,
          strict: bool) -> bool:
    """A good step: most beams explained (`quality_confirm` of them when `strict`: for a pose
    only a widened search found), by walls that pin the position down, and (checked last, it
    costs most) hardly a beam through a map wall."""
    tp = params.tracker
    least = tp.quality_confirm if strict else tp.quality_found
    if match.quality < least or match.constraint < tp.min_constraint:
        return False
    through = match.through
    if through is None:
        through = beams_through_walls(lmap.field, pts, match.pose, params.matcher)
    return through <= tp.max_through_walls


def _quality(lmap: LocalisationMap, pts: np.ndarray, pose: Pose, params: LocalisationParams) -> float:
    if len(pts) == 0:
        return 0.0
    d = lmap.field.distance(transform_points(pts, pose))
    return float(np.mean(d <= params.matcher.inlier_distance))


def _search_prior(
    lmap: LocalisationMap, pts: np.ndarray, params: LocalisationParams, failed: int
) -> Match | None:
    p = lmap.prior
    grow = params.search.lost_growth * failed
    return search(lmap.field, pts, (p.x, p.y), (p.half_x + grow, p.half_y + grow),
                  p.a, p.heading_range if failed == 0 else math.pi, params.search, params.matcher)


def _search_around(
    lmap: LocalisationMap, pts: np.ndarray, pose: Pose, radius: float, params: LocalisationParams
) -> Match | None:
    """Search a box of half-width `radius` around `pose` (clipped to the map), any heading."""
    x0, y0, x1, y1 = lmap.bounds
    lo_x, hi_x = max(x0, pose[0] - radius), min(x1, pose[0] + radius)
    lo_y, hi_y = max(y0, pose[1] - radius), min(y1, pose[1] + radius)
    if lo_x > hi_x or lo_y > hi_y:  # the estimate drifted off the map: search all of it
        lo_x, hi_x, lo_y, hi_y = x0, x1, y0, y1
    center = ((lo_x + hi_x) / 2, (lo_y + hi_y) / 2)
    return search(lmap.field, pts, center, ((hi_x - lo_x) / 2, (hi_y - lo_y) / 2),
                  pose[2], math.pi, params.search, params.matcher)
