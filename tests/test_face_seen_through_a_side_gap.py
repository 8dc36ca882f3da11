"""A T-opening whose face is seen only through a gap beside its jamb is a door.

A partition ends 0.8 m short of the building's outer wall: a doorway (a T-opening). Beside
the partition's end, the room's top wall stops 0.8 m short of it, and looking up through that
gap the robot sees the outer wall only from where the gap's far corner stops hiding it, 0.16
m past the partition's line. That piece of face floats at both ends (the corner hides one, the
jamb the other) and says nothing of how far it runs: it is met on its line up to
`end_face_reach` past its floating end, unless the scan looks past that point. It was met only
within `door_occlusion` (0.1 m), and the doorway was a lone jamb (slanted worlds, cafes).
"""

from __future__ import annotations

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import box, laser_view

PARAMS = load_config(None).perception.identify
ROBOT, HEADING = (1.0, 5.6), 0.6  # in the room below, looking up and right
PARTITION = [3.0, 4.0, 3.0, 6.6]  # its end (3.0, 6.6) the doorway's jamb
TOP = [0.0, 6.6, 2.2, 6.6]  # the room's top wall, ending 0.8 m short of the partition
STUB = [2.2, 6.6, 2.2, 7.4]  # ...turning up there to the outer wall (out of view)
OUTER = [0.0, 7.4, 6.0, 7.4]  # the outer wall, the doorway's face


def _identify(face_piece: list[float], solid: list[list[float]] | None = None):
    walls = np.array([PARTITION, TOP, face_piece])
    seen = np.array([[False, True], [False, True], [False, False]])  # the face floats at both ends
    view = laser_view(np.array(solid or [PARTITION, TOP, STUB, OUTER]), ROBOT, HEADING)
    return identify(walls, np.full((3, 2), -1, dtype=np.int64), seen, ROBOT, PARAMS, view)


def _doorway(face_piece: list[float]) -> list[str]:
    """The kinds of the doors found in the doorway (3.0, 6.6)-(3.0, 7.4)."""
    out = _identify(face_piece)
    doors = np.asarray(out.doors).reshape(-1, 4)
    return [k for d, k in zip(doors, out.door_kind, strict=True)
            if np.allclose(d[[0, 2]], 3.0, atol=0.05) and np.allclose(sorted(d[[1, 3]]), [6.6, 7.4], atol=0.05)]


def test_the_outer_wall_is_seen_from_past_the_partition_s_line():
    view = laser_view(np.array([PARTITION, TOP, STUB, OUTER]), ROBOT, HEADING)
    ang = view.angles + HEADING
    x = ROBOT[0] + view.ranges * np.cos(ang)
    y = ROBOT[1] + view.ranges * np.sin(ang)
    on_outer = view.valid & (np.abs(y - 7.4) < 1e-6)
    assert 3.12 < x[on_outer].min() < 3.2  # 0.12-0.2 m past the partition's line x = 3


def test_the_doorway_is_a_door():
    assert _doorway([3.16, 7.4, 4.6, 7.4]) == ["end_face"]


def test_a_piece_beyond_reach_makes_no_door():
    """Seen only from 0.7 m past the line on, more than end_face_reach: nothing says it runs on."""
    assert PARAMS.end_face_reach < 0.7
    assert _doorway([3.7, 7.4, 4.6, 7.4]) == []


def test_hidden_now_the_end_stays_a_lone_jamb_for_the_map():
    """Something standing in front hides the gap: no door, and the partition's end stays a lone
    jamb (a possible door of kind "jamb", from the end along the partition), which the combined
    map makes the map's opening there; a face met only past the glimpse's end takes nothing away."""
    person = box(2.0, 6.3, 0.2, 0.4).tolist()
    out = _identify([3.16, 7.4, 4.6, 7.4], [PARTITION, TOP, STUB, OUTER, *person])
    assert "end_face" not in out.door_kind
    jambs = [p for p, k in zip(np.asarray(out.possible_doors).reshape(-1, 4), out.possible_door_kind, strict=True)
             if k == "jamb"]
    assert any(np.allclose(p[:2], [3.0, 6.6]) and p[3] > 6.6 for p in jambs)


def test_found_the_door_leaves_no_lone_jamb_beside_it():
    """A narrower doorway (0.6 m), the top wall stopping 0.6 m short: the face seen from 0.24 m
    past the line. The lone jamb from the same end (its middle 0.35 m from the door's) goes."""
    top, stub, outer = [0.0, 6.6, 2.4, 6.6], [2.4, 6.6, 2.4, 7.2], [0.0, 7.2, 6.0, 7.2]
    walls = np.array([PARTITION, top, [3.24, 7.2, 4.6, 7.2]])
    seen = np.array([[False, True], [False, True], [False, False]])
    view = laser_view(np.array([PARTITION, top, stub, outer]), ROBOT, HEADING)
    out = identify(walls, np.full((3, 2), -1, dtype=np.int64), seen, ROBOT, PARAMS, view)
    doors = np.asarray(out.doors).reshape(-1, 4)
    assert any(k == "end_face" and np.allclose(d, [3.0, 6.6, 3.0, 7.2], atol=0.02)
               for d, k in zip(doors, out.door_kind, strict=True))
    assert "jamb" not in out.possible_door_kind
