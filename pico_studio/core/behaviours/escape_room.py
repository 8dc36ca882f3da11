"""Escape room (seed 003): find the room's exit, drive to it, through the hallway and out.

States:
    scan        stand still, look for the entrance over a few scans (median of the detections)
    rotate      no entrance: turn `scan_step` (30 deg) on odometry and scan again
    free space  a full turn without entrance: face the longest free direction, drive
                `free_space_distance` and start scanning again (give up after `max_full_turns`)
    approach    drive to a point `approach_offset` in front of the entrance's mouth, re-checking
                the entrance every `recheck_every` steps; after `lost_after` misses: scan again
    align       face straight out through the mouth
    hallway     drive on, centred between the hallway walls, until no wall is near ahead or
                beside (nothing within `free_range` over the front half)
    back out    the hallway ended in a wall: remember that mouth as a dead end, reverse to
                the point in front of it and scan again (a room whose only exits are dead
                ends ends in "gave up" after `max_full_turns` scans)
    out         drive `out_distance` more, then stop: done
bubbleRobot overrides any state when something comes closer than the bubble.

The entrance is the robot-frame opening found by `find_openings` from the raw scan (a range
jump whose near corner has a far-side point 0.5-1.3 m away: the mouth's two corners), or the
world model's `entrance` (angle, distance) with `entrance_source: world_model` (its mouth
direction is then taken as the bearing).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

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
from pico_studio.core.geometry import invert, transform_points, wrap_angle


@dataclass(frozen=True)
class Opening:
    """A gap in the walls: its mouth centre, outward unit normal and width (one frame)."""

    centre: np.ndarray  # (2,)
    normal: np.ndarray  # (2,), pointing away from the robot
    width: float


def find_openings(points: np.ndarray, gap_min: float, gap_max: float,
                  search: int = 200) -> list[Opening]:
    """Openings between consecutive scan points (robot frame, beam order), nearest first.

    A jump of at least `gap_min` between neighbouring points marks a corner of a gap; the gap's
    other corner is the far-side point nearest to that corner. The gap counts when that
    distance lies within [gap_min, gap_max].
    """
    if len(points) < 3:
        return []
    steps = np.hypot(*(np.diff(points, axis=0).T))
    found: list[Opening] = []
    for i in np.flatnonzero(steps >= gap_min):
        a, b = points[i], points[i + 1]
        if np.hypot(*a) <= np.hypot(*b):
            corner, far = a, points[i + 1: i + 1 + search]
        else:
            corner, far = b, points[max(0, i + 1 - search): i + 1]
        d = np.hypot(*(far - corner).T)
        k = int(np.argmin(d))
        width = float(d[k])
        if not gap_min <= width <= gap_max:
            continue
        other = far[k]
        centre = (corner + other) / 2
        tangent = (other - corner) / width
        normal = np.array([-tangent[1], tangent[0]])
        if normal @ centre < 0:
            normal = -normal
        if any(np.hypot(*(o.centre - centre)) < gap_min for o in found):
            continue
        found.append(Opening(centre=centre, normal=normal, width=width))
    found.sort(key=lambda o: float(np.hypot(*o.centre)))
    return found


class EscapeRoom(BehaviourBase):
    name = "escape-room"

    def __init__(self, params: BehaviourParams):
        super().__init__(params.common)
        self.p = params.escape_room
        self.bubble = Bubble(params.bubble, params.common)
        self.source = self.p.entrance_source
        self._state = "scan"
        self._detections: list[Opening] = []  # odometry frame
        self._scan_steps = 0
        self._turned = 0.0
        self._turn_goal: float | None = None
        self._turn_from: float = 0.0
        self._full_turns = 0
        self._entrance: Opening | None = None  # odometry frame
        self._steps = 0
        self._misses = 0
        self._drive_from: tuple[float, float] | None = None
        self._free_heading: float | None = None
        self._dead_ends: list[np.ndarray] = []  # mouths (odometry frame) that led nowhere

    # ---- perception of the entrance, in the odometry frame ----
    def _detect(self, near: np.ndarray | None = None) -> Opening | None:
        """The entrance seen in this scan (odometry frame): the nearest opening, or with
        `near` the opening closest to that point."""
        assert self.scan is not None and self.pose is not None
        if self.source == "world_model":
            ent = getattr(self.world_model, "entrance", None)
            if ent is None:
                return None
            ang, dist = float(ent[0]), float(ent[1])
            local = Opening(np.array([dist * math.cos(ang), dist * math.sin(ang)]),
                            np.array([math.cos(ang), math.sin(ang)]), self.p.gap_min)
        else:
            pts = self.scan.points
            far = np.hypot(pts[:, 0], pts[:, 1]) <= self.p.max_range
            found = [o for o in find_openings(pts[far], self.p.gap_min, self.p.gap_max)
                     if not self._is_dead_end(o.centre)]
            if not found:
                return None
            local = found[0]
            if near is not None:
                near_local = transform_points(np.array([near], dtype=float), invert(self.pose))[0]
                local = min(found, key=lambda o: float(np.hypot(*(o.centre - near_local))))
        centre = transform_points(local.centre[None, :], self.pose)[0]
        normal = transform_points(local.normal[None, :], (0.0, 0.0, self.pose[2]))[0]
        return Opening(centre, normal, local.width)

    def _is_dead_end(self, local_centre: np.ndarray) -> bool:
        """Is this robot-frame opening one already tried and found closed?"""
        assert self.pose is not None
        if not self._dead_ends:
            return False
        c = transform_points(local_centre[None, :], self.pose)[0]
        return any(float(np.hypot(*(c - d))) < self.p.gap_max for d in self._dead_ends)

    def _approach_point(self) -> np.ndarray:
        assert self._entrance is not None
        return self._entrance.centre - self._entrance.normal * self.p.approach_offset

    def _set_entrance(self, e: Opening) -> None:
        self._entrance = e
        self._target = (float(e.centre[0]), float(e.centre[1]))
        ap = self._approach_point()
        out = e.centre + e.normal * 1.0
        self._plan = np.array([ap, e.centre, out])

    # ---- the state machine ----
    def _step(self, now: float) -> Command:
        assert self.scan is not None and self.pose is not None
        override = self.bubble.check(self.scan, self.pose)
        if override is not None:
            if self._state in ("approach", "align"):
                self._misses = 0  # re-evaluate from where the back-away leaves us
            return override
        handler = {
            "scan": self._scan,
            "rotate": self._rotate,
            "free space": self._free_space,
            "approach": self._approach,
            "align": self._align,
            "hallway": self._hallway,
            "back out": self._back_out,
            "out": self._out,
        }[self._state]
        return handler()

    def _scan(self) -> Command:
        e = self._detect()
        self._scan_steps += 1
        if e is not None:
            self._detections.append(e)
        if len(self._detections) >= self.p.scans_to_confirm:
            cs = np.array([d.centre for d in self._detections])
            angs = np.array([math.atan2(d.normal[1], d.normal[0]) for d in self._detections])
            ang = float(angs[0] + np.median(wrap_angle(angs - angs[0])))
            self._set_entrance(Opening(np.median(cs, axis=0), np.array([math.cos(ang), math.sin(ang)]),
                                       float(np.median([d.width for d in self._detections]))))
            self._detections.clear()
            self._scan_steps = 0
            self._steps = 0
            self._misses = 0
            self._state = "approach"
        elif self._scan_steps >= 2 * self.p.scans_to_confirm:
            self._detections.clear()
            self._scan_steps = 0
            self._start_turn(self.p.scan_step)
            self._state = "rotate"
        return Command()

    def _start_turn(self, angle: float) -> None:
        assert self.pose is not None
        self._turn_from = self.pose[2]
        self._turn_goal = float(wrap_angle(self.pose[2] + angle))

    def _rotate(self) -> Command:
        assert self.pose is not None and self._turn_goal is not None
        err = float(wrap_angle(self._turn_goal - self.pose[2]))
        if abs(err) > 0.02:
            return Command(va=turn_rate(err, self.p.turn_speed, 0.3, 0.1))
        self._turned += self.p.scan_step
        if self._turned >= 2 * math.pi - 1e-6:
            self._turned = 0.0
            self._full_turns += 1
            if self._full_turns >= self.p.max_full_turns:
                self.give_up(f"no entrance found after {self._full_turns} full scans")
                return Command()
            self._free_heading = None
            self._state = "free space"
            return Command()
        self._state = "scan"
        return Command()

    def _free_space(self) -> Command:
        assert self.scan is not None and self.pose is not None
        if self._free_heading is None:
            # the longest free direction, smoothed over ~10 degrees so one stray beam cannot win
            r = np.where(np.isfinite(self.scan.ranges), self.scan.ranges, self.p.max_range)
            smooth = np.convolve(r, np.ones(45) / 45, mode="same")
            i = int(np.argmax(smooth))
            self._free_heading = float(wrap_angle(self.pose[2] + self.scan.angles[i]))
            self._drive_from = (self.pose[0], self.pose[1])
        err = float(wrap_angle(self._free_heading - self.pose[2]))
        if abs(err) > self.p.face_tolerance:
            return Command(va=turn_rate(err, self.p.turn_speed, 0.3, 0.1))
        assert self._drive_from is not None
        moved = math.hypot(self.pose[0] - self._drive_from[0], self.pose[1] - self._drive_from[1])
        if moved >= self.p.free_space_distance or self.scan.min_in(-0.3, 0.3) < 0.5:
            self._state = "scan"
            return Command()
        return Command(vx=self.p.drive_speed, va=self.p.heading_gain * err)

    def _recheck(self) -> bool:
        """Every few steps: refresh the entrance; False when it is lost (rescan)."""
        assert self._entrance is not None and self.pose is not None
        self._steps += 1
        if self._steps % self.p.recheck_every:
            return True
        if math.hypot(*(self._approach_point() - np.array(self.pose[:2]))) < self.p.approach_offset:
            return True  # this close the mouth is seen edge-on: trust the estimate
        e = self._detect(near=self._entrance.centre)
        if e is not None and np.hypot(*(e.centre - self._entrance.centre)) < self.p.recheck_radius:
            self._set_entrance(Opening((self._entrance.centre + e.centre) / 2,
                                       self._entrance.normal, e.width))
            self._misses = 0
            return True
        self._misses += 1
        return self._misses < self.p.lost_after

    def _in_hallway(self) -> bool:
        """Walls close on both sides and open ahead: already inside a hallway."""
        assert self.scan is not None
        left, right = self.scan.range_at(math.pi / 2, 4), self.scan.range_at(-math.pi / 2, 4)
        return (left < self.p.hallway_side and right < self.p.hallway_side
                and self.scan.min_in(-0.15, 0.15) > self.p.hallway_side)

    def _enter_hallway(self) -> Command:
        """Go on along the hallway as we face it now (no turning on the spot between its walls)."""
        assert self.pose is not None and self._entrance is not None
        self._entrance = Opening(self._entrance.centre,
                                 np.array([math.cos(self.pose[2]), math.sin(self.pose[2])]), self._entrance.width)
        self._state = "hallway"
        return Command()

    def _approach(self) -> Command:
        assert self.pose is not None
        if self._in_hallway():
            return self._enter_hallway()
        if not self._recheck():
            self._state = "scan"
            return Command()
        goal = self._approach_point()
        dx, dy = goal[0] - self.pose[0], goal[1] - self.pose[1]
        dist = math.hypot(dx, dy)
        if dist < 0.1:
            self._state = "align"
            return Command()
        err = float(wrap_angle(math.atan2(dy, dx) - self.pose[2]))
        if abs(err) > self.p.face_tolerance * 3:
            return Command(va=turn_rate(err, self.p.turn_speed, 0.3, 0.1))
        speed = min(self.p.drive_speed, 0.5 * dist + 0.05) * max(0.0, math.cos(err))
        return Command(vx=speed, va=clamp(self.p.heading_gain * err, self.p.turn_speed))

    def _align(self) -> Command:
        assert self.pose is not None and self._entrance is not None
        heading = math.atan2(self._entrance.normal[1], self._entrance.normal[0])
        err = float(wrap_angle(heading - self.pose[2]))
        if abs(err) > 0.03 and not self._in_hallway():
            return Command(va=turn_rate(err, self.p.turn_speed, 0.3, 0.1))
        self._state = "hallway"
        return Command()

    def _hallway(self) -> Command:
        assert self.scan is not None and self.pose is not None and self._entrance is not None
        if self.scan.min_in(-math.pi / 2, math.pi / 2) > self.p.free_range:
            self._drive_from = (self.pose[0], self.pose[1])
            self._state = "out"
            return Command(vx=self.p.drive_speed)
        if self.scan.min_in(-0.15, 0.15) < self.p.hallway_side / 2:
            # a wall straight ahead: a dead end, not the exit; remember it and back out
            self._dead_ends.append(self._entrance.centre.copy())
            self._state = "back out"
            return Command()
        heading = math.atan2(self._entrance.normal[1], self._entrance.normal[0])
        err = float(wrap_angle(heading - self.pose[2]))
        vy = 0.0
        left, right = self.scan.range_at(math.pi / 2, 4), self.scan.range_at(-math.pi / 2, 4)
        if left < self.p.hallway_side and right < self.p.hallway_side:
            vy = clamp(self.p.centre_gain * (left - right) / 2, 0.2)
            walls = [w for w in (wall_angle(self.scan, math.pi / 2, 0.3),
                                 wall_angle(self.scan, -math.pi / 2, 0.3)) if w is not None]
            if walls:
                # the wall direction (taken along the beam order) is the hallway's heading
                # relative to the robot (or its reverse): steer on it rather than old odometry
                rel = [float(wrap_angle(w if abs(wrap_angle(w)) < math.pi / 2 else w + math.pi)) for w in walls]
                err = float(np.mean(rel))
                self._entrance = Opening(self._entrance.centre,
                                         np.array([math.cos(self.pose[2] + err), math.sin(self.pose[2] + err)]),
                                         self._entrance.width)
        return Command(vx=self.p.drive_speed, vy=vy, va=clamp(self.p.heading_gain * err, self.p.turn_speed))

    def _back_out(self) -> Command:
        """Reverse out of a dead end to the point in front of its mouth, then scan again."""
        assert self.pose is not None and self._entrance is not None
        goal = self._approach_point()
        dx, dy = goal[0] - self.pose[0], goal[1] - self.pose[1]
        if math.hypot(dx, dy) < 0.1:
            self._entrance = None
            self._state = "scan"
            return Command()
        c, s = math.cos(self.pose[2]), math.sin(self.pose[2])
        # holonomic: move straight towards the goal in the robot frame, no turning in the hallway
        vx, vy = c * dx + s * dy, -s * dx + c * dy
        scale = min(1.0, self.p.drive_speed / 2 / max(math.hypot(vx, vy), 1e-9))
        return Command(vx=vx * scale, vy=vy * scale)

    def _out(self) -> Command:
        assert self.pose is not None and self._drive_from is not None
        moved = math.hypot(self.pose[0] - self._drive_from[0], self.pose[1] - self._drive_from[1])
        if moved >= self.p.out_distance:
            self.finish()
            return Command()
        return Command(vx=self.p.drive_speed)

    def result(self) -> dict[str, Any]:
        out = super().result()
        out["bubble_triggers"] = self.bubble.triggers
        return out
