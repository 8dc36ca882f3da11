"""Room finder pieces on hand-built ranges: edge counting with suppression and ceil(edges/2)."""

from __future__ import annotations

import numpy as np

from pico_studio.core.behaviours.room_finder import count_edges, count_objects


def test_one_box_is_two_edges_one_object():
    r = np.full(200, 1.4)
    r[80:120] = 0.8
    assert count_objects(r, 0.1, 5) == (1, 2)


def test_two_feet_are_two_objects_and_repeated_jumps_of_one_edge_count_once():
    r = np.full(200, 1.4)
    r[60:80] = 0.77
    r[120:140] = 0.77
    r[80] = 1.1  # an edge smeared over two beams: two jumps, within the suppression window
    assert count_edges(r, 0.1, 5) == 4
    assert count_objects(r, 0.1, 5)[0] == 2
    assert count_edges(r, 0.1, 0) == 5


def test_object_against_the_side_shows_one_edge_and_still_counts():
    r = np.full(200, 1.4)
    r[:50] = 0.9
    assert count_objects(r, 0.1, 5) == (1, 1)


def test_empty_room_and_noise_below_the_jump_count_nothing():
    rng = np.random.default_rng(0)
    r = 1.4 + rng.uniform(-0.01, 0.01, 200)
    assert count_objects(r, 0.1, 5) == (0, 0)


def test_nearest_wall_foot_skips_a_jamb_corner_for_the_wall_hit_square_on():
    from pico_studio.core.behaviours.room_finder import nearest_wall_beam
    from pico_studio.sim.raycast import Fan

    # facing a side room's opening (y -0.5..0.5 in the wall x = 1): its jamb corners are the
    # nearest points; the nearest wall hit square on is the side wall y = -1.5
    segs = np.array([[1, -3, 1, -0.5], [1, 0.5, 1, 3], [1, -0.5, 2, -0.5], [2, -0.5, 2, 0.5],
                     [2, 0.5, 1, 0.5], [-3, -1.5, 1, -1.5]], dtype=float)
    fan = Fan(-2.0, 4.0 / 999, 1000)
    r = fan.cast(segs)
    angles = -2.0 + np.arange(1000) * 4.0 / 999
    assert abs(abs(angles[np.argmin(r)]) - np.arctan2(0.5, 1)) < 0.01  # plain minimum: a jamb
    i = nearest_wall_beam(angles, r, 2.0)
    assert i is not None and abs(angles[i] + np.pi / 2) < 0.05
