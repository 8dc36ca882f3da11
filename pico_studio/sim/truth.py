"""Ground truth beside the robot interface: where the robot really is and what it really sees.

`sim.truth` is never reachable through the `RobotIO` methods. Everything is in the map frame.

Visibility, two definitions (each method says which it uses):
- *hit*: a wall is visible where beams of the latest scan actually hit it (noise-free);
- *in view*: a point (corner, door jamb) is visible when it lies within the laser's range and
  field of view and the ray from the laser to it is not blocked more than `visible_tolerance`
  before it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from pico_studio.sim.base import CollisionEvent

if TYPE_CHECKING:
    from pico_studio.sim.simulator import Simulator

Pose = tuple[float, float, float]


class GroundTruth:
    def __init__(self, sim: Simulator):
        self._sim = sim

    @property
    def pose(self) -> Pose:
        """The robot's true pose (x, y, a) in the map frame."""
        return self._sim.base.pose

    @property
    def collisions(self) -> int:
        """How many times the robot ran into something (one per contact)."""
        return len(self._sim.base.collisions)

    @property
    def collision_events(self) -> list[CollisionEvent]:
        return list(self._sim.base.collisions)

    @property
    def in_contact(self) -> bool:
        return self._sim.base.in_contact

    @property
    def distance(self) -> float:
        """True path length travelled, metres."""
        return self._sim.base.distance

    @property
    def odometry_pose(self) -> Pose:
        """The odometry's current pose in its own frame (whatever the reading form)."""
        return self._sim.odometry.pose

    def segments(self) -> np.ndarray:
        """Every solid segment of the world as it is now (walls, objects, doors, moving objects)."""
        return self._sim.world.segments().copy()

    def scan_hits(self) -> tuple[np.ndarray, np.ndarray]:
        """Noise-free ranges of the latest scan and the world segment index each beam hit (-1: none)."""
        return self._sim.laser.true_ranges.copy(), self._sim.laser.true_hits.copy()

    def as_dict(self) -> dict[str, object]:
        """The small per-frame truth the session records (JSON-friendly)."""
        return {"pose": self.pose, "collisions": self.collisions, "in_contact": self.in_contact}
