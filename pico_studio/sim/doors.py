"""Sliding doors: closed at the start, opened on request from in front, sliding at a fixed speed.

A door is the map's door polygon (usually a thin rectangle in the wall). Its own frame has
the origin at the polygon's centre and x along its longest edge, as in the official
simulator: the robot is *in front* when |y| <= open_distance and |x| <= size / 2 in that frame
(either side of the door). Once opened it slides along x by its own size, then stays there.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.core.geometry import relative


class SlidingDoor:
    def __init__(self, vertices: np.ndarray):
        self.vertices = np.asarray(vertices, dtype=float)
        edges = np.roll(self.vertices, -1, axis=0) - self.vertices
        longest = edges[np.argmax(np.hypot(edges[:, 0], edges[:, 1]))]
        self.axis = longest / np.hypot(*longest)
        self.normal = np.array([-self.axis[1], self.axis[0]])
        self.center = self.vertices.mean(axis=0)
        along = (self.vertices - self.center) @ self.axis
        across = (self.vertices - self.center) @ self.normal
        self.size = float(along.max() - along.min())
        self.thickness = float(across.max() - across.min())
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
        v = self.vertices + self.offset * self.axis
        return np.hstack([v, np.roll(v, -1, axis=0)])

    def opening_segment(self) -> np.ndarray:
        """The gap the door closes: its centre line from one jamb to the other, (4,)."""
        half = self.axis * self.size / 2
        return np.concatenate([self.center - half, self.center + half])
