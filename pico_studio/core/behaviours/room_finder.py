"""Room finder (seed 000): go round the main room with the wall on the right, look into every
side room and count what is inside, stop back at the starting corner.

States:
    scan          a 180 deg scan: turn to face the nearest wall (fast on odometry, the last 5
                  deg slowly)
    to wall       drive at it (fast, slow for the last `slow_distance`), stop `stop_distance` off
    turn left     turn 90 deg left (the wall ahead becomes the wall on the right)
    to corner     follow the wall to the corner ahead: this corner is the start
    follow        follow the wall on the right: two right beams keep the robot parallel and
                  `wall_distance` off; a jump of the right-hand range by `room_jump_min` ..
                  `room_jump_max` marks a side room
    centre        drive half a room width on, to stand in front of the room's middle
    face room     turn 90 deg right
    count         count the objects: edges where neighbouring ranges jump by `edge_jump`,
                  edges within `edge_suppress` beams of one found ignored, ceil(edges / 2)
    turn back     turn 90 deg left and go on following
    done          `corners` corners turned past the start one: every wall followed once
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config.behaviour_params import BehaviourParams
from pico_studio.core.behaviours.base import (
    BehaviourBase,
    Command,
    clamp,
    turn_rate,
    wall_angle,
)
from pico_studio.core.behaviours.bubble import Bubble
from pico_studio.core.geometry import wrap_angle


def count_edges(ranges: np.ndarray, jump: float, suppress: int) -> int:
    """Object edges in a fan of ranges: neighbour jumps above `jump`, the next `suppress`
    beams after an edge ignored (one edge often shows as several jumps)."""
    r = np.where(np.isfinite(ranges), ranges, 1e3)
    jumps = np.flatnonzero(np.abs(np.diff(r)) > jump)
    edges, last = 0, -(10**9)
    for i in jumps:
        if i - last > suppress:
            edges += 1
            last = int(i)
    return edges


def count_objects(ranges: np.ndarray, jump: float, suppress: int) -> tuple[int, int]:
    """(objects, edges): an object has two edges; one hidden against a wall still counts."""
    edges = count_edges(ranges, jump, suppress)
    return math.ceil(edges / 2), edges


def nearest_wall_beam(angles: np.ndarray, ranges: np.ndarray, fov: float, half_window: int = 10,
                      straightness: float = 0.03, square: float = 0.17) -> int | None:
    """The beam (index) of the nearest *wall foot* within +-fov: the beam hits a straight
    piece (its +-half_window neighbours within `straightness` of their chord) square on
    (|cos| between beam and chord below `square`). None when no beam qualifies; a
    room's jamb corner is near but never a straight piece hit square on."""
    n = len(ranges)
    pts = np.column_stack([ranges * np.cos(angles), ranges * np.sin(angles)])
    for i in np.argsort(ranges):
        if not np.isfinite(ranges[i]):
            break  # sorted: only no-returns are left
        if abs(angles[i]) > fov:
            continue
        lo, hi = i - half_window, i + half_window
        if lo < 0 or hi >= n or not np.all(np.isfinite(ranges[lo:hi + 1])):
            continue
        chord = pts[hi] - pts[lo]
        length = float(np.hypot(*chord))
        if length < 1e-6:
            continue
        t = chord / length
        off = np.abs((pts[lo:hi + 1, 0] - pts[lo, 0]) * t[1] - (pts[lo:hi + 1, 1] - pts[lo, 1]) * t[0])
        beam = np.array([math.cos(angles[i]), math.sin(angles[i])])
        if off.max() <= straightness and abs(float(beam @ t)) <= square:
            return int(i)
    return None


class RoomFinder(BehaviourBase):
    name = "room-finder"

    def __init__(self, params: BehaviourParams):
        super().__init__(params.common)
        self.p = params.room_finder
        self.bubble = Bubble(params.bubble, params.common)
        self._state = "scan"
        self._turn_goal: float | None = None
        self._after_turn = ""
        self._corners = -1  # the corner reached at the end of "to corner" is number 0
        self._wall_heading: float | None = None  # odometry heading along the current wall
        self._baseline = self.p.wall_distance
        self._in_gap = False
        self._mark: tuple[float, float] | None = None
        self._counts: list[tuple[int, int]] = []
        self._rescan = False

    # ---- helpers ----
    def _front(self) -> float:
        assert self.scan is not None
        return self.scan.range_at(0.0, 6)

    def _turn(self) -> Command | None:
        """Turn towards `_turn_goal`; None once there."""
        assert self.pose is not None and self._turn_goal is not None
        err = float(wrap_angle(self._turn_goal - self.pose[2]))
        if abs(err) <= self.p.turn_tolerance:
            return None
        return Command(va=turn_rate(err, self.p.fast_turn, self.p.slow_turn, self.p.slow_turn_angle))

    def _drive_speed(self, front: float) -> float:
        left = front - self.p.stop_distance
        return self.p.fast_speed if left > self.p.slow_distance else self.p.slow_speed

    def _right_wall(self) -> tuple[float, float] | None:
        """(angle of the right wall relative to the heading, its distance), from the two right
        beams; None when they do not both see one straight wall near by."""
        assert self.scan is not None
        d = self.p.side_beam_angle
        a = wall_angle(self.scan, -math.pi / 2, d)
        if a is None:
            return None
        r1, r2 = self.scan.range_at(-math.pi / 2 - d), self.scan.range_at(-math.pi / 2 + d)
        limit = (self.p.wall_distance + self.p.room_jump_min / 2) / math.cos(d)
        if max(r1, r2) > limit:
            return None
        # distance of the line through the two hit points from the robot's centre
        p1 = np.array([r1 * math.cos(-math.pi / 2 - d), r1 * math.sin(-math.pi / 2 - d)])
        p2 = np.array([r2 * math.cos(-math.pi / 2 + d), r2 * math.sin(-math.pi / 2 + d)])
        t = (p2 - p1) / np.hypot(*(p2 - p1))
        dist = abs(p1[0] * t[1] - p1[1] * t[0])
        a = float(wrap_angle(a))
        if abs(a) > self.p.max_wall_angle:
            return None  # the two beams are not on one wall (an opening, a corner)
        return a, float(dist)

    def _follow_command(self, front: float, use_wall: bool = True) -> Command:
        """Drive along the right wall (parallel, `wall_distance` off); hold the odometry
        heading where the wall is missing (a side room's opening)."""
        assert self.pose is not None
        vx = self._drive_speed(front)
        wall = self._right_wall() if use_wall else None
        if wall is not None:
            angle, dist = wall
            self._wall_heading = float(wrap_angle(self.pose[2] + angle))
            va = clamp(self.p.align_gain * angle, self.p.fast_turn)
            vy = clamp(-self.p.distance_gain * (dist - self.p.wall_distance), 0.15)
            return Command(vx=vx, vy=vy, va=va)
        if self._wall_heading is None:
            self._wall_heading = self.pose[2]
        err = float(wrap_angle(self._wall_heading - self.pose[2]))
        return Command(vx=vx, va=clamp(self.p.align_gain * err, self.p.fast_turn))

    def _moved_since_mark(self) -> float:
        assert self.pose is not None and self._mark is not None
        return math.hypot(self.pose[0] - self._mark[0], self.pose[1] - self._mark[1])

    # ---- the state machine ----
    def _step(self, now: float) -> Command:
        assert self.scan is not None and self.pose is not None
        override = self.bubble.check(self.scan, self.pose)
        if override is not None:
            return override
        s = self._state
        if s == "scan":
            return self._scan()
        if s in ("turn left", "face room", "turn back", "turn"):
            cmd = self._turn()
            if cmd is not None:
                return cmd
            self._state = self._after_turn if self._after_turn != "follow after room" else "follow"
            if self._state == "count":
                self._counts.clear()
            return Command()
        if s == "to wall":
            front = self._front()
            if front <= self.p.stop_distance:
                # turn along the wall ahead, so it ends up on the right whatever angle we met
                # it at: its nearest point is square to it (unlike two beams, which a side
                # room's opening next to the spot can fool)
                fan = np.abs(self.scan.angles) <= self.p.scan_fov / 1.5
                i = int(np.argmin(np.where(fan, self.scan.ranges, np.inf)))
                turn = float(wrap_angle(self.scan.angles[i] + math.pi / 2))
                self._turn_goal = float(wrap_angle(self.pose[2] + turn))
                self._after_turn, self._state = "to corner", "turn left"
                return Command()
            return Command(vx=self._drive_speed(front))
        if s in ("to corner", "follow"):
            return self._follow(s)
        if s == "centre":
            if self._moved_since_mark() >= self.p.room_width / 2:
                self._turn_goal = float(wrap_angle(self.pose[2] - math.pi / 2))
                self._after_turn, self._state = "count", "face room"
                return Command()
            return self._follow_command(math.inf, use_wall=False)
        if s == "count":
            return self._count()
        return Command()

    def _scan(self) -> Command:
        assert self.scan is not None and self.pose is not None
        if self._turn_goal is None:
            fan = np.abs(self.scan.angles) <= self.p.scan_fov
            r = np.where(fan, self.scan.ranges, np.inf)
            foot = nearest_wall_beam(self.scan.angles, self.scan.ranges, self.p.scan_fov)
            i = int(np.argmin(r)) if foot is None else foot
            self._turn_goal = float(wrap_angle(self.pose[2] + self.scan.angles[i]))
            # nearest at the fan's edge: the nearest wall may lie beyond it; scan again there
            self._rescan = abs(self.scan.angles[i]) > self.p.scan_fov - self.p.rescan_margin
            self._target = None
        cmd = self._turn()
        if cmd is not None:
            return cmd
        if self._rescan:
            self._turn_goal = None
            return Command()
        self._state = "to wall"
        return Command()

    def _follow(self, s: str) -> Command:
        assert self.scan is not None and self.pose is not None
        front = self._front()
        if front <= self.p.stop_distance:
            self._corners += 1
            if s == "follow" and self._corners >= self.p.corners:
                self.finish()
                return Command()
            self._turn_goal = float(wrap_angle(self.pose[2] + math.pi / 2))
            self._after_turn, self._state = "follow", "turn left"
            self._wall_heading = None
            self._in_gap = False
            return Command()
        side = self.scan.range_at(-math.pi / 2, 2)
        if s == "follow":
            jump = side - self._baseline
            if not self._in_gap and self.p.room_jump_min <= jump <= self.p.room_jump_max:
                self._in_gap = True
                self._mark = (self.pose[0], self.pose[1])
                self._state = "centre"
                return self._follow_command(front, use_wall=False)
            # leave the room behind: past its far edge (measured from its centre) and the
            # right-hand range back to the wall's
            past = self._mark is None or self._moved_since_mark() > self.p.room_width
            if self._in_gap and past and jump < self.p.room_jump_min / 2:
                self._in_gap = False
        if not self._in_gap and math.isfinite(side) and side < self.p.wall_distance + self.p.room_jump_min / 2:
            self._baseline = 0.8 * self._baseline + 0.2 * side
        return self._follow_command(front)

    def _count(self) -> Command:
        assert self.scan is not None and self.pose is not None
        fan = np.abs(self.scan.angles) <= self.p.content_fov
        self._counts.append(count_objects(self.scan.ranges[fan], self.p.edge_jump, self.p.edge_suppress))
        if len(self._counts) < 5:
            return Command()
        objects = int(np.median([c[0] for c in self._counts]))
        edges = int(np.median([c[1] for c in self._counts]))
        self.outcome.rooms.append({
            "objects": objects, "edges": edges,
            "odom_xy": [round(self.pose[0], 3), round(self.pose[1], 3)],
        })
        self._target = (self.pose[0] + math.cos(self.pose[2]) * (self.p.wall_distance + self.p.room_width / 2),
                        self.pose[1] + math.sin(self.pose[2]) * (self.p.wall_distance + self.p.room_width / 2))
        self._turn_goal = float(wrap_angle(self.pose[2] + math.pi / 2))
        self._after_turn, self._state = "follow after room", "turn back"
        return Command()
