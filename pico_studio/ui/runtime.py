"""The live core behind the web page, without any viser: source, perceptor, behaviour, timeline.

`Studio` is what the page drives. One `tick(dt)` is one `Session.tick` (advance the source,
read, perceive, behave, send the base reference).
Every frame goes on the timeline with the state before it (perceptor, and localisation tracker
when there is a map), so `reprocess()` can re-run the pure perceptor and localisation on the
frame under the cursor with the current parameters.

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
from dataclasses import dataclass, fields
from typing import Any

from pico_studio.config import Config, get_value, with_value
from pico_studio.core.behaviours.registry import BEHAVIOURS as CORE_BEHAVIOURS
from pico_studio.core.behaviours.registry import make_behaviour
from pico_studio.core.behaviours.wander import Wander
from pico_studio.core.geometry import compose, invert, wrap_angle
from pico_studio.core.io import BaseReference, Frame, LaserData, OdometryData, RobotIO
from pico_studio.core.localisation import TrackerState, build_localisation_map, localise_world_model
from pico_studio.core.perception import PerceptorState, perceive
from pico_studio.errors import UserError
from pico_studio.json_map import GlobalMap
from pico_studio.session import Session
from pico_studio.ui.timeline import FrameRecord, Pose, Timeline

try:  # scoring against the simulator's truth lives in sim/ (the UI may import it, core may not)
    from pico_studio.sim import scoring
except ImportError:  # pragma: no cover - a build without the simulator
    scoring = None  # type: ignore[assignment]

log = logging.getLogger(__name__)


@dataclass
class SourceBundle:
    """A data source plus what it knows beside the RobotIO interface."""

    source: RobotIO
    truth_pose: Callable[[], Pose | None]  # map-frame ground truth, or None
    truth: Any = None  # the simulator's `sim.truth`, for scoring
    world: Callable[[], Any] | None = None  # (K, 4) moving parts of the simulated world, map frame
    kind: str = "sim"


SourceFactory = Callable[[Config, GlobalMap | None], SourceBundle]

BehaviourFactory = Callable[[str, Config, GlobalMap | None, Pose | None], Any]


def behaviour_factories() -> dict[str, BehaviourFactory]:
    """Behaviours the page can run: the built-in wander and the core registry's, all objects
    with `step(world_model, laser, odometry, now, *, ok)` returning a command (vx, vy, va,
    optional open_door) and `state`, `target`, `plan`, `frame` for drawing (see
    docs/ARCHITECTURE.md, the web UI). Factories get the spec (`name[:args]`, e.g.
    `hospital:0,2`), the config, the map and the robot's map pose now (when known)."""
    out: dict[str, BehaviourFactory] = {"wander": lambda _spec, cfg, _map, _pose: Wander(cfg.ui.wander)}
    for name in CORE_BEHAVIOURS:
        out[name] = lambda spec, cfg, m, pose: make_behaviour(spec, cfg.behaviour, m, initial_pose=pose)
    return out


def _check_behaviour(spec: str, field: str) -> str:
    name = spec.partition(":")[0].strip()
    if name not in BEHAVIOURS:
        raise UserError(f"unknown behaviour {name!r}; choose one of {', '.join(BEHAVIOURS)}", field=field)
    return name


BEHAVIOURS = (*behaviour_factories(), "teleop", "stop")  # what the behaviour dropdown offers


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
            tracker = TrackerState.initial(len(self.lmap.field.segments)) if self.lmap is not None else None
            self.state: tuple[Any, Any] = (PerceptorState.initial(), tracker)
            self.true_zero: Pose | None = None  # true pose when the perceptor took its zero
            self.run_score = RunningScore() if scoring is not None else None
            self.behaviour = self._make_behaviour(self.behaviour_spec)
            self.teleop_command: BaseReference | None = None
            self.teleop_until = 0.0
            self.cursor = None
            self.frame_count = 0
            self.perceive_ms.clear()
            self.perceive_walltimes.clear()
            self.last_command = BaseReference(0.0, 0.0, 0.0)
            self._pending: FrameRecord | None = None
            self.session = Session(
                self.source,
                perceptor=_SessionPerceptor(self._session_perceive),
                behaviour=self._session_behave,
                history=1,  # the timeline keeps the frames (with perceptor state) instead
            )

    def _localisation_map(self) -> Any:
        """The global map's distance field and prior (built once per map and field params)."""
        if self.global_map is None or not len(self.global_map.walls):
            return None
        key = (id(self.global_map), self.cfg.localisation.field, self.cfg.localisation.prior)
        if getattr(self, "_lmap_key", None) != key:
            self._lmap = build_localisation_map(self.global_map, self.cfg.localisation)
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
            self._pending = None
            self.session.tick(dt)
            frame, self._pending = self._pending, None
            if frame is not None:
                frame.map_xy = self.robot_pose_in_map(frame)[:2]
                self.timeline.append(frame)
                self._forget_old_world_models()
            return frame

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
        ui = self.cfg.ui
        if ui.score_rate_hz > 0 and frame.index % max(1, round(ui.rate_hz / ui.score_rate_hz)) == 0:
            self._score_live(frame, add=True)
        self._pending = frame
        return frame.wm

    def _session_behave(self, _frame: Frame, _wm: Any) -> BaseReference | None:
        frame = self._pending
        if frame is None:  # no new scan this tick: keep driving as before
            return None
        cmd = self._behave(frame)
        frame.command = cmd
        self.last_command = cmd
        return cmd

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
        factory = behaviour_factories().get(spec.partition(":")[0].strip())
        if factory is None:
            return None
        latest = self.timeline.latest if hasattr(self, "timeline") else None
        pose = self.robot_pose_in_map(latest) if latest is not None else self.bundle.truth_pose()
        return factory(spec, self.cfg, self.global_map, pose)

    def _behave(self, frame: FrameRecord) -> BaseReference:
        now = frame.time
        name = self.behaviour_name
        if name == "teleop":
            frame.behaviour_state = "teleop"
            if self.teleop_command is not None and time.monotonic() < self.teleop_until:
                return BaseReference(self.teleop_command.vx, self.teleop_command.vy, self.teleop_command.va, now)
            return BaseReference(0.0, 0.0, 0.0, now)
        b = self.behaviour
        if b is None:
            frame.behaviour_state = "stopped"
            return BaseReference(0.0, 0.0, 0.0, now)
        cmd = b.step(frame.wm, frame.laser, frame.odometry, now, ok=self.source.ok())
        if getattr(cmd, "open_door", False):
            self.source.open_door()
        self._note_behaviour(frame, b)
        return BaseReference(float(cmd.vx), float(cmd.vy), float(cmd.va), now)

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
                self._score_live(frame, add=False)

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
            out["scores"] = self._scores(frame)
            out["localisation"] = self._localisation_figures(frame)
            lm = getattr(wm, "laser_motion", None)
            out["laser_motion"] = tuple(map(float, lm)) if lm is not None else None
            out["laser_motion_matches"] = int(getattr(wm, "laser_motion_matches", 0) or 0)
            entrance = getattr(wm, "entrance", None)
            out["entrance"] = tuple(map(float, entrance)) if entrance is not None else None
            out["hallway"] = bool(getattr(wm, "hallway", False))
            out["room"] = dict(getattr(wm, "room", None) or {})
            return out

    def _scores(self, frame: FrameRecord | None) -> dict[str, dict[str, float]]:
        """The latest scored frame's and the run's scores (the live frames only: the truth is
        *now*; a frame on the timeline shows nothing)."""
        if self.cursor is not None or self.run_score is None or not self.run_score.count:
            return {}
        out = {"run": _score_figures(self.run_score.summary())}
        latest = frame.score if frame is not None and frame.score is not None else self.run_score.last
        out["frame"] = _score_figures(_summary([latest]))
        return out

    @staticmethod
    def _localisation_figures(frame: FrameRecord | None) -> dict[str, Any]:
        wm = frame.wm if frame is not None else None
        if wm is None or not hasattr(wm, "localisation_quality"):
            return {}
        out: dict[str, Any] = {"quality": float(wm.localisation_quality), "lost": bool(wm.lost)}
        g, t = wm.global_pose, frame.truth_pose if frame is not None else None
        if g is not None and t is not None:
            out["error_m"] = math.hypot(g[0] - t[0], g[1] - t[1])
            out["error_rad"] = abs(float(wrap_angle(g[2] - t[2])))
        return out

    def _score_live(self, frame: FrameRecord, *, add: bool) -> None:
        """Score the latest frame's world model against the simulator's truth (if any)."""
        truth = self.bundle.truth
        if scoring is None or truth is None or frame.wm is None:
            return
        if self.true_zero is None:
            self.true_zero = frame.truth_pose
        try:
            frame.score = scoring.score_frame(frame.wm, truth, true_zero=self.true_zero)
        except Exception as e:  # a scoring bug must not take the page down
            log.warning("scoring failed: %s", e)
            frame.score = None
            return
        if add:
            self.run_score.add(frame.score)

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


class RunningScore:
    """The run's scores as a running sum (the page reads them every frame; summing a list of
    every scored frame again each time grew with the run): `add`, `summary()` like
    `scoring.RunScore`'s, `count`, `last`."""

    def __init__(self) -> None:
        self.total = scoring.FrameScore()
        self.count = 0
        self.last: Any = None
        self._summary: dict[str, Any] | None = None

    def add(self, frame: Any) -> None:
        for name in _SCORE_FIELDS:
            setattr(self.total, name, getattr(self.total, name) + getattr(frame, name))
        self.count += 1
        self.last = frame
        self._summary = None

    def summary(self) -> dict[str, Any]:
        if self._summary is None:
            out = _summary([self.total])  # the ratios of the sums are the run's ratios ...
            for key in ("pose_error_m", "pose_error_rad"):  # ... the mean errors divide by n
                out[key] = out[key] / max(self.count, 1)
            out["frames"] = self.count
            self._summary = out
        return self._summary


_SCORE_FIELDS = tuple(f.name for f in fields(scoring.FrameScore)) if scoring is not None else ()


def _summary(frames: list[Any]) -> dict[str, Any]:
    run = scoring.RunScore()
    for f in frames:
        run.add(f)
    return run.summary()


def _score_figures(summary: dict[str, Any]) -> dict[str, float]:
    return {label: float(summary[key]) for key, label in SCORE_FIGURES.items() if key in summary}


@dataclass
class _SessionPerceptor:
    """Adapter: the session calls `step(laser, odometry)`; the studio runs the pure perceptor."""

    step: Callable[[LaserData, OdometryData | None], Any]


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
