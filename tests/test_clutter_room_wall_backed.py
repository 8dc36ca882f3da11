"""A room's wall opens whatever stands behind its end: a T-opening from the end of a wall at
least `end_face_room_wall` long whose far end is a concave corner is a door though the rays
through it end on a cabinet within `end_face_depth` behind it (suite:1202, suite:321: a cabinet
0.8 m inside the room beyond a doorway beside the corridor's wall). A shorter wall so — a bed's
2 m side, its head against the back wall — is a pocket's side: the cabinet backs the gap."""

from __future__ import annotations

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import box, has_gap, laser_view

PARAMS = load_config(None).perception.identify
ROBOT = (2.08, 1.62)
HEADING = -0.24
FACE_Y = 0.1  # the corridor wall's face, the doorway's far side
END = (3.55, 0.99)  # the room wall's end, the doorway's near side
DOORWAY = [END[0], END[1], END[0], FACE_Y]


def _scene(length: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[list[float]]]:
    """The room wall running `length` up from its end into the back wall (concave), the corridor
    wall's face, a cabinet 0.86 m behind the doorway standing against the face (concave)."""
    top = END[1] + length
    cabinet = box(4.86, 0.5, 0.9, 0.8)  # x 4.41-5.31, y 0.1-0.9
    solid = [[0.0, FACE_Y, 8.0, FACE_Y], [END[0], END[1], END[0], top], [END[0], END[1], 3.75, END[1]],
             [3.75, END[1], 3.75, top], [0.5, top, END[0], top], *cabinet.tolist()]
    walls = np.array([[END[0], END[1], END[0], top], [END[0], top, 1.74, top],
                      [3.1, FACE_Y, 4.41, FACE_Y], [4.41, FACE_Y, 4.41, 0.62]])
    connected = np.array([[-1, 1], [0, -1], [-1, 3], [2, -1]], dtype=np.int64)
    seen = np.array([[True, False], [False, False], [False, False], [False, False]])
    return walls, connected, seen, solid


def _doors(length: float) -> np.ndarray:
    walls, connected, seen, solid = _scene(length)
    return identify(walls, connected, seen, ROBOT, PARAMS, laser_view(solid, ROBOT, HEADING)).doors


def test_a_room_walls_end_is_a_door_with_a_cabinet_behind():
    assert has_gap(_doors(2.39), DOORWAY, 0.05)


def test_a_beds_side_so_is_a_pockets_side():
    assert not has_gap(_doors(2.0), DOORWAY, 0.05)
