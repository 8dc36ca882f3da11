"""A box standing a few cm off a wall beside a doorway's jamb.

hospital_2021: a 0.4 m box stands 0.21 m in front of the wall beside a doorway's jamb. Seen
from across the room the box's side facing the doorway runs on across the narrow gap into the
wall (one cluster at that angle), so the jamb's short piece of wall, the box's side and its
front make one connected group under a metre across, its ends seen past: a small object's
shape, and an object's walls make no jamb. But the group turns at a concave corner where the
box's side meets the wall: the laser looks into a corner, which no free-standing thing seen from
outside shows (its corners all turn convex; seen all round, a closed loop, it is a thing however
its far corners look through it), so the group is no object and the doorway keeps its jamb
(120 s wander through hospital_2021, `run --localise`: own door recall 0.780 -> 0.865).
"""

from __future__ import annotations

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.identify import identify, object_walls
from pico_studio.core.perception.identify_kernels import object_groups
from tests.clutter_scenes import laser_view

PARAMS = load_config(None).perception.identify
ROBOT = (0.3, -2.5)

# the doorway in a wall along y = 0 (the room below), its left jamb a thin wall's end at x = -0.55
LEFT = [-3.55, 0.0, -0.55, 0.0]
# right of it: the jamb's 0.4 m of wall, the box's side across the gap into it, the box's front
PIECE, SIDE, FRONT = [0.45, 0.0, 0.85, 0.0], [0.85, 0.0, 0.85, -0.6], [0.85, -0.6, 1.22, -0.6]


def _identify(walls: list[list[float]], conn: list[list[int]], seen: list[list[bool]]):
    w = np.array(walls, dtype=float)
    return identify(w, np.array(conn, dtype=np.int64), np.array(seen, dtype=bool), ROBOT, PARAMS,
                    laser_view(w, ROBOT, np.pi / 2))


def test_a_jambs_piece_fused_with_a_box_beside_it_keeps_the_doorway():
    out = _identify([LEFT, PIECE, SIDE, FRONT], [[-1, -1], [-1, 2], [1, 3], [2, -1]],
                    [[False, True], [True, True], [True, True], [True, True]])
    assert not out.object_wall.any()
    assert out.door_kind == ["jambs"]
    assert np.allclose(np.sort(out.doors[0][[0, 2]]), [-0.55, 0.45], atol=1e-6)
    assert np.allclose(out.doors[0][[1, 3]], 0.0, atol=1e-6)


def test_the_same_group_turning_only_at_convex_corners_is_an_object():
    """A box seen from outside (two faces, a convex corner) under a metre across is an object;
    the same walls turning into each other at a concave corner are not, nor a thing seen whole
    for the bays' rays (`object_groups`: one definition for both)."""
    box = np.array([[0.0, 0.0, 0.0, -0.6], [0.0, -0.6, 0.6, -0.6]])
    conn = np.array([[-1, 1], [0, -1]], dtype=np.int64)
    size, depth = PARAMS.object_max_size, PARAMS.object_min_depth
    convex = np.array([[2, 2], [2, 2]], dtype=np.int64)
    assert object_walls(box, conn, convex, size, depth).tolist() == [True, True]
    into_a_corner = np.array([[2, 3], [3, 2]], dtype=np.int64)
    assert object_walls(box, conn, into_a_corner, size, depth).tolist() == [False, False]
    assert object_groups(box, conn, convex, size, 0, 3)[1].tolist() == [True, True]
    assert object_groups(box, conn, into_a_corner, size, 0, 3)[1].tolist() == [False, False]


def test_a_box_seen_all_round_is_an_object_though_its_far_corner_looks_concave():
    """A closed loop (every end joined: the box seen all round over a drive) is a thing however
    its corners look from here: its far corner, seen through the box, comes out concave."""
    sides = np.array([[0.0, 0.0, 0.4, 0.0], [0.4, 0.0, 0.4, 0.4], [0.4, 0.4, 0.0, 0.4], [0.0, 0.4, 0.0, 0.0]])
    conn = np.array([[3, 1], [0, 2], [1, 3], [2, 0]], dtype=np.int64)
    far_concave = np.array([[2, 2], [2, 3], [3, 2], [2, 2]], dtype=np.int64)
    size, depth = PARAMS.object_max_size, PARAMS.object_min_depth
    assert object_walls(sides, conn, far_concave, size, depth).all()
