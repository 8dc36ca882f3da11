"""A jamb frames one door. A thick partition (x 4.05-4.3) with a doorway in its own line (y
1.15-2.2) has its lower piece's end as that doorway's jamb; a table standing by the room's wall,
its front (y 0.95) pointing at that end from 0.7 m away, made a second "door" from the table's
corner to the same end (suite:171: 9 of 50 poses). The end is the doorway's: a gap leaving it
in another direction than the doorway it frames is refused — from its own corner or from its
cap's far corner, between jambs or as a bay. With no doorway in the partition's line the end
frames nothing yet, and the rule is silent; two doorways meeting at one corner, the walls on
one grid, are both doors."""

from __future__ import annotations

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify
from tests.clutter_scenes import has_gap, laser_view

PARAMS = load_config(None).perception.identify
# the room's wall (y 0), the table (x 1.75-3.35, y 0.2-0.95), the partition (x 4.05-4.3) from
# the wall up to its end at y 1.15, its doorway to y 2.2, its upper piece on to y 4
TABLE = [[1.75, 0.2, 3.35, 0.2], [3.35, 0.2, 3.35, 0.95], [3.35, 0.95, 1.75, 0.95], [1.75, 0.95, 1.75, 0.2]]
PARTITION = [[4.05, 0.0, 4.05, 1.15], [4.05, 1.15, 4.3, 1.15], [4.3, 1.15, 4.3, 0.0],
             [4.05, 4.0, 4.05, 2.2], [4.05, 2.2, 4.3, 2.2], [4.3, 2.2, 4.3, 4.0]]
ROOM = [[-1.0, 0.0, 8.0, 0.0], [-1.0, 4.0, 8.0, 4.0]]
DOORWAY = [4.05, 1.15, 4.05, 2.2]
TABLE_GAP = [3.33, 0.95, 4.05, 1.15]


def _local_map(upper: bool, robot_left: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The table's front (its far end floating), the partition's lower piece with its cap (both
    its corners seen; from the right its right face), the upper piece's end when `upper`."""
    walls = [[1.95, 0.95, 3.33, 0.95]]
    connected = [[-1, -1]]
    seen = [[False, True]]
    if robot_left:  # the lower piece's left face, its cap seen on to the far corner
        walls += [[4.06, 0.12, 4.05, 1.15], [4.05, 1.15, 4.3, 1.15]]
    else:  # the right face, the cap seen back to the left face's corner
        walls += [[4.3, 0.12, 4.3, 1.15], [4.3, 1.15, 4.05, 1.15]]
    connected += [[-1, 2], [1, -1]]
    seen += [[False, False], [False, True]]
    if upper:
        x = 4.05 if robot_left else 4.3
        walls.append([x, 3.4, x, 2.2])
        connected.append([-1, -1])
        seen.append([False, True])
    return np.array(walls, dtype=float), np.array(connected, dtype=np.int64), np.array(seen, dtype=bool)


def _has(doors: np.ndarray, gap: list[float]) -> bool:
    return has_gap(doors, gap, 0.08)


def _view(robot: tuple[float, float], heading: float) -> object:
    return laser_view(TABLE + PARTITION + ROOM, robot, heading)


def test_the_partitions_end_frames_its_doorway_not_a_gap_to_the_table():
    robot = (2.69, 2.42)
    walls, connected, seen = _local_map(upper=True, robot_left=True)
    out = identify(walls, connected, seen, robot, PARAMS, _view(robot, 0.34))
    assert _has(out.doors, DOORWAY)
    assert not _has(out.doors, TABLE_GAP)


def test_nor_from_its_caps_far_corner():
    # from the partition's right the doorway's jamb is the right face's end; the cap's far corner
    # (x 4.05) is the same jamb, pointed at by the table's front
    robot = (4.79, 1.80)
    walls, connected, seen = _local_map(upper=True, robot_left=False)
    out = identify(walls, connected, seen, robot, PARAMS, _view(robot, 2.52))
    assert _has(out.doors, [4.3, 1.15, 4.3, 2.2])
    assert not _has(out.doors, TABLE_GAP)


def test_with_no_doorway_in_its_line_the_rule_is_silent():
    # the upper piece unseen: nothing claims the end, the gap is judged by the jamb rules alone
    # (here a door: the table's front and the end look like a doorway in one wall)
    robot = (2.69, 2.42)
    walls, connected, seen = _local_map(upper=False, robot_left=True)
    out = identify(walls, connected, seen, robot, PARAMS, _view(robot, 0.34))
    assert _has(out.doors, TABLE_GAP)


# two doorways meeting at one corner (hospital_2021's rooms): the bottom wall's doorway x -6.0 to
# -4.9 and, at its right jamb, the doorway down the room's right side from the side wall's end
# (y -4.1): the same corner frames both, the walls on one grid
CORNER_SOLID = [[-7.0, -5.05, -6.0, -5.05], [-4.9, -5.05, -3.0, -5.05], [-4.9, -1.5, -4.9, -4.1],
                [-7.0, -1.5, -7.0, -5.05], [-7.0, -1.5, -3.0, -1.5], [-8.0, -6.5, -2.0, -6.5],
                [-3.0, -1.5, -3.0, -5.05]]


def test_two_doorways_meeting_at_one_corner_on_one_grid_are_both_doors():
    robot = (-5.5, -2.5)
    walls = np.array([[-6.8, -5.05, -6.0, -5.05], [-4.9, -5.05, -4.6, -5.05], [-4.9, -1.8, -4.9, -4.1]])
    connected = np.full((3, 2), -1, dtype=np.int64)
    seen = np.array([[False, True], [True, False], [False, True]])
    out = identify(walls, connected, seen, robot, PARAMS, laser_view(CORNER_SOLID, robot, -1.0))
    assert _has(out.doors, [-6.0, -5.05, -4.9, -5.05])
    assert _has(out.doors, [-4.9, -4.1, -4.9, -5.05])


def test_a_bay_leaving_a_doorways_jamb_is_no_door_either():
    # suite:901's run (96 frames): from the partition's right (its faces x 7.99 / 8.18, its doorway y
    # 0.68-1.4) the jamb rules refuse the table's corner (its side seen, 0.82 m: a block's corner),
    # but as a bay it was seen through to the room beyond: a door from the doorway's jamb, passing
    # over the jamb's own cap to the table
    solid = [[5.0, 0.97, 6.98, 0.97], [6.98, 0.97, 6.98, 0.1], [0.0, 0.1, 12.0, 0.1],
             [7.99, 0.1, 7.99, 0.68], [7.99, 0.68, 8.18, 0.68], [8.18, 0.68, 8.18, 0.1],
             [7.99, 4.0, 7.99, 1.4], [7.99, 1.4, 8.18, 1.4], [8.18, 1.4, 8.18, 4.0], [0.0, 4.0, 12.0, 4.0]]
    walls = np.array([[6.98, 0.1, 7.97, 0.11], [8.18, 0.1, 10.11, 0.1], [8.18, 0.68, 8.18, 0.1],
                      [7.99, 0.68, 8.18, 0.68], [8.17, 3.86, 8.18, 1.4], [6.98, 0.92, 6.98, 0.1],
                      [8.18, 1.4, 7.99, 1.4]])
    connected = np.array([[5, -1], [2, -1], [3, 1], [-1, 2], [-1, 6], [-1, 0], [4, -1]], dtype=np.int64)
    seen = np.array([[False, False], [False, False], [False, False], [True, False], [False, False], [True, False],
                     [False, True]])
    robot = (9.32, 0.92)
    out = identify(walls, connected, seen, robot, PARAMS, laser_view(solid, robot, -2.93))
    assert _has(out.doors, [8.18, 0.68, 8.18, 1.4])
    for corner in ([8.18, 0.68], [7.99, 0.68]):
        assert not _has(out.doors, corner + [6.98, 0.92])
