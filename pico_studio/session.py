"""The headless loop: a source, an optional perceptor, a behaviour and an optional recorder.

    session = Session(sim, perceptor=Perceptor(cfg.perception), behaviour=my_behaviour)
    for _ in range(200):
        session.tick(0.05)      # advance, read, perceive, behave, send, record
    session.history[-1]         # the newest SessionFrame (for the UI's timeline)

What plugs in (duck-typed, so each engineer's part stays independent):
- `source`: a `RobotIO` with `advance(dt)`; when it has a `truth` (the simulator), its
  `truth.as_dict()` is stored with every frame; a replay that knows the true pose (CARMEN's
  corrected pose, a recorded simulation) gives it by `truth_pose()`, stored as {"pose": ...}.
- `perceptor`: anything with `step(laser, odometry) -> world model`; called when a new scan
  arrived (the newest odometry reading, possibly None, goes with it).
- `behaviour`: a callable `(frame, world_model) -> command`, where command is a
  `BaseReference`, a `Command` (which can also ask to open a door), a (vx, vy, va) tuple, or
  None (send nothing; the source keeps the previous reference).
- `recorder`: anything with `record(frame, command)`.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

from pico_studio.core.io import BaseReference, Command, Frame, LaserData, OdometryData
from pico_studio.progress import Progress


class Perceiving(Protocol):
    def step(self, laser: LaserData, odometry: OdometryData | None) -> Any: ...


class Recording(Protocol):
    def record(self, frame: Frame, command: Command | None) -> None: ...


Behaviour = Callable[[Frame, Any], "Command | BaseReference | tuple[float, float, float] | None"]


@dataclass
class SessionFrame:
    """One tick as the UI's timeline keeps it."""

    index: int
    frame: Frame
    world_model: Any
    command: Command | None


def as_command(command: Any) -> Command | None:
    """Normalise what a behaviour returned."""
    if command is None or isinstance(command, Command):
        return command
    if isinstance(command, BaseReference):
        return Command(command.vx, command.vy, command.va)
    if isinstance(command, (tuple, list)) and len(command) == 3:
        return Command(float(command[0]), float(command[1]), float(command[2]))
    raise TypeError(f"a behaviour must return a Command, BaseReference, (vx, vy, va) or None, got {command!r}")


class Session:
    def __init__(
        self,
        source: Any,
        *,
        perceptor: Perceiving | None = None,
        behaviour: Behaviour | None = None,
        recorder: Recording | None = None,
        history: int = 2000,
    ):
        self.source = source
        self.perceptor = perceptor
        self.behaviour = behaviour
        self.recorder = recorder
        self.history: deque[SessionFrame] = deque(maxlen=history)
        self.ticks = 0
        self.world_model: Any = None
        self.last_laser: LaserData | None = None
        self.last_odometry: OdometryData | None = None

    def tick(self, dt: float) -> SessionFrame:
        """Advance the source by dt, then read, perceive, behave, send and record once."""
        self.source.advance(dt)
        laser = self.source.read_laser()
        odometry = self.source.read_odometry()
        if laser is not None:
            self.last_laser = laser
        if odometry is not None:
            self.last_odometry = odometry
        truth = getattr(self.source, "truth", None)
        frame = Frame(
            laser=laser,
            odometry=odometry,
            time=self.source.now(),
            truth=truth.as_dict() if truth is not None else _replay_truth(self.source),
        )
        if self.perceptor is not None and laser is not None:
            self.world_model = self.perceptor.step(laser, odometry)
        command = as_command(self.behaviour(frame, self.world_model)) if self.behaviour is not None else None
        if command is not None:
            self.source.send_base_reference(command.vx, command.vy, command.va)
            if command.open_door:
                self.source.open_door()
        if self.recorder is not None:
            self.recorder.record(frame, command)
        out = SessionFrame(self.ticks, frame, self.world_model, command)
        self.history.append(out)
        self.ticks += 1
        return out

    def run(self, seconds: float, dt: float = 0.05, progress: Progress | None = None) -> int:
        """Tick until `seconds` of source time have passed or the source stops; returns ticks."""
        n = 0
        start = self.source.now()
        end = start + seconds
        while self.source.ok() and self.source.now() < end - 1e-9:
            self.tick(min(dt, end - self.source.now()))
            n += 1
            if progress is not None:
                progress.set(self.source.now() - start)
        return n


def _replay_truth(source: Any) -> dict[str, object]:
    truth_pose = getattr(source, "truth_pose", None)
    pose = truth_pose() if callable(truth_pose) else None
    return {"pose": pose} if pose is not None else {}
