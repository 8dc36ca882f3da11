"""A doorway far along a corridor's wall, seen at a grazing angle: the wall past it is only
sparse scan points, no wall of the local map; the near jamb's wall runs on in them past a door's
width (`core/perception/line_jambs.py`)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from pico_studio.core.perception.line_jambs import line_jamb_doors
from pico_studio.core.world_model import CONVEX
from tests.clutter_scenes import laser_view

PARAMS = load_config(None).perception.identify
ROBOT = (0.5, 1.5)
# the corridor: its lower wall y = 0, its upper wall y = 2 with a doorway 5.0..6.0, a room behind
LOWER, NEAR, FAR = [-1.0, 0.0, 12.0, 0.0], [-1.0, 2.0, 5.0, 2.0], [6.0, 2.0, 12.0, 2.0]
ROOM = [[5.0, 2.0, 5.0, 6.0], [6.0, 2.0, 6.0, 6.0], [5.0, 6.0, 6.0, 6.0]]
DOOR = np.array([5.0, 2.0, 6.0, 2.0])
# the local map: both corridor walls up to the doorway, the near one's end there seen; the far
# wall past the doorway, seen at 2.5-5 degrees, is not in it
WALLS = np.array([LOWER, NEAR])
CONNECTED = np.full((2, 2), -1, dtype=np.int64)
SEEN = np.array([[False, False], [False, True]])


def _doors(solid: list[list[float]], params=PARAMS):
    out = identify(WALLS, CONNECTED, SEEN, ROBOT, params, laser_view(solid, ROBOT, 0.0))
    return out, [d for d, k in zip(out.doors, out.door_kind, strict=True) if k == "jambs"]


def test_a_doorway_seen_at_a_grazing_angle_is_a_door():
    out, jambs = _doors([LOWER, NEAR, FAR, *ROOM])
    assert len(jambs) == 1 and np.allclose(jambs[0], DOOR, atol=0.05)
    assert "jamb" not in out.possible_door_kind  # the lone jamb it was
    off = _doors([LOWER, NEAR, FAR, *ROOM], replace(PARAMS, line_jamb_run=0.0))[0]
    assert len(off.doors) == 0 and "jamb" in off.possible_door_kind


def test_a_short_thing_in_line_is_no_far_jamb():
    """A box 0.2 m long standing in the wall's line past a door's width, nothing beyond it: too
    short for a wall running on (line_jamb_run)."""
    assert PARAMS.line_jamb_run > 0.2
    _, jambs = _doors([LOWER, NEAR, [6.0, 2.0, 6.2, 2.0], *ROOM])
    assert not jambs


def test_a_gap_closed_right_behind_is_no_door():
    """Seen from below the gap, every ray through it ends on a wall right behind it (a recess
    shallower than door_occlusion, its back off the line by more than door_offset_short): not
    seen through, the end stays a lone jamb; open behind, the same view finds the door."""
    depth = (PARAMS.door_offset_short + PARAMS.door_occlusion) / 2
    assert PARAMS.door_offset_short < depth < PARAMS.door_occlusion
    robot, heading = (5.5, 0.5), np.pi / 2

    def found(solid: list[list[float]]) -> bool:
        out = identify(WALLS, CONNECTED, SEEN, robot, PARAMS, laser_view(solid, robot, heading))
        return any(np.allclose(d, DOOR, atol=0.05) for d in out.doors)

    assert not found([LOWER, NEAR, FAR, [5.0, 2.0 + depth, 6.0, 2.0 + depth]])
    assert found([LOWER, NEAR, FAR, *ROOM])


def test_points_on_a_wall_of_the_local_map_are_left_to_the_pairs():
    """Where the far wall is in the local map, its points are door_pairs' to judge."""
    view = laser_view([LOWER, NEAR, FAR, *ROOM], ROBOT, 0.0)
    lone = np.array([[5.0, 2.0, 5.0 + PARAMS.door_max_width, 2.0]])
    doors, used = line_jamb_doors(lone, WALLS, view.ranges, view.angles, view.valid, view.valid, view.pose, PARAMS)
    assert used.tolist() == [True] and np.allclose(doors[0], DOOR, atol=0.05)
    doors, used = line_jamb_doors(lone, np.vstack([WALLS, [FAR]]), view.ranges, view.angles, view.valid, view.valid,
                                  view.pose, PARAMS)
    assert used.tolist() == [False] and len(doors) == 0


def test_a_tracked_object_in_line_is_no_far_jamb():
    """A person walking in the wall's line past the gap: the beams on them are a tracked
    object's (View.tracked), no wall's points; untracked, the same beams make a far jamb."""
    person = [[6.0, 2.0, 6.4, 2.0], [6.0, 2.0, 6.0, 2.3], [6.4, 2.0, 6.4, 2.3]]
    robot, heading = (3.5, 1.0), 0.3
    view = laser_view([LOWER, NEAR, *person, *ROOM], robot, heading)
    x = view.ranges * np.cos(view.angles + heading) + robot[0]
    y = view.ranges * np.sin(view.angles + heading) + robot[1]
    tracked = view.valid & (np.abs(y - 2.0) < 0.02) & (x > 5.9)
    assert tracked.sum() >= 3
    untracked = identify(WALLS, CONNECTED, SEEN, robot, PARAMS, view)
    assert any(np.allclose(d, DOOR, atol=0.05) for d in untracked.doors)
    out = identify(WALLS, CONNECTED, SEEN, robot, PARAMS, replace(view, tracked=tracked))
    assert "jambs" not in out.door_kind


def test_the_wall_running_on_past_the_local_maps_end_is_no_gap():
    """The local map's merged end lags the scan's (here by 0.4 m): the scan's points between
    them are the wall running on, and the gap starts at the last of them, not at the end."""
    walls = np.array([LOWER, [-1.0, 2.0, 4.6, 2.0]])
    out = identify(walls, CONNECTED, SEEN, ROBOT, PARAMS, laser_view([LOWER, NEAR, FAR, *ROOM], ROBOT, 0.0))
    jambs = [d for d, k in zip(out.doors, out.door_kind, strict=True) if k == "jambs"]
    assert len(jambs) == 1
    assert 4.7 < jambs[0][0] <= 5.0 and np.allclose(jambs[0][1:], DOOR[1:], atol=0.05)


def test_a_long_wall_whose_far_end_turns_into_a_glimpse_is_still_a_lone_jamb():
    """A corridor's wall 3 m long whose far end turns at a convex corner into a side seen in
    part (the shape of a block's front: no T-opening's jamb) is still a lone jamb when nothing
    faces its end, and the scan's points in its line past the gap make the doorway a door."""
    side = [2.0, 2.0, 2.0, 2.3]
    walls = np.array([LOWER, [2.0, 2.0, 5.0, 2.0], side])
    connected = np.array([[-1, -1], [2, -1], [1, -1]], dtype=np.int64)
    seen = np.array([[False, False], [True, True], [True, False]])
    out = identify(walls, connected, seen, ROBOT, PARAMS, laser_view([LOWER, NEAR, FAR, side, *ROOM], ROBOT, 0.0))
    assert out.endpoint_property[1].tolist() == [CONVEX, CONVEX]
    jambs = [d for d, k in zip(out.doors, out.door_kind, strict=True) if k == "jambs"]
    assert len(jambs) == 1 and np.allclose(jambs[0], DOOR, atol=0.05)
