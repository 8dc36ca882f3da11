"""The one loop: a source, an optional perceptor, a behaviour, and observers of every tick.

    session = Session(sim, perceptor=Perceptor(cfg.perception), behaviour=Wander(cfg.ui.wander),
                      observers=[TruthScorer(lambda: sim.truth)])
    for sf in session.frames(until=30.0):   # advance, read, perceive, behave, send, observe
        ...                                 # sf: SessionFrame(index, frame, world_model, command)
    session.run(30.0)                       # the same, drained; returns the ticks
    session.summaries()                     # {observer name: observer.summary()}

This is the only place in pico_studio that advances a source and steps a perceptor and a
behaviour together: `run` (sim, bags, CARMEN, live), `run --behaviour`, `eval`, replays and
the page's `Studio` all come through `tick`. What plugs in (duck-typed, so each part stays
independent):

- `source`: a `RobotIO` with `advance(dt)`. What it knows of the truth is stored with every
  frame: the simulator's `truth.as_dict()`, else a replay's `truth_dict()` (a kept frame's
  whole truth), else `truth_pose()` as {"pose": ...} (CARMEN's corrected pose, a bag's).
- `perceptor`: anything with `step(laser, odometry) -> world model` (a `LocalisingPerceptor`
  localises as well); called when a new scan arrived, with the newest odometry (or None).
- `behaviour`: the behaviour protocol of `core/behaviours`: `step(world_model, laser,
  odometry, now, *, ok) -> Command | None` (None: send nothing, the source keeps the previous
  reference). `laser` / `odometry` are the readings new this tick (None when none arrived).
- `observers`: anything with `on_frame(sf: SessionFrame) -> None` and `summary() -> dict`
  (JSON-able); called in order after every tick. The bag recorder, the progress display, the
  scorers and judges of `pico_studio.evaluation` and the page's timeline are observers.
- `recorder`: shorthand for `observers=[RecorderObserver(recorder)]` (anything with
  `record(frame, command)`).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import Any, Protocol

from pico_studio.core.io import BaseReference, Command, Frame, LaserData, OdometryData
from pico_studio.progress import Progress, ProgressObserver


class Perceiving(Protocol):
    def step(self, laser: LaserData, odometry: OdometryData | None) -> Any: ...


class Stepping(Protocol):
    def step(self, world_model: Any, laser: LaserData | None, odometry: OdometryData | None,
             now: float, *, ok: bool = True) -> Command | BaseReference | None: ...


class Recording(Protocol):
    def record(self, frame: Frame, command: Command | None) -> None: ...


@dataclass
class SessionFrame:
    """One tick: what the source delivered, what the perceptor made of it, what was sent."""

    index: int
    frame: Frame
    world_model: Any  # the newest world model (the previous one when no scan arrived)
    command: Command | None


class Observer(Protocol):
    def on_frame(self, sf: SessionFrame) -> None: ...

    def summary(self) -> dict[str, Any]: ...


def as_command(command: Any) -> Command | None:
    """Normalise what a behaviour returned."""
    if command is None or isinstance(command, Command):
        return command
    if isinstance(command, BaseReference):
        return Command(command.vx, command.vy, command.va)
    if isinstance(command, (tuple, list)) and len(command) == 3:
        return Command(float(command[0]), float(command[1]), float(command[2]))
    raise TypeError(f"a behaviour must return a Command, BaseReference, (vx, vy, va) or None, got {command!r}")


class RecorderObserver:
    """A recorder (`record(frame, command)`, e.g. `BagRecorder`) as an observer."""

    name = "recorded"

    def __init__(self, recorder: Recording):
        self.recorder = recorder

    def on_frame(self, sf: SessionFrame) -> None:
        self.recorder.record(sf.frame, sf.command)

    def summary(self) -> dict[str, Any]:
        counts = getattr(self.recorder, "counts", {})
        path = getattr(self.recorder, "path", None)
        return {"file": str(path) if path is not None else None, "messages": dict(sorted(counts.items()))}


class FrameKeeper:
    """Keeps every frame of a session (what the page's timeline does), to replay or score
    again later (`sources.frames.FramesReplay([sf.frame for sf in keeper.frames])`)."""

    name = "keep"

    def __init__(self) -> None:
        self.frames: list[SessionFrame] = []

    def on_frame(self, sf: SessionFrame) -> None:
        self.frames.append(sf)

    def summary(self) -> dict[str, Any]:
        return {"frames": len(self.frames)}


class Session:
    def __init__(
        self,
        source: Any,
        *,
        perceptor: Perceiving | None = None,
        behaviour: Stepping | None = None,
        recorder: Recording | None = None,
        observers: list[Any] | None = None,
        history: int = 0,
    ):
        self.source = source
        self.perceptor = perceptor
        self.behaviour = behaviour
        self.observers: list[Any] = list(observers or [])
        if recorder is not None:
            self.observers.append(RecorderObserver(recorder))
        # the newest frames, for callers that look back (0: keep none; the page's timeline is
        # an observer with its own memory)
        self.history: deque[SessionFrame] = deque(maxlen=max(history, 1))
        self.ticks = 0
        self.world_model: Any = None
        self.last_laser: LaserData | None = None
        self.last_odometry: OdometryData | None = None

    @property
    def recorder(self) -> Recording | None:
        """The recorder among the observers (None: not recording)."""
        for o in self.observers:
            if isinstance(o, RecorderObserver):
                return o.recorder
        return None

    @recorder.setter
    def recorder(self, recorder: Recording | None) -> None:
        """Start (or, with None, stop) recording from the next tick on."""
        self.observers = [o for o in self.observers if not isinstance(o, RecorderObserver)]
        if recorder is not None:
            self.observers.append(RecorderObserver(recorder))

    def tick(self, dt: float) -> SessionFrame:
        """Advance the source by dt, then read, perceive, behave, send and observe once.

        The behaviour's `ok` is the source's `ok()` as the tick began (emc's
        `while (io.ok()) { ... }`), so a replay's last frame is behaved on like the others."""
        ok = self.source.ok()
        self.source.advance(dt)
        laser = self.source.read_laser()
        odometry = self.source.read_odometry()
        if laser is not None:
            self.last_laser = laser
        if odometry is not None:
            self.last_odometry = odometry
        now = self.source.now()
        frame = Frame(laser=laser, odometry=odometry, time=now, truth=frame_truth(self.source))
        if self.perceptor is not None and laser is not None:
            self.world_model = self.perceptor.step(laser, odometry)
        command = None
        if self.behaviour is not None:
            command = as_command(self.behaviour.step(self.world_model, laser, odometry, now, ok=ok))
        if command is not None:
            self.source.send_base_reference(command.vx, command.vy, command.va)
            if command.open_door:
                self.source.open_door()
        out = SessionFrame(self.ticks, frame, self.world_model, command)
        self.history.append(out)
        self.ticks += 1
        for observer in self.observers:
            observer.on_frame(out)
        return out

    def frames(self, until: float | None = None, dt: float = 0.05, *,
               steps: Iterable[float] | None = None) -> Iterator[SessionFrame]:
        """Tick while the source is ok, yielding every frame; with `until`, stop once the
        source's clock reaches it (the last tick is shortened to land on it).

        `steps`: the dt of each tick instead of a fixed `dt` (a replay's `frame_steps`, which
        meet every recorded frame once); a step that would pass `until` is not taken."""
        it = iter(steps) if steps is not None else None
        while self.source.ok():
            now = self.source.now()
            if it is not None:
                step = next(it, None)
                if step is None or (until is not None and now + step > until + 1e-9):
                    return
            else:
                step = dt
                if until is not None:
                    if until - now <= 1e-9:
                        return
                    step = min(dt, until - now)
            yield self.tick(step)

    def run(self, seconds: float, dt: float = 0.05, progress: Progress | None = None) -> int:
        """Tick until `seconds` of source time have passed or the source stops; returns ticks."""
        start = self.source.now()
        watch = ProgressObserver(progress, start) if progress is not None else None
        n = 0
        for sf in self.frames(until=start + seconds, dt=dt):
            n += 1
            if watch is not None:
                watch.on_frame(sf)
        return n

    def summaries(self) -> dict[str, dict[str, Any]]:
        """Every observer's summary, by its `name` (else its class name)."""
        return {getattr(o, "name", type(o).__name__): o.summary() for o in self.observers}


def frame_truth(source: Any) -> dict[str, object]:
    """What `source` knows of the truth now (see the module docstring)."""
    truth = getattr(source, "truth", None)
    if truth is not None and hasattr(truth, "as_dict"):
        return truth.as_dict()
    truth_dict = getattr(source, "truth_dict", None)
    if callable(truth_dict):
        return dict(truth_dict())
    truth_pose = getattr(source, "truth_pose", None)
    pose = truth_pose() if callable(truth_pose) else None
    return {"pose": pose} if pose is not None else {}
