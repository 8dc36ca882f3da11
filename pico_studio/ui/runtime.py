"""The live core behind the web page, without any viser: source, perceptor, behaviour, timeline.

`Studio` is what the page drives. One `tick(dt)` is one `Session.tick` (advance the source,
read, perceive, behave, send the base reference, observe). The session's perceptor is the
pure perceptor run on the studio's state; its observers are the truth scorer
(`evaluation.TruthScorer`) and the timeline: every frame with a new scan goes on it with the
state before it (perceptor, and localisation tracker when there is a map), so `reprocess()`
can re-run the pure perceptor and localisation on the frame under the cursor with the
current parameters.

Thread safety: the page's callbacks and the 20 Hz loop run on different threads; every public
method takes `self.lock`.
"""

from __future__ import annotations

import logging
import math
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from pico_studio.config import Config, get_value, with_value
from pico_studio.core.behaviours.registry import BEHAVIOURS as REGISTRY
from pico_studio.core.behaviours.registry import make_behaviour
from pico_studio.core.behaviours.wander import Wander
from pico_studio.core.geometry import compose, invert, wrap_angle
from pico_studio.core.io import BaseReference, LaserData, OdometryData, RobotIO
from pico_studio.core.localisation import (
    TrackerState,
    build_localisation_map,
    localise_world_model,
    prior_pose,
)
from pico_studio.core.perception import PerceptorState, perceive
from pico_studio.errors import UserError
from pico_studio.evaluation.run_score import TruthScorer, summarise
from pico_studio.json_map import GlobalMap
from pico_studio.session import Session, SessionFrame
from pico_studio.ui.reference_layer import ReferenceAgreement
from pico_studio.ui.timeline import FrameRecord, Pose, Timeline

log = logging.getLogger(__name__)


@dataclass
class SourceBundle:
    """A data source plus what it knows beside the RobotIO interface."""

    source: RobotIO
    truth_pose: Callable[[], Pose | None]  # map-frame ground truth, or None
    truth: Any = None  # the simulator's `sim.truth`, for scoring
    world: Callable[[], Any] | None = None  # (K, 4) moving parts of the simulated world, map frame
    kind: str = "sim"
    # the localisation prior the source knows (`prior.prior_pose`): a sim config's start pose,
    # and where the simulator put the robot (used when neither the config nor the map says)
    initial_pose: Pose | None = None
    start_pose: Pose | None = None


SourceFactory = Callable[[Config, GlobalMap | None], SourceBundle]

def _check_behaviour(spec: str, field: str) -> str:
    name = spec.partition(":")[0].strip()
    if name not in REGISTRY and name != "teleop":
        raise UserError(f"unknown behaviour {name!r}; choose one of {', '.join(BEHAVIOURS)}", field=field)
    return name


# what the behaviour dropdown offers: the registry's behaviours (those a bare name makes),
# and driving by hand; `set_behaviour` takes any registry spec (`drive:0.2,0,0`)
def behaviour_names() -> tuple[str, ...]:
    """Read when the page is built, so behaviours a plugin registered are in the list."""
    return (*(n for n, e in REGISTRY.items() if not e.needs_argument), "teleop")


BEHAVIOURS: tuple[str, ...] = behaviour_names()


class Studio:
    def __init__(
        self,
        cfg: Config,
        global_map: GlobalMap | None,
        make_source: SourceFactory,
        behaviour: str = "wander",
        map_name: str = "",
    ):
        self.lock = threading.RLock()
        self.cfg = cfg
        self.global_map = global_map
        self.map_name = map_name
        self._make_source = make_source
        self.behaviour_name = _check_behaviour(behaviour, "--behaviour")
        self.behaviour_spec = behaviour
        self.playing = True
        self.speed = 1.0
        self.cursor: int | None = None  # timeline position shown; None = follow the live frame
        self.perceive_ms: deque[float] = deque(maxlen=50)
        self.perceive_walltimes: deque[float] = deque(maxlen=50)
        # more observers of every new session, each made for its source (the what-if's kept run)
        self.observer_factories: list[Callable[[Studio], Any]] = []
        self.reset()

    # ----- lifecycle -----------------------------------------------------------------------
    def reset(self) -> None:
        """A fresh source (new simulator from the current config), perceptor and timeline."""
        with self.lock:
            bundle = self._make_source(self.cfg, self.global_map)
            old_close = getattr(getattr(self, "source", None), "close", None)
            if callable(old_close):  # the live robot's topics, a simulator's threads
                old_close()
            self.bundle = bundle
            self.source = bundle.source
            ui = self.cfg.ui
            self.timeline = Timeline(round(ui.timeline_seconds * ui.rate_hz))
            self.lmap = self._localisation_map()
            self.state: tuple[Any, Any] = self.initial_state()
            self.scorer = self._make_scorer()
            # a replay with true poses: its reference map (built once per recording) and
            # the local map's agreement with it
            self.reference = ReferenceAgreement(self.source) if ReferenceAgreement.applies(self.source) else None
            self.behaviour = self._make_behaviour(self.behaviour_spec)
            self.teleop_command: BaseReference | None = None
            self.teleop_until = 0.0
            self.cursor = None
            self.frame_count = 0
            self.perceive_ms.clear()
            self.perceive_walltimes.clear()
            self.last_command = BaseReference(0.0, 0.0, 0.0)
            self._perceived: FrameRecord | None = None  # the record the perceptor step filled
            self.session = Session(
                self.source,
                perceptor=_StudioPerceptor(self._session_perceive),
                behaviour=_StudioBehaviour(self),
                observers=[_TimelineObserver(self), *(make(self) for make in self.observer_factories)],
            )

    def initial_state(self) -> tuple[Any, Any]:
        """The perceptor's and localiser's state at the start of a run (a replay's jumps
        start from it when no checkpoint is near)."""
        tracker = TrackerState.initial(len(self.lmap.field.segments)) if self.lmap is not None else None
        return (PerceptorState.initial(), tracker)

    def _make_scorer(self) -> TruthScorer | None:
        """Scores against the simulator's truth (the live frames, at `ui.score_rate_hz`)."""
        truth = self.bundle.truth
        if truth is None:
            return None
        return TruthScorer(lambda: truth, every=self._score_every())

    def _score_every(self) -> int:
        ui = self.cfg.ui
        return max(1, round(ui.rate_hz / ui.score_rate_hz)) if ui.score_rate_hz > 0 else 1

    def _localisation_map(self) -> Any:
        """The global map's distance field and prior (built once per map and field params)."""
        if self.global_map is None or not len(self.global_map.walls):
            return None
        pose = prior_pose(self.bundle.initial_pose, self.global_map, self.cfg.localisation.prior,
                          self.bundle.start_pose)
        key = (id(self.global_map), self.cfg.localisation.field, self.cfg.localisation.prior, pose)
        if getattr(self, "_lmap_key", None) != key:
            old = getattr(self, "_lmap_key", None)
            same_field = old is not None and old[:2] == key[:2]  # the field is the expensive part
            self._lmap = build_localisation_map(self.global_map, self.cfg.localisation, pose,
                                                self._lmap.field if same_field else None)
            self._lmap_key = key
        return self._lmap

    def set_map(self, global_map: GlobalMap, name: str) -> None:
        """Switch the world to another map (the simulator restarts in it)."""
        with self.lock:
            old = (self.global_map, self.map_name)
            self.global_map, self.map_name = global_map, name
            try:
                self.reset()
            except Exception:
                self.global_map, self.map_name = old
                self.reset()
                raise

    # ----- the loop ----------------------------------------------------------------------
    def tick(self, dt: float) -> FrameRecord | None:
        """One control period through the session loop (advance, read, perceive, behave,
        send); a frame with a new scan goes on the timeline."""
        with self.lock:
            if not self.source.ok():
                self.playing = False
                return None
            before = self.frame_count
            self.session.tick(dt)  # the timeline observer appends a frame with a new scan
            return self.timeline.latest if self.frame_count != before else None

    def _forget_old_world_models(self, keep: int = 3) -> None:
        """Old frames keep what re-processing needs (readings, state before), not their world
        model: a shown frame is re-processed anyway, and 2 minutes of world models would cost
        hundreds of megabytes."""
        n = len(self.timeline)
        if n > keep:
            old = self.timeline[n - keep - 1]
            if self.cursor is None or old is not self.shown():
                old.wm = None

    def _session_perceive(self, laser: LaserData, odometry: OdometryData | None) -> Any:
        """The session's perceptor: the pure perceptor, remembering the state before the frame."""
        frame = FrameRecord(
            index=self.frame_count,
            time=self.source.now(),
            laser=laser,
            odometry=odometry,
            truth_pose=self.bundle.truth_pose(),
            state_before=self.state,
            sim_world=self.bundle.world() if self.bundle.world is not None else None,
        )
        self.frame_count += 1
        self.state = self._perceive(frame, live=True)
        self._perceived = frame
        return frame.wm

    def _on_frame(self, sf: SessionFrame) -> None:
        """The timeline observer: a frame with a new scan goes on the timeline, with the
        command sent and what the behaviour showed, scored against the truth at its rate."""
        frame, self._perceived = self._perceived, None
        if frame is None:  # no new scan this tick
            return
        cmd = sf.command
        if cmd is not None:
            frame.command = self.last_command = BaseReference(cmd.vx, cmd.vy, cmd.va, frame.time)
        if self.behaviour_name == "teleop":
            frame.behaviour_state = "teleop"
        elif self.behaviour is not None:
            self._note_behaviour(frame, self.behaviour)
        if self.scorer is not None and frame.wm is not None and self.cfg.ui.score_rate_hz > 0:
            n = self.scorer.run.count
            try:
                self.scorer.on_frame(sf)
            except Exception as e:  # a scoring bug must not take the page down
                log.warning("scoring failed: %s", e)
            if self.scorer.run.count != n:
                frame.score = self.scorer.run.last
        if self.reference is not None:
            self.reference.frame_agreement(frame)  # for the run's figure
        frame.map_xy = self.robot_pose_in_map(frame)[:2]
        self.timeline.append(frame)
        self._forget_old_world_models()

    def _perceive(self, frame: FrameRecord, *, live: bool) -> Any:
        """Run the perceptor (and localisation, with a map) on one frame with the current
        params; returns the state after: (perceptor state, tracker state or None)."""
        t0 = time.perf_counter()
        p_before, t_before = frame.state_before
        try:
            wm, p_after = perceive(p_before, frame.laser, frame.odometry, self.cfg.perception)
            t_after = t_before
            if self.lmap is not None and t_before is not None and self.cfg.localisation.enabled:
                _, t_after = localise_world_model(t_before, wm, self.lmap, self.cfg.localisation)
        except UserError as e:
            frame.errors = [str(e)]
            return frame.state_before
        state_after = (p_after, t_after)
        ms = (time.perf_counter() - t0) * 1000.0
        frame.wm = wm
        frame.errors = []
        self.perceive_ms.append(ms)
        if live:
            self.perceive_walltimes.append(time.monotonic())
        return state_after

    def _make_behaviour(self, spec: str) -> Any:
        """The registry's behaviour for `spec` (None for teleop: the page drives)."""
        if spec.partition(":")[0].strip() == "teleop":
            return None
        latest = self.timeline.latest if hasattr(self, "timeline") else None
        pose = self.robot_pose_in_map(latest) if latest is not None else self.bundle.truth_pose()
        return make_behaviour(spec, self.cfg, self.global_map, pose)

    def _teleop_command(self) -> BaseReference:
        if self.teleop_command is not None and time.monotonic() < self.teleop_until:
            return self.teleop_command
        return BaseReference(0.0, 0.0, 0.0)

    @staticmethod
    def _note_behaviour(frame: FrameRecord, behaviour: Any) -> None:
        """What the page shows of a behaviour: its `state`, and its `target` (x, y) and `plan`
        (K, 2) when it has them, in its `frame`: "zero" (the perceptor's), "odom" (the
        odometry readings', with its `pose` there) or "global" (the map)."""
        frame.behaviour_state = f"{getattr(behaviour, 'name', '')}: {getattr(behaviour, 'state', '')}"
        frame.behaviour_target = getattr(behaviour, "target", None)
        frame.behaviour_plan = getattr(behaviour, "plan", None)
        frame.behaviour_frame = str(getattr(behaviour, "frame", "zero"))
        frame.behaviour_pose = getattr(behaviour, "pose", None)

    # ----- controls ------------------------------------------------------------------------
    def teleop(self, vx: float, vy: float, va: float) -> None:
        """Drive by hand for `ui.teleop_hold` seconds (switches the behaviour to teleop)."""
        with self.lock:
            self.behaviour_name = self.behaviour_spec = "teleop"
            self.teleop_command = BaseReference(vx, vy, va)
            self.teleop_until = time.monotonic() + self.cfg.ui.teleop_hold

    def set_behaviour(self, name: str) -> None:
        base = _check_behaviour(name, "behaviour")
        with self.lock:
            behaviour = self._make_behaviour(name)  # may refuse (e.g. hospital without a map)
            self.behaviour_name, self.behaviour_spec, self.behaviour = base, name, behaviour

    def open_door(self) -> None:
        with self.lock:
            self.source.open_door()

    def set_param(self, path: str, value: Any) -> None:
        """Change one parameter (validated); perception changes re-process the shown frame."""
        with self.lock:
            self.set_config(with_value(self.cfg, path, value))

    def set_config(self, cfg: Config) -> None:
        with self.lock:
            self.cfg = cfg
            if self.scorer is not None:
                self.scorer.every = self._score_every()
            lmap = self._localisation_map()
            if lmap is not self.lmap:  # a new field: every kept frame localises afresh in it
                self.lmap = lmap
                tracker = TrackerState.initial(len(lmap.field.segments)) if lmap is not None else None
                self.state = (self.state[0], tracker)
                for frame in self.timeline:
                    frame.state_before = (frame.state_before[0], tracker)
            if isinstance(self.behaviour, Wander):
                self.behaviour.params = cfg.ui.wander
            self.reprocess()

    def reprocess(self) -> FrameRecord | None:
        """Re-run the perceptor on the frame under the cursor with the current parameters.

        On the live frame the result also becomes the state the loop carries on from, so the
        new values take effect from here on."""
        with self.lock:
            frame = self.shown()
            if frame is None:
                return None
            state_after = self._perceive(frame, live=False)
            if frame is self.timeline.latest:
                self.state = state_after
                frame.score = None  # stale; `rescore()` (after the redraw) computes it again
            return frame

    def rescore(self) -> None:
        """Score the live frame again after a re-processing (kept apart: it is slow, and the
        page redraws the layers before it)."""
        with self.lock:
            frame = self.shown()
            if frame is not None and frame is self.timeline.latest and frame.score is None and self.cfg.ui.score_rate_hz > 0:
                self._score_live(frame)

    def scrub(self, position: int | None) -> FrameRecord | None:
        """Show timeline position `position` (None: the live frame), re-processed."""
        with self.lock:
            self.cursor = None if position is None else self.timeline.clamp(position)
            return self.reprocess()

    def shown(self) -> FrameRecord | None:
        with self.lock:
            if not len(self.timeline):
                return None
            if self.cursor is None:
                return self.timeline.latest
            return self.timeline[self.timeline.clamp(self.cursor)]

    # ----- what the page shows ------------------------------------------------------------------
    def robot_pose_in_map(self, frame: FrameRecord) -> Pose:
        """Where robot-frame data (laser, current map) is drawn: the localised pose, else the
        ground truth, else the perceptor's zero frame put on the map origin."""
        wm = frame.wm
        g = getattr(wm, "global_pose", None)
        if g is not None:
            return tuple(map(float, g))  # type: ignore[return-value]
        if frame.truth_pose is not None:
            return frame.truth_pose
        if wm is not None:
            return tuple(map(float, wm.pose))  # type: ignore[return-value]
        o = frame.odometry
        return (o.x, o.y, o.a) if o is not None and o.form == "absolute" else (0.0, 0.0, 0.0)

    def zero_frame_in_map(self, frame: FrameRecord) -> Pose | None:
        """The map-frame pose of the perceptor's zero frame (where the local map is drawn)."""
        wm = frame.wm
        if wm is None:
            return None
        robot = self.robot_pose_in_map(frame)
        return compose(robot, invert(tuple(map(float, wm.pose))))  # type: ignore[arg-type]

    def metrics(self) -> dict[str, Any]:
        """Perception rate and per-stage times, and scores against the truth when simulated."""
        with self.lock:
            out: dict[str, Any] = {"frames": len(self.timeline)}
            w = list(self.perceive_walltimes)
            out["hz"] = (len(w) - 1) / (w[-1] - w[0]) if len(w) > 2 and w[-1] > w[0] else 0.0
            out["ms"] = self.perceive_ms[-1] if self.perceive_ms else math.nan
            frame = self.shown()
            wm = frame.wm if frame is not None else None
            out["stages"] = dict(getattr(wm, "timings_ms", {}) or {})
            out["warnings"] = list(getattr(wm, "warnings", []) or []) + (frame.errors if frame else [])
            out["counts"] = _counts(wm)
            rms = np.asarray(getattr(wm, "current_map_rms", ()), dtype=float)
            # how well the walls fit their points (median rms of the current map's walls, mm)
            out["fit_rms_mm"] = 1000 * float(np.median(rms)) if len(rms) else None
            out["scores"] = self._scores(frame)
            out["localisation"] = self._localisation_figures(frame)
            lm = getattr(wm, "laser_motion", None)
            out["laser_motion"] = tuple(map(float, lm)) if lm is not None else None
            out["laser_motion_matches"] = int(getattr(wm, "laser_motion_matches", 0) or 0)
            entrance = getattr(wm, "entrance", None)
            out["entrance"] = tuple(map(float, entrance)) if entrance is not None else None
            out["hallway"] = bool(getattr(wm, "hallway", False))
            out["room"] = dict(getattr(wm, "room", None) or {})
            out["agreement"] = self.reference.figures(frame) if self.reference is not None else {}
            return out

    def _scores(self, frame: FrameRecord | None) -> dict[str, dict[str, float]]:
        """The latest scored frame's and the run's scores (the live frames only: the truth is
        *now*; a frame on the timeline shows nothing)."""
        if self.cursor is not None or self.scorer is None or not self.scorer.run.count:
            return {}
        out = {"run": _score_figures(self.scorer.run.summary())}
        latest = frame.score if frame is not None and frame.score is not None else self.scorer.run.last
        out["frame"] = _score_figures(summarise(latest, 1))
        return out

    @staticmethod
    def _localisation_figures(frame: FrameRecord | None) -> dict[str, Any]:
        wm = frame.wm if frame is not None else None
        # no localiser ran (a replay without a map): no figures, rather than a "quality 0.00"
        if wm is None or "localisation" not in wm.timings_ms:
            return {}
        out: dict[str, Any] = {"quality": float(wm.localisation_quality), "lost": bool(wm.lost)}
        g, t = wm.global_pose, frame.truth_pose if frame is not None else None
        if g is not None and t is not None:
            out["error_m"] = math.hypot(g[0] - t[0], g[1] - t[1])
            out["error_rad"] = abs(float(wrap_angle(g[2] - t[2])))
        return out

    def _score_live(self, frame: FrameRecord) -> None:
        """Score a re-processed live frame against the simulator's truth now (not added to
        the run: the run scored the frame as it came)."""
        if self.scorer is None or frame.wm is None:
            return
        try:
            frame.score = self.scorer.score(frame.wm)
        except Exception as e:  # a scoring bug must not take the page down
            log.warning("scoring failed: %s", e)
            frame.score = None

    def param(self, path: str) -> Any:
        return get_value(self.cfg, path)


SCORE_FIGURES = {  # RunScore.summary() key -> label on the page
    "wall_precision": "wall P",
    "wall_recall": "wall R",
    "corner_precision": "corner P",
    "corner_recall": "corner R",
    "door_precision": "door P",
    "door_recall": "door R",
    "pose_error_m": "pose err m",
    "pose_error_rad": "pose err rad",
}


def _score_figures(summary: dict[str, Any]) -> dict[str, float]:
    return {label: float(summary[key]) for key, label in SCORE_FIGURES.items() if key in summary}


@dataclass
class _StudioPerceptor:
    """Adapter: the session calls `step(laser, odometry)`; the studio runs the pure perceptor."""

    step: Callable[[LaserData, OdometryData | None], Any]


class _StudioBehaviour:
    """The session's behaviour: the studio's current one (the registry's), or teleop."""

    def __init__(self, studio: Studio):
        self.studio = studio

    def step(self, world_model: Any, laser: LaserData | None, odometry: OdometryData | None,
             now: float, *, ok: bool = True) -> Any:
        s = self.studio
        if s.behaviour_name == "teleop":
            return s._teleop_command()
        if s.behaviour is None:
            return None
        return s.behaviour.step(world_model, laser, odometry, now, ok=ok)


class _TimelineObserver:
    """The session observer that keeps the studio's timeline (see `Studio._on_frame`)."""

    name = "timeline"

    def __init__(self, studio: Studio):
        self.studio = studio

    def on_frame(self, sf: SessionFrame) -> None:
        self.studio._on_frame(sf)

    def summary(self) -> dict[str, Any]:
        return {"frames": len(self.studio.timeline)}


def _counts(wm: Any) -> dict[str, int]:
    if wm is None:
        return {}
    out: dict[str, int] = {}
    for name in ("current_map", "corners", "doors", "possible_doors"):
        v = getattr(wm, name, None)
        if v is not None:
            out[name] = len(v)
    lm = getattr(wm, "local_map", None)
    walls = getattr(lm, "walls", None) if lm is not None else None
    if walls is not None:
        out["local_walls"] = len(walls)
    return out
