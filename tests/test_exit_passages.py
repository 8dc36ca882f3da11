"""A short exit passage between two mouths.

An escape room's exit: a passage 0.6 m wide and 1 m long from the room's wall to the outside.
Seen at a slant from the room, every ray through its mouth ends on its far side, within
`door_depth`: no ray shows free space behind, and both sides end at their far ends in the open
(the laser seen past them, convex and joined to nothing) — a side running `door_depth` deep
into a seen end may be a bed's foot, but both sides of a passage running out so is a passage
(`map_proven_kernels.deep_sides`). 120 s own door recall escape:0 0.901 -> 0.949, escape:2
0.912 -> 0.992. One side ending free and the other at a seen corner stays a possible bay."""

from __future__ import annotations

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import laser_view

PARAMS = load_config(None).perception.identify
LEFT_WALL, RIGHT_WALL = [-3.0, 0.0, 0.0, 0.0], [0.6, 0.0, 3.0, 0.0]  # the room's wall
LEFT_SIDE, RIGHT_SIDE = [0.0, 0.0, 0.0, -1.0], [0.6, 0.0, 0.6, -1.0]  # the passage, down to y = -1
MOUTH = np.array([0.0, 0.0, 0.6, 0.0])
ROBOT, HEADING = (-2.0, 2.0), -0.8


def _bays(walls: list[list[float]], connected: list[list[int]], seen: list[list[bool]]):
    w = np.array(walls, dtype=float)
    out = identify(w, np.array(connected, dtype=np.int64), np.array(seen, dtype=bool), ROBOT, PARAMS,
                   laser_view(w, ROBOT, HEADING))
    def at_mouth(gaps: np.ndarray) -> bool:
        return any(np.allclose(g, MOUTH, atol=0.02) or np.allclose(g, np.r_[MOUTH[2:], MOUTH[:2]], atol=0.02) for g in gaps)
    return at_mouth(out.doors), at_mouth(out.possible_doors[[k == "bay" for k in out.possible_door_kind]])


WALLS = [LEFT_WALL, RIGHT_WALL, LEFT_SIDE, RIGHT_SIDE]
JOINED = [[-1, 2], [3, -1], [0, -1], [1, -1]]  # each side joined to the room's wall at the mouth


def test_both_sides_running_out_into_the_open_make_a_door():
    door, _ = _bays(WALLS, JOINED, [[False, True], [True, False], [True, True], [True, True]])
    assert door


def test_one_side_ending_at_a_seen_corner_is_not_enough():
    foot = [0.0, -1.0, 0.3, -1.0]  # the left side turns at its far end (a bed's foot)
    door, possible = _bays(WALLS + [foot], [[-1, 2], [3, -1], [0, 4], [1, -1], [2, -1]],
                           [[False, True], [True, False], [True, True], [True, True], [True, True]])
    assert not door and possible
