"""Escape room pieces on hand-built scans: opening detection, bubbleRobot, the state machine."""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config.tree import Config
from pico_studio.core.behaviours.base import Scan
from pico_studio.core.behaviours.bubble import Bubble, box_clearance
from pico_studio.core.behaviours.escape_room import EscapeRoom, find_openings
from pico_studio.core.io import LaserData, OdometryData


def wall_points(x0, y0, x1, y1, step=0.02):
    n = max(2, int(math.hypot(x1 - x0, y1 - y0) / step))
    t = np.linspace(0, 1, n)
    return np.column_stack([x0 + t * (x1 - x0), y0 + t * (y1 - y0)])


def sorted_by_angle(p):
    return p[np.argsort(np.arctan2(p[:, 1], p[:, 0]))]


def test_opening_in_the_wall_ahead_is_found_with_its_width_and_normal():
    # wall at x = 2 with a 0.8 m gap from y = 0.2 to y = 1.0; a hallway beyond, open at its end
    pts = np.vstack([
        wall_points(2, -2, 2, 0.2), wall_points(2, 1.0, 2, 3),
        wall_points(2, 1.0, 3.5, 1.0),  # far hallway wall (the near one is hidden)
    ])
    ang = np.arctan2(pts[:, 1], pts[:, 0])
    pts = sorted_by_angle(pts[np.abs(ang) <= 2.0])
    found = find_openings(pts, 0.5, 1.3)
    assert len(found) == 1
    o = found[0]
    assert abs(o.width - 0.8) < 0.05
    assert np.allclose(o.centre, [2.0, 0.6], atol=0.05)
    assert np.allclose(o.normal, [1.0, 0.0], atol=0.05)


def test_closed_room_has_no_opening_and_narrow_gaps_are_ignored():
    pts = np.vstack([wall_points(2, -2, 2, 0.0), wall_points(2, 0.3, 2, 3)])
    assert find_openings(sorted_by_angle(pts), 0.5, 1.3) == []
    closed = sorted_by_angle(wall_points(2, -2, 2, 3))
    assert find_openings(closed, 0.5, 1.3) == []


def laser(ranges, t):
    n = len(ranges)
    return LaserData(0.01, 10.0, -2.0, 2.0, 4.0 / (n - 1), t, np.asarray(ranges, float))


def flat_wall_ranges(distance, n=1000):
    ang = -2.0 + np.arange(n) * 4.0 / (n - 1)
    with np.errstate(divide="ignore"):
        r = np.where(np.cos(ang) > 0.05, distance / np.cos(ang), np.inf)
    return r


def test_bubble_triggers_near_a_wall_and_backs_off_further_than_the_bubble():
    cfg = Config().behaviour
    b = Bubble(cfg.bubble, cfg.common)
    far = Scan.from_laser(laser(flat_wall_ranges(1.0), 0.0))
    assert b.check(far, (0, 0, 0)) is None
    near = Scan.from_laser(laser(flat_wall_ranges(0.2), 0.0))  # front of the box at 0.18
    assert b.check(near, (0, 0, 0)) is not None and b.active
    cmd = b.check(near, (0, 0, 0))
    assert cmd is not None and cmd.vx < 0 and abs(cmd.vy) < 1e-9
    needed = cfg.bubble.radius + cfg.bubble.backoff_extra - 0.02
    assert b.check(near, (-(needed - 0.01), 0, 0)) is not None
    assert b.check(far, (-(needed + 0.01), 0, 0)) is None and not b.active
    assert box_clearance(np.array([[0.0, 0.0]]), 0.36, 0.16)[0] == 0.0


def test_no_entrance_rotates_in_30_degree_steps_then_moves_to_free_space():
    cfg = Config().behaviour
    er = EscapeRoom(cfg)
    r = flat_wall_ranges(2.0)
    heading, t, states = 0.0, 0.0, []
    for _ in range(2000):
        cmd = er.step(None, laser(r, t), OdometryData(0.0, 0.0, heading, t), t)
        heading = math.remainder(heading + cmd.va * 0.05, 2 * math.pi)
        t += 0.05
        states.append(er.state)
        if er.state == "free space":
            break
    assert "rotate" in states and states[-1] == "free space"
    assert er._full_turns == 1


def test_stale_data_and_not_ok_stop_the_base():
    cfg = Config().behaviour
    er = EscapeRoom(cfg)
    r = flat_wall_ranges(2.0)
    er.step(None, laser(r, 0), OdometryData(0, 0, 0, 0), 0.0)
    cmd = er.step(None, None, None, 5.0)
    assert (cmd.vx, cmd.vy, cmd.va) == (0, 0, 0) and "stale" in er.halted_reason
    cmd = er.step(None, laser(r, 5.05), OdometryData(0, 0, 0, 5.05), 5.05, ok=False)
    assert (cmd.vx, cmd.vy, cmd.va) == (0, 0, 0) and er.halted_reason == "robot not ok"
