"""A T-opening whose face is seen only through the gap.

Seen obliquely past a room's wall's end, the wall beyond a doorway shows only the piece the
jamb does not hide, out to the view's edge: a piece floating at both ends (cafe:131's doorway,
missed in most poses before this rule). From a building wall's end a face so is still a face,
met on its line up to `end_face_reach` past its floating end while the scan does not look past
that point (`tests/test_face_seen_through_a_side_gap.py`: a piece ending farther short makes
none).
"""

from __future__ import annotations

import numpy as np
import pytest

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import laser_view

PARAMS = load_config(None).perception.identify
ROBOT, HEADING = (-1.5, -3.0), -0.81  # the gap's meeting point just past the view's edge
JAMB = [0.0, -4.0, 0.0, 0.0]  # a room's wall, 4 m, its end at the origin seen
FACE = [-3.0, 0.85, 5.0, 0.85]  # the wall beyond, 0.85 m on


def _identify(piece: list[float]):
    walls = np.array([JAMB, piece])
    seen = np.array([[False, True], [False, False]])  # the jamb's end seen; the piece floating
    view = laser_view(np.array([JAMB, FACE]), ROBOT, HEADING)
    return identify(walls, np.full((2, 2), -1, dtype=np.int64), seen, ROBOT, PARAMS, view)


def test_the_scene_is_what_the_laser_sees():
    """The view shows the face from just past the jamb's line to the jamb's shadow, no more."""
    view = laser_view(np.array([JAMB, FACE]), ROBOT, HEADING)
    ang = view.angles + HEADING
    pts = np.stack([ROBOT[0] + view.ranges * np.cos(ang), ROBOT[1] + view.ranges * np.sin(ang)], axis=1)
    on_face = view.valid & (np.abs(pts[:, 1] - 0.85) < 1e-6)
    assert 0.0 < pts[on_face, 0].min() < PARAMS.door_occlusion
    assert pts[on_face, 0].max() == pytest.approx(0.425, abs=0.02)


def test_a_face_seen_only_through_the_gap_makes_a_door():
    out = _identify([0.04, 0.85, 0.42, 0.85])
    assert out.door_kind == ["end_face"]
    assert np.allclose(out.doors[0], [0.0, 0.0, 0.0, 0.85], atol=1e-6)


@pytest.mark.parametrize("short", [0.15, 0.3])
def test_a_piece_ending_short_of_the_jambs_line_within_reach_makes_one(short):
    """The same piece ending `short` m before the jamb's line, the scan not looking there (the
    view's edge): it may run on, within end_face_reach, so the door stands."""
    assert short < PARAMS.end_face_reach
    out = _identify([short, 0.85, 0.42, 0.85])
    assert out.door_kind == ["end_face"]
    assert np.allclose(out.doors[0], [0.0, 0.0, 0.0, 0.85], atol=1e-6)
