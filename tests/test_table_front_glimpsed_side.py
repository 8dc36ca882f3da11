"""A table's front as long as a building's wall, its far end turning into a side seen in part.

The suites' tables are 1.4-1.6 m long, a building wall's length (`end_face_min_length`); one
standing against a wall, its front's free end a door's width from another wall's face, is a
T-opening's shape. Seen from in front and to one side, the table's far side shows only its
first few cm (floating: the rest hidden, or out of view) and the pocket's back is hidden behind
the front. A building's wall so short turning at a convex corner into a side seen in part is
only ever a possible door "end_face", for the map to prove (suite:141, suite:2's 120 s run own
door precision 0.941 -> 0.985).
"""

from __future__ import annotations

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import box, laser_view

PARAMS = load_config(None).perception.identify
ROBOT, HEADING = (-1.0, -1.13), 0.3
FRONT = [1.58, 0.0, 0.0, 0.0]  # the table's front; its end at x = 1.58 faces the wall at x = 2.44
SIDE = [0.0, 0.0, 0.0, 0.19]  # the first 0.19 m of its far side, the rest unseen
FACE = [2.44, -1.6, 2.44, 0.37]  # the wall a door's width on, seen in part


def _solid() -> np.ndarray:
    """The world: the table 1.58 x 0.84 m against the wall behind it (y = 0.84), the face."""
    return np.vstack([box(0.79, 0.42, 1.58, 0.84), [[-3.0, 0.84, 2.44, 0.84], [2.44, -3.0, 2.44, 0.84]]])


def test_a_table_front_turning_into_a_side_seen_in_part_is_no_door():
    walls = np.array([FRONT, SIDE, FACE])
    conn = np.array([[-1, 1], [0, -1], [-1, -1]], dtype=np.int64)
    seen = np.array([[True, True], [True, False], [False, False]])
    out = identify(walls, conn, seen, ROBOT, PARAMS, laser_view(_solid(), ROBOT, HEADING))
    assert "end_face" not in out.door_kind
    assert "end_face" in out.possible_door_kind


def test_the_same_wall_running_on_out_of_view_is_a_door():
    """No side: its far end floating, the wall runs on (a room's wall) — a T-opening."""
    walls = np.array([FRONT, FACE])
    seen = np.array([[True, False], [False, False]])
    view = laser_view(np.array([[1.58, 0.0, -3.0, 0.0], FACE]), ROBOT, HEADING)
    out = identify(walls, np.full((2, 2), -1, dtype=np.int64), seen, ROBOT, PARAMS, view)
    assert out.door_kind == ["end_face"]
    assert np.allclose(out.doors[0], [1.58, 0.0, 2.44, 0.0], atol=1e-6)
