"""A corridor's mouth is no T-opening.

A room's wall ends where it turns into the side of a corridor as wide as a door, facing the
corridor's other wall, which runs straight on as the room's wall (hospital_2021's four
corridors; rooms opening into a corridor at a corner in ward:131, slant:95). From beside the end
its far side hides behind the wall itself; once the local map holds that side (seen before,
from elsewhere), the end is a corner whose other wall runs on beyond the gap's line, no wall's
end: only a possible door, for the map to prove. A thick wall's end cap (no longer than
`jamb_cap_max`) is no such wall, nor a free end; and a face that ends at the gap's line makes
a passage's mouth (an escape room's corridor), a door as before.
"""

from __future__ import annotations

import numpy as np
import pytest

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import laser_view

PARAMS = load_config(None).perception.identify
ROBOT, HEADING = (2.5, -2.0), 2.3  # in the room, beside the end, looking at the gap
WALL = [4.0, 0.0, 1.0, 0.0]  # the room's north wall, its end at (1, 0)
FACE = [0.0, -4.0, 0.0, 4.0]  # the room's west wall, running on north past the gap


def _identify(side: list[float] | None, face: list[float] = FACE, face_seen: bool = True):
    walls = [WALL, face] + ([side] if side else [])
    connected = np.full((len(walls), 2), -1, dtype=np.int64)
    if side:
        connected[0, 1], connected[2, 0] = 2, 0  # the side joins the wall at its end
    view = laser_view(np.array(walls), ROBOT, HEADING)
    seen = np.ones((len(walls), 2), dtype=bool)
    seen[1, 0] = face_seen
    return identify(np.array(walls), connected, seen, ROBOT, PARAMS, view)


def test_the_corridor_side_known_makes_only_a_possible_door():
    out = _identify([1.0, 0.0, 1.0, 3.0])
    assert len(out.doors) == 0
    assert "end_face" in out.possible_door_kind
    k = out.possible_door_kind.index("end_face")
    assert np.allclose(out.possible_doors[k], [1.0, 0.0, 0.0, 0.0], atol=1e-6)


@pytest.mark.parametrize("side", [None, [1.0, 0.0, 1.0, 0.2]], ids=["free end", "end cap"])
def test_a_wall_end_stays_a_door(side):
    out = _identify(side)
    assert out.door_kind == ["end_face"]
    assert np.allclose(out.doors[0], [1.0, 0.0, 0.0, 0.0], atol=1e-6)


def test_a_passage_mouth_stays_a_door():
    """The face ending at the gap's line (its corner there, the room's wall beside it unseen,
    its end floating: an escape room's corridor) makes a passage's mouth, a door."""
    out = _identify([1.0, 0.0, 1.0, 3.0], [0.0, -0.05, 0.0, 4.0], face_seen=False)
    assert out.door_kind == ["end_face"]


def test_the_side_out_of_view_now():
    """The corridor's side lies behind the room's wall from here: the view cannot tell."""
    view = laser_view(np.array([WALL, FACE, [1.0, 0.0, 1.0, 3.0]]), ROBOT, HEADING)
    ang = view.angles + HEADING
    pts = np.stack([ROBOT[0] + view.ranges * np.cos(ang), ROBOT[1] + view.ranges * np.sin(ang)], axis=1)
    on_side = view.valid & (np.abs(pts[:, 0] - 1.0) < 1e-6) & (pts[:, 1] > 0.01)
    assert not on_side.any()
