"""A pocket seen closed stays closed: beside a table standing against a wall, the gap between
the table's front end and the room's side wall is a T-opening by shape, and seen edge-on its rays
say nothing (they land on the side wall), so from one scan it is a door. Seen once from in front,
its rays ending on its back (the wall behind the table) within `end_face_depth`, the place is
remembered closed: later, edge-on, after the local map forgot the back, it is only a possible
door (120 s suite runs: the table pockets were most of the false doors); rays seen through it
deep open it again."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception import Perceptor
from pico_studio.core.perception.face_kernels import BANNED, tally
from tests.clutter_scenes import box, cast, odometry, room

PARAMS = load_config(None).perception
WALLS = np.vstack([room(6.0, 5.0), box(1.6, 0.42, 1.6, 0.8)])  # a table x 0.8-2.4, y 0.02-0.82 by the wall y = 0
HEADING = -math.pi / 2
FRONT, EDGE = (0.4, 2.5), (2.3, 2.4)  # above the pocket (x 0-0.8); above the table's far end


def _look(*views: tuple[tuple[float, float], float]):
    """Ten scans from each (position, start time) in turn, facing -y."""
    p = Perceptor(PARAMS)
    wm = None
    for xy, t0 in views:
        for k in range(10):
            pose, t = (*xy, HEADING), t0 + k * 0.05
            wm = p.step(dataclasses.replace(cast(WALLS, pose), timestamp=t), odometry(pose, t))
    return wm


def _pocket(gaps: np.ndarray, first: tuple[float, float]) -> bool:
    """Is one of `gaps` (the zero frame: the robot's first pose, at `first` facing -y) the
    pocket's mouth, y = 0.82 from x = 0 to 0.8 in the room?"""
    x, y, a = *first, HEADING
    c, s = math.cos(a), math.sin(a)
    for g in np.asarray(gaps, float).reshape(-1, 4):
        ends = [(x + c * g[i] - s * g[i + 1], y + s * g[i] + c * g[i + 1]) for i in (0, 2)]
        if all(abs(e[1] - 0.82) < 0.1 for e in ends) and sorted(round(e[0], 1) for e in ends) == [0.0, 0.8]:
            return True
    return False


def test_seen_edge_on_alone_the_pocket_is_a_door():
    wm = _look((EDGE, 0.0))
    assert _pocket(wm.doors, EDGE)


def test_seen_closed_before_it_stays_a_possible_door():
    # from in front, then 25 s later (the back forgotten: merge.forget_seconds) edge-on
    wm = _look((FRONT, 0.0), (EDGE, 25.0))
    assert not _pocket(wm.doors, FRONT)
    assert _pocket(wm.possible_doors, FRONT)


def test_a_place_closed_opens_again_when_seen_through():
    gap = np.array([[0.0, 0.0, 0.8, 0.0]])
    no, yes = np.array([False]), np.array([True])
    ev, count = tally(np.zeros((0, 5)), gap, no, yes, 0.1, 0.3, 8, True)
    assert count[0] == int(BANNED)
    ev, count = tally(ev, gap + 0.02, yes, no, 0.1, 0.3, 8, True)  # the same place, seen through
    assert count[0] == 0 and ev[:, 4].tolist() == [0.0]
    # seen through where it was never closed: no record (the short walls' counts keep their room)
    assert len(tally(np.zeros((0, 5)), gap, yes, no, 0.1, 0.3, 8, True)[0]) == 0
    # another place (its middle 0.06 m off, beyond 0.1 / 2) is not reopened
    ev, _ = tally(np.zeros((0, 5)), gap, no, yes, 0.1, 0.3, 8, True)
    ev, count = tally(ev, gap + np.array([0.0, 0.06, 0.0, 0.06]), yes, no, 0.1, 0.3, 8, True)
    assert count[0] == 0 and ev[:, 4].tolist() == [BANNED]
    # a short wall's T-opening counting scans (reopen off) stays banned for good
    ev, _ = tally(np.zeros((0, 5)), gap, no, yes, 0.1, 0.3, 8)
    assert tally(ev, gap, yes, no, 0.1, 0.3, 8)[1][0] < 0
