"""Replaying kept frames: a `RobotIO` over a list of `Frame`s (e.g. a session's history).

    live = [sf.frame for sf in Session(sim, perceptor=p1, behaviour=b).frames(until=30)]
    again = Session(FramesReplay(live), perceptor=p2, observers=[PoseErrorScorer()])
    again.run(math.inf)     # the same sensor stream, judged with another config

One kept frame per tick, whatever `dt` is asked for: `advance` moves to the next frame and
`now()` is that frame's time, so a session over the replay sees exactly the readings (new
laser or None, new odometry or None) and the truth (`truth_dict()`, `truth_pose()`) the live
session saw, tick by tick. Commands sent are kept in `sent`, not acted on.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from pico_studio.core.io import Frame, LaserData, OdometryData


class FramesReplay:
    def __init__(self, frames: Sequence[Frame]):
        self.frames = list(frames)
        self.index = -1  # the frame delivered by the last `advance`; -1 before the first
        self._read_laser = self._read_odometry = True
        self.sent: list[tuple[float, float, float]] = []
        self.doors_opened = 0

    def advance(self, dt: float = 0.0) -> None:
        if self.index + 1 < len(self.frames):
            self.index += 1
            self._read_laser = self._read_odometry = False

    def _frame(self) -> Frame | None:
        return self.frames[self.index] if 0 <= self.index < len(self.frames) else None

    def read_laser(self) -> LaserData | None:
        f = self._frame()
        if f is None or self._read_laser:
            return None
        self._read_laser = True
        return f.laser

    def read_odometry(self) -> OdometryData | None:
        f = self._frame()
        if f is None or self._read_odometry:
            return None
        self._read_odometry = True
        return f.odometry

    def send_base_reference(self, vx: float, vy: float, va: float) -> None:
        self.sent.append((vx, vy, va))

    def open_door(self) -> None:
        self.doors_opened += 1

    def ok(self) -> bool:
        """More frames to come."""
        return self.index + 1 < len(self.frames)

    def now(self) -> float:
        f = self._frame()
        if f is not None:
            return f.time
        return self.frames[0].time if self.frames else 0.0

    def truth_dict(self) -> dict[str, object]:
        f = self._frame()
        return dict(f.truth) if f is not None else {}

    def truth_pose(self) -> Any:
        return self.truth_dict().get("pose")
