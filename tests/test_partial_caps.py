"""A door's jamb whose frame corner came out in fragments.

Seen at a slant from far down a corridor, the corner of a doorway's thick wall comes out as a
piece a few cm long joined to the wall's end at an angle, its far end floating: a cap seen in
part, which makes no jamb (a table's side seen in part may run deep). A building wall's end
joined to such a piece is a jamb all the same opposite another building wall in its line
(`end_face_min_length` both: ward corridors' doors, held-out and unseen wards' own door recall up
0.002); never towards a short piece across the line (a bed's foot seen in part beside a door
frame's cap), nor as a T-opening's.
"""

from __future__ import annotations

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import laser_view

PARAMS = load_config(None).perception.identify
ROBOT = (0.0, -1.5)


def _identify(walls: list[list[float]], conn: list[list[int]], seen: list[list[bool]], solid: int):
    w = np.array(walls, dtype=float)
    return identify(w, np.array(conn, dtype=np.int64), np.array(seen, dtype=bool), ROBOT, PARAMS,
                    laser_view(w[:solid], ROBOT, np.pi / 2))


# the corridor wall's left part, 3 m, ending at x = -0.45 in a 7 cm fragment (its frame corner)
LEFT, FRAGMENT = [-3.45, 0.0, -0.45, 0.0], [-0.52, 0.05, -0.45, 0.0]


def test_a_building_walls_end_with_a_fragment_is_a_jamb_opposite_a_building_wall_in_line():
    out = _identify([LEFT, [0.45, 0.0, 2.45, 0.0], FRAGMENT], [[-1, 2], [-1, -1], [-1, 0]],
                    [[False, True], [True, False], [False, True]], 2)
    assert out.door_kind == ["jambs"]
    assert np.allclose(out.doors[0], [-0.45, 0.0, 0.45, 0.0], atol=1e-6)


def test_opposite_a_short_wall_it_is_none():
    """The same end opposite a 1 m piece in its line (shorter than a building's wall): none."""
    out = _identify([LEFT, [0.45, 0.0, 1.45, 0.0], FRAGMENT], [[-1, 2], [-1, -1], [-1, 0]],
                    [[False, True], [True, True], [False, True]], 2)
    assert "jambs" not in out.door_kind


def test_it_makes_no_t_opening():
    """The same end 0.9 m from a wall's face across its line: no T-opening (from an end joined to
    nothing it is one)."""
    face = [0.45, -2.5, 0.45, 2.5]
    out = _identify([LEFT, face, FRAGMENT], [[-1, 2], [-1, -1], [-1, 0]],
                    [[False, True], [False, False], [False, True]], 2)
    assert "end_face" not in out.door_kind
    alone = _identify([LEFT, face], [[-1, -1], [-1, -1]], [[False, True], [False, False]], 2)
    assert alone.door_kind == ["end_face"]
