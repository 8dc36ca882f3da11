"""A doorway seen through a nearer doorway is a door.

Rooms in a row (hospital_2019): from one room the robot looks through the doorway ahead into
the next room and on through that room's far doorway. The near doorway's jambs hide all but a
few dm of the far wall beside the far doorway: two short pieces in one line, their jamb ends
seen, their far ends floating where the view stopped. Neither is a door frame's length
(`door_wall_min_length`), so until now the far doorway was neither a door nor a possible door;
pieces seen in part in one line, each continuing through the gap, are its jambs
(`identify_kernels.door_pairs`' `part`). Pieces seen whole (a box's faces in a row) or a piece
in line with a short piece seen whole are not.
"""

from __future__ import annotations

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import laser_view

PARAMS = load_config(None).perception.identify
ROBOT, HEADING = (1.35, -0.5), np.pi / 2  # in the first room, facing the doorways
NEAR = [[-1.0, 2.0, 0.8, 2.0], [1.7, 2.0, 3.5, 2.0]]  # the doorway ahead, 0.8-1.7 m
FAR = [[-1.0, 4.0, 0.8, 4.0], [1.7, 4.0, 3.5, 4.0]]  # the next room's far wall, its doorway in line
LEFT, RIGHT = [0.37, 4.0, 0.8, 4.0], [1.97, 4.0, 1.7, 4.0]  # what the near jambs leave in view


def _identify(pieces: list[list[float]], far_seen: list[bool]):
    """identify on the near walls and `pieces` (each's first end its far end: seen or not)."""
    walls = NEAR + pieces
    connected = np.full((len(walls), 2), -1, dtype=np.int64)
    seen = np.ones((len(walls), 2), dtype=bool)
    for k, s in enumerate(far_seen):
        seen[len(NEAR) + k, 0] = s
    view = laser_view(np.array(NEAR + FAR), ROBOT, HEADING)
    return identify(np.array(walls), connected, seen, ROBOT, PARAMS, view)


def _far_doors(out) -> list[tuple[np.ndarray, str]]:
    """The doors found on the far wall's line, with their kinds."""
    doors = np.asarray(out.doors).reshape(-1, 4)
    return [(d, k) for d, k in zip(doors, out.door_kind, strict=True) if min(d[1], d[3]) > 3.0]


def test_the_near_jambs_hide_all_but_a_few_dm_of_the_far_wall():
    view = laser_view(np.array(NEAR + FAR), ROBOT, HEADING)
    ang = view.angles + HEADING
    x = ROBOT[0] + view.ranges * np.cos(ang)
    y = ROBOT[1] + view.ranges * np.sin(ang)
    on_far = view.valid & (np.abs(y - 4.0) < 1e-6)
    assert on_far.any()
    assert 0.3 < x[on_far].min() < 0.4 and 1.9 < x[on_far].max() < 2.0  # 0.44 and 0.28 m of wall


def test_the_far_doorway_is_a_door():
    out = _identify([LEFT, RIGHT], [False, False])
    far = _far_doors(out)
    assert len(far) == 1
    door, kind = far[0]
    assert np.allclose(sorted(door[[0, 2]]), [0.8, 1.7]) and np.allclose(door[[1, 3]], 4.0)
    assert kind == "jambs"


def test_pieces_seen_whole_are_no_door():
    """Both far ends seen: two short things in a row (a box's faces), no walls running on."""
    out = _identify([LEFT, RIGHT], [True, True])
    assert _far_doors(out) == []


def test_a_piece_in_line_with_a_short_piece_seen_whole_is_no_door():
    out = _identify([LEFT, RIGHT], [False, True])
    assert _far_doors(out) == []
