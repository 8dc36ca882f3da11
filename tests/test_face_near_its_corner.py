"""A T-opening whose face is met near that wall's own corner.

A room's wall ending in a doorway faces the room's side wall, which ends a wall's thickness
past the doorway's line where it turns (slant:26, slant:22: a thick wall's end; the door in
the room's corner). The end's ray meets the side wall's face within `jamb_cap_max` of its
free convex end: a table's corner looks so too, but a table's corner pokes into the line
from beyond it, its side running on away from the robot; the room's own wall lies on the
robot's side, only its end past the line. Before this rule a side wall ending 0.2-0.35 m past
the line fell between the two rules (two convex ends make a door up to about 0.2 m off the
line; a face counted only `jamb_cap_max` from its corner): slant:26's recall 0.82 -> 0.94.
"""

from __future__ import annotations

import numpy as np
import pytest

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import laser_view

PARAMS = load_config(None).perception.identify
ROBOT, HEADING = (2.0, -2.0), 2.3  # in the room, looking towards its north-west corner
JAMB = [4.0, 0.0, 1.0, 0.0]  # the room's north wall, its end at (1, 0): the doorway's jamb


def _identify(side: list[float]):
    walls = np.array([JAMB, side])
    view = laser_view(walls, ROBOT, HEADING)
    seen = np.ones((2, 2), dtype=bool)  # every end in view: the side's end a free convex corner
    return identify(walls, np.full((2, 2), -1, dtype=np.int64), seen, ROBOT, PARAMS, view)


@pytest.mark.parametrize("past", [0.25, 0.3])
def test_the_side_wall_ending_just_past_the_line_makes_a_door(past):
    """The room's west wall runs from the robot's side to `past` m beyond the doorway's line."""
    out = _identify([0.0, -4.0, 0.0, past])
    assert out.door_kind == ["end_face"]
    assert np.allclose(out.doors[0], [1.0, 0.0, 0.0, 0.0], atol=1e-6)


@pytest.mark.parametrize("into", [0.25, 0.3])
def test_a_corner_poking_into_the_line_from_beyond_makes_none(into):
    """The same wall running away beyond the line, its end `into` m into the room (a table's
    corner, its side behind the doorway's line): no door from its corner."""
    out = _identify([0.0, 4.0, 0.0, -into])
    assert len(out.doors) == 0


def test_the_rules_either_side_stand():
    """Nearer the line the two convex ends make the door; farther past, the face is met well
    away from its corner."""
    assert _identify([0.0, -4.0, 0.0, 0.1]).door_kind == ["jambs"]
    assert _identify([0.0, -4.0, 0.0, PARAMS.jamb_cap_max + 0.2]).door_kind == ["end_face"]
