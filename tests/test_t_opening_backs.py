"""What a T-opening's rays land on: its back, or not.

A T-opening (a wall's end facing another wall's face) is backed, no door, when most rays through
it end within `end_face_depth` behind its line between its jambs: the pocket beside a table.
Two things the rays land on are no back:

* the face itself, run on past the gap. The far jamb is the face's line, square to the gap only
  within `door_angle`: in a slanted building (`slant` worlds) the rays landing on the face a few
  dm past the gap lie 0.1-0.2 m off the gap's normal there, and were taken for a back;
* a small object standing in the room behind (a box a few dm past the gap), as for a bay's rays.
"""

from __future__ import annotations

import numpy as np
import pytest

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import box, laser_view

PARAMS = load_config(None).perception.identify


@pytest.mark.parametrize("robot, heading", [((2.33, 3.37), -1.2), ((2.8, 2.6), -1.0)])
def test_rays_landing_on_a_slanted_face_past_the_gap_are_no_back(robot, heading):
    """slant:301: a partition 80 degrees to the corridor's wall ends 1.25 m from it; seen from
    beside the partition every ray through the gap lands on the corridor's wall beyond it."""
    wall, face = [4.28, 4.38, 3.67, 1.25], [-1.0, 0.0, 8.0, 0.0]
    walls = np.array([wall, face])
    seen = np.array([[False, True], [False, False]])
    out = identify(walls, np.full((2, 2), -1, dtype=np.int64), seen, robot, PARAMS, laser_view(walls, robot, heading))
    assert out.door_kind == ["end_face"]
    assert np.allclose(out.doors[0], [3.67, 1.25, 3.43, 0.0], atol=0.01)


@pytest.mark.parametrize("depth", [0.35, 0.5, 0.6])
def test_a_box_standing_behind_a_t_opening_is_no_back(depth):
    """A wall ending 0.9 m from a wall's face, a 0.3 m box standing `depth` behind the gap: the
    rays through the gap end on the box, a thing in the room behind, not the room's back."""
    walls = np.vstack([[[-3.0, 0.0, 0.0, 0.0], [0.9, -2.5, 0.9, 2.5]], box(0.45, depth, 0.3)])
    conn = np.full((6, 2), -1, dtype=np.int64)
    for i in range(4):  # the box's sides joined around it
        conn[2 + i, 1], conn[2 + (i + 1) % 4, 0] = 2 + (i + 1) % 4, 2 + i
    seen = np.array([[False, True], [False, False]] + [[True, True]] * 4)
    robot = (-0.5, -1.5)
    out = identify(walls, conn, seen, robot, PARAMS, laser_view(walls, robot, 1.2))
    assert out.door_kind == ["end_face"]
    assert np.allclose(out.doors[0], [0.0, 0.0, 0.9, 0.0], atol=1e-6)
    # a wall as close behind the gap, no object, is its back: a pocket
    back = np.array([[-3.0, 0.0, 0.0, 0.0], [0.9, -2.5, 0.9, 2.5], [0.9, depth + 0.15, -3.0, depth + 0.15]])
    seen3 = np.array([[False, True], [False, False], [True, False]])
    pocket = identify(back, np.full((3, 2), -1, dtype=np.int64), seen3, robot, PARAMS, laser_view(back, robot, 1.2))
    assert "end_face" not in pocket.door_kind
