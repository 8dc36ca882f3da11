"""A corner is judged from where its walls were seen: a room's corner the robot has left
behind a wall stays concave. Judged from where the robot stands now, the corner of the room it
came from points at it from behind the partition — convex — and a convex corner is a door's
jamb (suite:5's run: a table's corner in the next room read as a T-opening's jamb for 66 frames).
And a wall seen through another's line ends at an outer corner, not a T: two cabinets' fronts
fused across the slot between them (hall:900's run, convexity 0.897)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception import Perceptor
from pico_studio.core.perception.junction_kernels import junctions
from pico_studio.core.world_model import CONCAVE, CONVEX, FLOATING, WorldModel
from tests.clutter_scenes import cast, odometry

PARAMS = load_config(None).perception
# room A (x 0-4, y 0-4) and room B (x 4.2-8, y 0.5-4.5) beside it, a partition 0.2 m thick
# between them with a doorway at y 2.8-3.8; room A's corner (4, 0): its floor wall and the
# partition's face
WALLS = np.array([
    [0.0, 0.0, 4.0, 0.0], [0.0, 0.0, 0.0, 4.0], [0.0, 4.0, 4.0, 4.0],  # room A
    [4.0, 0.0, 4.0, 2.8], [4.0, 3.8, 4.0, 4.0],  # the partition's face in room A
    [4.0, 2.8, 4.2, 2.8], [4.0, 3.8, 4.2, 3.8], [4.0, 0.0, 4.2, 0.5],  # the doorway's jambs, the foot
    [4.2, 0.5, 4.2, 2.8], [4.2, 3.8, 4.2, 4.5],  # its face in room B
    [4.2, 0.5, 8.0, 0.5], [8.0, 0.5, 8.0, 4.5], [4.2, 4.5, 8.0, 4.5], [4.0, 4.0, 4.2, 4.5],  # room B
])
CORNER = (4.0, 0.0)
IN_A, IN_B = (2.0, 1.5, 0.0), (6.5, 1.5, 0.0)


def _corner(wm: WorldModel, first: tuple[float, float, float]) -> bool | None:
    """The convexity of the local map's corner at CORNER (zero frame: the robot's first pose),
    None when there is none."""
    x, y, a = first
    c, s = math.cos(a), math.sin(a)
    for (px, py), convex in zip(np.asarray(wm.corners, float).reshape(-1, 2), wm.corner_convex, strict=True):
        if math.hypot(x + c * px - s * py - CORNER[0], y + s * px + c * py - CORNER[1]) < 0.1:
            return bool(convex)
    return None


def _run(poses: list[tuple[tuple[float, float, float], float]]) -> WorldModel:
    p = Perceptor(PARAMS)
    wm = None
    for pose, t in poses:
        wm = p.step(dataclasses.replace(cast(WALLS, pose), timestamp=t), odometry(pose, t))
    assert wm is not None
    return wm


def _walk(a: tuple[float, float, float], b: tuple[float, float, float], t0: float, n: int) -> list:
    """n poses from a to b, 20 Hz from t0 (the heading turned at once)."""
    return [((a[0] + (b[0] - a[0]) * k / n, a[1] + (b[1] - a[1]) * k / n, b[2]), t0 + k * 0.05)
            for k in range(1, n + 1)]


def test_a_room_corner_seen_from_inside_is_concave():
    wm = _run([(IN_A, k * 0.05) for k in range(10)])
    assert _corner(wm, IN_A) is False


def test_the_corner_of_the_room_left_behind_stays_concave():
    # ten scans in room A, then through the doorway into room B: the corner is hidden there
    door_a, door_b = (3.5, 3.3, 0.0), (4.7, 3.3, 0.0)
    poses = [(IN_A, k * 0.05) for k in range(10)]
    poses += _walk(IN_A, door_a, 0.5, 30) + _walk(door_a, door_b, 2.0, 20) + _walk(door_b, IN_B, 3.0, 30)
    poses += [(IN_B, 4.5 + k * 0.05) for k in range(10)]
    wm = _run(poses)
    assert _corner(wm, IN_A) is False  # judged from room B it would point at the robot: convex


def test_junctions_judge_each_wall_from_where_it_was_seen():
    # room A's corner: the floor wall last seen through the doorway from room B's side of the
    # partition's line (4.64, 3.3), still above the floor; the partition's face from inside
    # (3.92, 3.3): each far end lies on the other wall's free side, concave (the robot, judged
    # from either place alone, would stand outside the wedge at (4.64, 3.3): convex)
    walls = np.array([[4.0, 0.0, 0.0, 0.0], [4.0, 0.0, 4.0, 2.8]])
    connected = np.array([[1, -1], [0, -1]], dtype=np.int64)
    seen = np.zeros((2, 2), dtype=bool)
    eyes = np.array([[4.64, 3.3], [3.92, 3.3]])
    prop = junctions(walls, connected, seen, eyes, FLOATING, CONVEX, CONCAVE)[0]
    assert prop[0, 0] == CONCAVE and prop[1, 0] == CONCAVE
    assert junctions(walls, connected, seen, eyes[[0, 0]], FLOATING, CONVEX, CONCAVE)[0][0, 0] == CONVEX
    # a box's corner (the box x 0-4, y -2.8-0): its top seen from above, its side from the right
    box_walls = np.array([[4.0, 0.0, 0.0, 0.0], [4.0, 0.0, 4.0, -2.8]])
    eyes = np.array([[2.0, 1.0], [5.0, -1.0]])
    assert junctions(box_walls, connected, seen, eyes, FLOATING, CONVEX, CONCAVE)[0][0, 0] == CONVEX


# two cabinets against the wall x = 0.2, their fronts on x = 0.9: y 2.6-3.8 and 1.2-2.45, a slot
# 0.15 m between them; the lower one's top face y = 2.45 (and the upper one's bottom face) seen
# through the slot from the room (x > 0.9), the fronts later seen at a graze as one wall
FRONT = [0.9, 3.8, 0.9, 1.2]
TOP_FACE = [0.9, 2.45, 0.2, 2.45]
T_JOINED = np.array([[-1, -1], [0, -1]], dtype=np.int64)  # the face's end on the front's inside


def test_a_face_seen_through_a_wall_ends_at_an_outer_corner():
    walls = np.array([FRONT, TOP_FACE])
    seen = np.zeros((2, 2), dtype=bool)
    eyes = np.array([[1.3, 4.3], [3.2, 2.3]])  # the front from above, at a graze; the face through the slot
    prop = junctions(walls, T_JOINED, seen, eyes, FLOATING, CONVEX, CONCAVE)[0]
    assert prop[1, 0] == CONVEX  # the lower cabinet's corner, as the truth has it


def test_a_t_behind_a_thin_wall_seen_from_its_other_side_stays_concave():
    # a thin wall x = 0.9 seen last from the room x > 0.9, a partition joined to its back seen
    # from the room behind (x < 0.9): a T on the far side, concave
    walls = np.array([FRONT, TOP_FACE])
    seen = np.zeros((2, 2), dtype=bool)
    eyes = np.array([[1.3, 3.0], [0.5, 3.0]])
    assert junctions(walls, T_JOINED, seen, eyes, FLOATING, CONVEX, CONCAVE)[0][1, 0] == CONCAVE
    # ...and a T on the robot's side seen from there is concave
    stem = np.array([FRONT, [0.9, 2.45, 1.6, 2.45]])
    eyes = np.array([[1.3, 3.0], [1.3, 3.0]])
    assert junctions(stem, T_JOINED, seen, eyes, FLOATING, CONVEX, CONCAVE)[0][1, 0] == CONCAVE
