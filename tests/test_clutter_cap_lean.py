"""An end cap's direction is measured over its few cm: a wall standing across a doorway's line
may lean by `door_angle` plus atan(`door_cap_noise` / its length). A slanted room wall with a
doorway beside it (slant:172): the doorway's far jamb is the 0.1 m end of the horizontal wall's
stub against the slanted face, seen from the slanted face's corner — 19° off square, past the
17° a long wall may lean, so the doorway went unseen from the corridor. A wall as long as a
door frame's keeps the strict angle."""

from __future__ import annotations

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import has_gap, laser_view

PARAMS = load_config(None).perception.identify
# the corridor's upper wall (faces y 2.15 / 2.25) ending at x 13.42; the slanted room wall's face
# from (13.69, 0) up to the stub (x 14.18-14.22) beside the doorway, then on up
SOLID = [[10.0, 2.15, 13.42, 2.15], [13.42, 2.15, 13.42, 2.25], [13.42, 2.25, 10.0, 2.25],
         [13.69, 0.0, 14.217, 2.15], [14.217, 2.15, 14.18, 2.15], [14.18, 2.15, 14.18, 2.25],
         [14.18, 2.25, 14.242, 2.25], [14.242, 2.25, 15.1, 5.69], [10.0, 0.0, 13.69, 0.0],
         [10.0, 4.5, 16.0, 4.5]]
DOORWAY = [13.42, 2.17, 14.18, 2.24]


def _local_map(cap: list[float]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The corridor wall (its end seen), the slanted face's lower piece turning at a concave
    corner into `cap`, the face above the doorway."""
    walls = np.array([[13.42, 2.17, 11.24, 2.17], [13.98, 1.17, 14.22, 2.15], cap, [14.32, 2.53, 15.1, 5.69]])
    connected = np.array([[-1, -1], [-1, 2], [1, -1], [-1, -1]], dtype=np.int64)
    seen = np.array([[True, False], [False, False], [False, True], [False, False]])
    return walls, connected, seen


def _has(doors: np.ndarray, gap: list[float]) -> bool:
    return has_gap(doors, gap, 0.05)


def test_a_short_cap_leaning_with_a_slanted_wall_frames_the_doorway():
    robot = (12.6, 1.0)
    walls, connected, seen = _local_map([14.22, 2.15, 14.18, 2.24])
    out = identify(walls, connected, seen, robot, PARAMS, laser_view(SOLID, robot, 0.6))
    assert _has(out.doors, DOORWAY)


def test_a_longer_wall_leaning_so_frames_nothing():
    # the same lean over 0.5 m, joined to nothing (a door frame's wall seen askew, a bed's side):
    # no wall standing across the line
    robot = (12.6, 1.0)
    walls, connected, seen = _local_map([14.383, 1.783, 14.18, 2.24])
    connected[1, 1], connected[2, 0] = -1, -1
    out = identify(walls, connected, seen, robot, PARAMS, laser_view(SOLID, robot, 0.6))
    assert not _has(out.doors, DOORWAY)
