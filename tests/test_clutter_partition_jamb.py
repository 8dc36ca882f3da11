"""A thick partition's end meeting a corridor's wall between two doorways is a door frame, seen
in part: its cap lies in the corridor wall's line and its face, seen through the doorway, runs
up only a few dm past the far jamb's thickness (slant:900's run: a doorway missed for 199
frames, a possible "bay" only). A lone short wall across the line with no cap (a box's or a
person's side) is still no jamb, nor one whose "cap" is as wide as an object is deep
(`object_min_depth`): a small box's corner seen through a doorway (hall:310)."""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import laser_view

PARAMS = load_config(None).perception.identify
# the corridor's wall (its face y = 0, 0.2 m thick) with two doorways, x 1.0-1.8 and 2.0-2.9, the
# partition (x 1.8-2.0) between them running up into the rooms above
SOLID = [
    [-3.0, 0.0, 1.0, 0.0], [1.0, 0.0, 1.0, 0.2], [1.0, 0.2, -3.0, 0.2],
    [1.8, 0.0, 2.0, 0.0], [1.8, 0.0, 1.8, 3.0], [2.0, 0.0, 2.0, 3.0],
    [2.9, 0.0, 9.0, 0.0], [2.9, 0.0, 2.9, 0.2], [2.9, 0.2, 9.0, 0.2],
    [-3.0, 3.0, 9.0, 3.0],
]
ROBOT, HEADING = (7.0, -0.8), math.pi
DOORWAY = [2.0, 0.0, 2.9, 0.0]


def _local_map(face: list[float] | None, cap_end: float = 1.8) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The local map seen from ROBOT: the corridor wall's pieces, the partition's cap and the
    start of its face (its far end floating, hidden past the far jamb's thickness), or no face."""
    # (the corner 1 cm off the corridor wall's line, as merged: the ray along that line from the
    # far jamb passes under it, meeting no face, no T-opening)
    walls = [[-3.0, 0.0, 1.0, 0.0], [2.0, 0.01, cap_end, 0.0], [9.0, 0.0, 2.9, 0.0]]
    connected = [[-1, -1], [-1, -1], [-1, -1]]
    seen = [[False, True], [False, True], [False, True]]
    if face is not None:
        walls.append(face)
        connected[1][0] = 3
        connected.append([1, -1])
        seen.append([False, False])
    return np.array(walls, dtype=float), np.array(connected, dtype=np.int64), np.array(seen, dtype=bool)


def _is_the_doorway(doors: np.ndarray) -> bool:
    return any(np.allclose(sorted([d[0], d[2]]), [2.0, 2.9], atol=0.05) and abs(d[1]) < 0.05 and abs(d[3]) < 0.05
               for d in np.asarray(doors, float).reshape(-1, 4))


def test_a_partition_seen_in_part_frames_the_doorway():
    walls, connected, seen = _local_map([2.0, 0.01, 1.9, 0.42])
    out = identify(walls, connected, seen, ROBOT, PARAMS, laser_view(SOLID, ROBOT, HEADING))
    assert _is_the_doorway(out.doors)


def test_a_lone_short_side_across_the_line_is_no_jamb():
    # the same side seen alone (no cap joined to it: a box's or a person's side) frames nothing
    walls, connected, seen = _local_map(None)
    walls = np.vstack([walls[[0, 2]], [[2.0, 0.01, 1.9, 0.42]]])
    connected = np.full((3, 2), -1, dtype=np.int64)
    seen = np.array([[False, True], [False, True], [True, False]])
    out = identify(walls, connected, seen, ROBOT, PARAMS, laser_view(SOLID, ROBOT, HEADING))
    assert not _is_the_doorway(out.doors)


def test_a_box_corner_seen_in_part_is_no_frame():
    # a "cap" 0.35 m long is a box's top, its side seen in part: no door frame
    walls, connected, seen = _local_map([2.0, 0.01, 1.9, 0.42], cap_end=1.65)
    out = identify(walls, connected, seen, ROBOT, PARAMS, laser_view(SOLID, ROBOT, HEADING))
    assert not _is_the_doorway(out.doors)
