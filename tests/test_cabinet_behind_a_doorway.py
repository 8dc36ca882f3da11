"""A cabinet standing behind a doorway leaves it a door; a pocket's back does not.

A T-opening (a room wall's end facing the side wall's face, 1 m on) is looked through before
it is a door: the rays through the gap that end within `end_face_depth` behind it, between
its jambs, are a pocket's back (a table standing against a wall makes one). A box or a
cabinet standing in the room beyond, half a metre in, catches those rays too; but the laser
saw past its end, there in the gap's shadow, which no pocket's back shows (it runs across the
whole shadow into its corners). Rays ending on a wall with a seen end in the shadow, joined to
neither jamb's walls, say nothing of a back (`identify_kernels.backed_beside_things`); rooms'
closets and wards' doorways with a cabinet behind were missed for it. Nor is the side wall
turning into a wall just past the line a pocket's back while such a thing stands there.
"""

from __future__ import annotations

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import box, laser_view

PARAMS = load_config(None).perception.identify
ROBOT, HEADING = (2.0, -1.5), np.pi / 2  # in the room, the doorway ahead and to the right
JAMB = [0.0, 0.0, 3.0, 0.0]  # the room's wall, its end at (3, 0) the doorway's jamb
FACE = [4.0, -2.0, 4.0, 3.0]  # the side wall, running on past the doorway's line
CABINET = box(3.5, 0.6, 0.4).tolist()  # a cabinet half a metre in
FRONT = [3.7, 0.4, 3.3, 0.4]  # all the local map holds of it: its front, its right end hidden by the face
BACK = [4.0, 0.6, 2.5, 0.6]  # a pocket's back, across the whole shadow


def _doorway_doors(local: list[list[float]], connected: list[list[int]], seen: list[list[bool]],
                   solid: list[list[float]]) -> list[str]:
    """The kinds of the doors found in the doorway (3, 0)-(4, 0)."""
    view = laser_view(np.array(solid), ROBOT, HEADING)
    out = identify(np.array(local), np.array(connected, dtype=np.int64), np.array(seen), ROBOT, PARAMS, view)
    doors = np.asarray(out.doors).reshape(-1, 4)
    return [k for d, k in zip(doors, out.door_kind, strict=True)
            if np.allclose(sorted(d[[0, 2]]), [3.0, 4.0], atol=0.05) and np.allclose(d[[1, 3]], 0.0, atol=0.05)]


def test_the_rays_through_the_doorway_end_on_the_cabinet():
    view = laser_view(np.array([JAMB, FACE, *CABINET]), ROBOT, HEADING)
    ang = view.angles + HEADING
    x = ROBOT[0] + view.ranges * np.cos(ang)
    y = ROBOT[1] + view.ranges * np.sin(ang)
    on_front = view.valid & (np.abs(y - 0.4) < 1e-6) & (x > 3.3) & (x < 3.7)
    through = view.valid & (y > 0.05) & (x > 3.0) & (x < 4.0)
    assert on_front.sum() > 0.5 * through.sum()  # most of what passes the gap lands on the cabinet


def test_a_doorway_with_a_cabinet_behind_is_a_door():
    """The front's left end seen past (convex): something standing there, not the room's back.
    (Seen whole, the front would be a small object, whose rays said nothing before.)"""
    local = [JAMB, FACE, FRONT]
    seen = [[False, True], [False, False], [False, True]]
    assert _doorway_doors(local, [[-1, -1]] * 3, seen, [JAMB, FACE, *CABINET]) == ["end_face"]


def test_a_pocket_with_its_back_across_is_no_door():
    local = [JAMB, FACE, BACK]
    seen = [[False, True], [False, False], [False, False]]  # the back runs on behind the jamb, out of view
    assert _doorway_doors(local, [[-1, -1]] * 3, seen, local) == []


def test_a_cabinet_seen_as_a_back_without_its_end_is_no_door():
    """The same front, neither end seen past (it may run on out of view): a back, as before."""
    local = [JAMB, FACE, FRONT]
    seen = [[False, True], [False, False], [False, False]]
    assert _doorway_doors(local, [[-1, -1]] * 3, seen, [JAMB, FACE, *CABINET]) == []


# The side wall turning, 0.7 m past the doorway's line, into a wall along the room beyond (the
# top of a cabinet standing against it, fused with its corner): from a wall whose far end is no
# room's corner, that is a pocket's back (a table 1.5 m long standing against a wall), unless
# a thing stands in the shadow apart from the jambs' walls, its end seen past.
SHORT_FACE = [4.0, -2.0, 4.0, 0.7]
TURN = [4.0, 0.7, 3.75, 0.7]
PIECE = [3.7, 0.5, 3.3, 0.5]  # the cabinet's front, its left end seen past
SOLID = [JAMB, SHORT_FACE, TURN, *box(3.5, 0.7, 0.4).tolist()]


def _turning(piece_joined: bool) -> list[str]:
    local = [JAMB, SHORT_FACE, TURN, PIECE]
    connected = [[-1, -1], [-1, 2], [1, 3 if piece_joined else -1], [2 if piece_joined else -1, -1]]
    seen = [[False, True], [False, False], [False, False], [False, True]]
    return _doorway_doors(local, connected, seen, SOLID)


def test_a_cabinet_standing_apart_in_a_shallow_turn_leaves_a_door():
    assert _turning(piece_joined=False) == ["end_face"]


def test_a_piece_joined_to_the_face_is_the_pocket_s_own():
    assert _turning(piece_joined=True) == []
