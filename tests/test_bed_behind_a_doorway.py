"""A bed's foot a metre behind a thick wall's doorway is no door's jamb.

Seen from outside, a doorway in a thick wall shows the two faces and their end caps; a bed
stands in the room beyond, its 0.9 m foot square to the doorway a metre in, its sides edge-on
(ward:130, slant:130). The cap is a stub on the wall's face: its line runs on through the room,
and the bed's foot stands across that line. A stub's line ends at no block's face across it
(a wall seen whole, both ends convex, longer than a cap, shorter than a building's wall).
"""

from __future__ import annotations

import numpy as np
import pytest

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import box, laser_view

PARAMS = load_config(None).perception.identify


def _scene(bed_at: float):
    """The local map (faces, caps, the bed's foot), its connections and seen ends, and the solid
    world the laser sees (the wall 0.2 m thick, its doorway 0.9 m wide; the bed 0.9 x 2 m)."""
    walls = np.array([[-3.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.2],  # left face and its cap
                      [4.0, 0.0, 0.9, 0.0], [0.9, 0.0, 0.9, 0.2],  # right face and its cap
                      [0.0, bed_at, 0.9, bed_at]])  # the bed's foot
    conn = np.full((5, 2), -1, dtype=np.int64)
    conn[0, 1], conn[1, 0], conn[2, 1], conn[3, 0] = 1, 0, 3, 2
    seen = np.array([[False, True], [True, True], [False, True], [True, True], [True, True]])
    solid = np.vstack([walls[:4], [[-3.0, 0.2, 0.0, 0.2], [0.9, 0.2, 4.0, 0.2]],
                       box(0.45, bed_at + 1.0, 0.9, 2.0)])
    return walls, conn, seen, solid


@pytest.mark.parametrize("robot", [(0.45, -1.5), (-0.3, -1.2), (1.4, -1.0)])
def test_the_doorway_is_a_door_and_the_bed_no_jamb(robot):
    walls, conn, seen, solid = _scene(1.2)
    heading = np.arctan2(0.6 - robot[1], 0.45 - robot[0])
    out = identify(walls, conn, seen, robot, PARAMS, laser_view(solid, robot, heading))
    doors = np.asarray(out.doors, dtype=float).reshape(-1, 4)
    across = [d for d in doors if abs(d[3] - d[1]) < 0.25]  # along the wall: the doorway
    along = [d for d in doors if abs(d[3] - d[1]) >= 0.25]  # into the room, to the bed's foot
    assert len(across) == 1 and abs(abs(across[0][2] - across[0][0]) - 0.9) < 0.05
    assert along == []
