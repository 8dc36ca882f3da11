"""The timeline: the last N frames, each with what is needed to re-process it.

A frame keeps the raw readings (laser, odometry), the ground truth when known, the
perceptor state *before* the frame (so the pure perceptor can re-run it with new
parameters) and the world model last computed for it.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from pico_studio.core.io import BaseReference, LaserData, OdometryData
from pico_studio.core.world_model import WorldModel

Pose = tuple[float, float, float]


@dataclass
class FrameRecord:
    index: int  # running frame number since the last reset
    time: float  # the source's clock, s
    laser: LaserData | None
    odometry: OdometryData | None
    truth_pose: Pose | None  # map frame, when the source knows it
    state_before: Any  # perceptor state going into this frame (None without a perceptor)
    wm: WorldModel | None = None  # the WorldModel last computed for this frame
    command: BaseReference | None = None  # what was sent to the base after this frame
    behaviour_state: str = ""
    behaviour_target: tuple[float, float] | None = None  # when the behaviour has one
    behaviour_plan: Any = None  # (K, 2) waypoints, when the behaviour plans
    behaviour_frame: str = "zero"  # the frame of target/plan: "zero", "odom" or "global"
    behaviour_pose: Any = None  # the behaviour's own pose in its "odom" frame
    errors: list[str] = field(default_factory=list)
    sim_world: Any = None  # (K, 4) the simulator's doors and moving objects now, map frame
    map_xy: tuple[float, float] | None = None  # where the robot was drawn live (for the trail)
    score: Any = None  # evaluation.FrameScore against the truth, for the live frame when simulated


class Timeline:
    """A bounded ring of frames; positions 0 .. len-1, oldest first."""

    def __init__(self, max_frames: int):
        self.max_frames = max(1, int(max_frames))
        self._frames: deque[FrameRecord] = deque(maxlen=self.max_frames)

    def append(self, frame: FrameRecord) -> None:
        self._frames.append(frame)

    def clear(self) -> None:
        self._frames.clear()

    def __len__(self) -> int:
        return len(self._frames)

    def __getitem__(self, position: int) -> FrameRecord:
        return self._frames[position]

    def __iter__(self) -> Iterator[FrameRecord]:
        return iter(self._frames)

    @property
    def latest(self) -> FrameRecord | None:
        return self._frames[-1] if self._frames else None

    def clamp(self, position: int) -> int:
        return min(max(int(position), 0), max(len(self._frames) - 1, 0))

    def up_to(self, position: int, count: int) -> list[FrameRecord]:
        """The `count` frames ending at `position` (inclusive), oldest first."""
        position = self.clamp(position)
        start = max(0, position - count + 1)
        return [self._frames[i] for i in range(start, position + 1)]
