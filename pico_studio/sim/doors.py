"""Sliding doors: closed at the start, opened on request from in front, sliding at a fixed speed.

A door is the map's door polygon (usually a thin rectangle in the wall). Its own frame has
the origin at the centre of the polygon's bounding rectangle and x along its long side, as in
the official simulator: the robot is *in front* when |y| <= open_distance and |x| <= size / 2
in that frame (either side of the door). Once opened it slides along x by its own size (the
way `slide_direction` says), then stays there.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.core.geometry import relative
from pico_studio.json_map.openings import door_frame


def slide_direction(axis: np.ndarray, grey: int | None) -> np.ndarray:
    """Where an opened door slides, as the emc simulator has it for an axis-aligned door:
    along its long axis towards decreasing x (or y, for a door along y), and the other way
    when its heightmap grey value is below 128. A JSON map's door (no grey) slides like a
    grey-128 one, so the JSON and PNG versions of a map agree."""
    a = np.asarray(axis, dtype=float)
    dominant = 0 if abs(a[0]) >= abs(a[1]) else 1
    if a[dominant] > 0:
        a = -a
    return -a if grey is not None and grey < 128 else a


class SlidingDoor:
    def __init__(self, vertices: np.ndarray, grey: int | None = None):
        """`grey`: the door's grey value in a heightmap, which sets its sliding direction."""
        self.vertices = np.asarray(vertices, dtype=float)
        self.center, self.axis, self.size, self.thickness = door_frame(self.vertices)
        self.normal = np.array([-self.axis[1], self.axis[0]])
        self.slide = slide_direction(self.axis, grey)
        self.pose = (float(self.center[0]), float(self.center[1]), math.atan2(self.axis[1], self.axis[0]))
        self.offset = 0.0  # how far it has slid along its axis
        self.opening = False

    @property
    def closed(self) -> bool:
        return not self.opening

    @property
    def moving(self) -> bool:
        return self.opening and self.offset < self.size

    def in_front(self, robot_xy: tuple[float, float], max_distance: float) -> bool:
        rel = relative(self.pose, (robot_xy[0], robot_xy[1], 0.0))
        return abs(rel[1]) <= max_distance and abs(rel[0]) <= self.size / 2

    def request_open(self, robot_xy: tuple[float, float], max_distance: float) -> bool:
        """Start opening if closed and the robot is in front; True when it started."""
        if self.opening or not self.in_front(robot_xy, max_distance):
            return False
        self.opening = True
        return True

    def update(self, dt: float, speed: float) -> None:
        if self.moving:
            self.offset = min(self.size, self.offset + speed * dt)

    def segments(self) -> np.ndarray:
        """The door's current outline (K, 4), map frame."""
        v = self.vertices + self.offset * self.slide
        return np.hstack([v, np.roll(v, -1, axis=0)])
