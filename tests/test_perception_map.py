"""Merge (local map) and identify (corners, doors) on hand-built scenes, and their stability."""

from __future__ import annotations

import math

import numpy as np
from perception_scenes import DOOR_ROOM, HALLWAY, SQUARE, odom, poly, scan_of

from pico_studio.config import Config
from pico_studio.core.geometry import point_segment_distance, segment_lengths
from pico_studio.core.perception import Perceptor
from pico_studio.core.world_model import CONCAVE

P = Config().perception


def _drive(walls, poses, params=P, noise=0.01):
    p = Perceptor(params)
    out = []
    for k, pose in enumerate(poses):
        out.append(p.step(scan_of(walls, pose, noise=noise, seed=k, t=0.05 * k), odom(pose, 0.05 * k)))
    return out


def _spin(x=0.3, y=-0.2, n=40, rate=0.08):
    return [(x, y, -0.5 + rate * k) for k in range(n)]


def _in_world(wm, pts):
    """Zero-frame points to the world frame (the first pose of the run is the zero pose)."""
    z = wm.zero_pose
    c, s = math.cos(z[2]), math.sin(z[2])
    return pts @ np.array([[c, s], [-s, c]]) + np.array(z[:2])


def test_square_room_local_map_is_the_room():
    wm = _drive(SQUARE, _spin())[-1]
    walls = wm.local_map.walls
    assert len(walls) == 4
    world = _in_world(wm, walls.reshape(-1, 2)).reshape(-1, 4)
    assert point_segment_distance(world.reshape(-1, 2), SQUARE).min(axis=1).max() < 0.05
    assert segment_lengths(world).sum() > 14.0
    # four concave corners at the room's corners
    assert len(wm.corners) == 4 and not wm.corner_convex.any()
    corners = _in_world(wm, wm.corners)
    for c in ([-2, -2], [2, -2], [2, 2], [-2, 2]):
        assert np.hypot(*(corners - c).T).min() < 0.05
    assert (wm.local_map.endpoint_property == CONCAVE).all()
    assert wm.doors.shape == (0, 4)


def test_door_in_a_wall_is_found_with_convex_jambs():
    poses = [(0.0, 0.0, 1.2 + 0.02 * k) for k in range(20)]
    wm = _drive(DOOR_ROOM, poses)[-1]
    assert len(wm.doors) == 1
    door = _in_world(wm, wm.doors.reshape(-1, 2))
    np.testing.assert_allclose(sorted(door[:, 0]), [-0.45, 0.45], atol=0.05)
    np.testing.assert_allclose(door[:, 1], [2.0, 2.0], atol=0.05)
    jambs = _in_world(wm, wm.corners[wm.corner_convex])
    assert len(jambs) == 2


def test_convex_corner_of_a_box_seen_from_outside():
    box = poly((1.0, -0.5), (2.0, -0.5), (2.0, 0.5), (1.0, 0.5))
    walls = np.vstack([box, SQUARE * 2])
    wm = _drive(walls, [(-0.5, -1.5, 0.9 + 0.01 * k) for k in range(15)])[-1]
    corners = _in_world(wm, wm.corners)
    k = np.argmin(np.hypot(*(corners - [1.0, -0.5]).T))
    assert np.hypot(*(corners[k] - [1.0, -0.5])) < 0.06
    assert wm.corner_convex[k]


def test_loose_ends_give_possible_doors():
    # a 1 m door in a wall 1.5 m ahead, its jambs hidden behind a box: two loose ends
    walls = np.vstack([
        poly((-3, 1.5), (-0.5, 1.5), closed=False), poly((0.5, 1.5), (3, 1.5), closed=False),
        poly((-0.35, 0.9), (0.35, 0.9), (0.35, 1.0), (-0.35, 1.0)),
    ])
    wm = _drive(walls, [(0.0, 0.0, math.pi / 2)] * 5)[-1]
    assert len(wm.doors) == 0
    kinds = wm.possible_door_kind
    assert "loose_loose" in kinds
    door = wm.possible_doors[kinds.index("loose_loose")].reshape(2, 2)
    np.testing.assert_allclose(np.abs(door[:, 1]), [0.585, 0.585], atol=0.05)  # zero frame: x fwd


def test_hallway_entrance():
    wm = _drive(HALLWAY, [(0.0, 0.0, 0.0)] * 6)[-1]
    assert wm.entrance is not None
    angle, dist = wm.entrance
    assert wm.hallway
    assert abs(angle) < 0.1 and dist > 1.0


def test_room_entrance_is_the_gap():
    wm = _drive(DOOR_ROOM, [(0.0, -1.0, math.pi / 2)] * 6)[-1]
    angle, dist = wm.entrance
    assert abs(angle) < 0.1  # straight ahead
    assert dist == np.float64(dist) and abs(dist - 3.0) < 0.1


def test_local_map_is_stable_over_hundreds_of_scans():
    """Driving around a room with a box for 400 scans: bounded size, no flicker of walls."""
    box = poly((0.8, 0.6), (1.4, 0.6), (1.4, 1.2), (0.8, 1.2))
    walls = np.vstack([SQUARE, box])
    poses = []
    for k in range(400):
        t = 2 * math.pi * k / 200
        poses.append((-0.8 * math.cos(t), -0.8 * math.sin(t), t - math.pi / 2 + 0.6 * math.sin(3 * t)))
    wms = _drive(walls, poses)
    counts = np.array([len(w.local_map.walls) for w in wms])
    assert counts[100:].max() <= 12
    # the room's walls, once seen, stay: every late frame shows walls on all four sides
    late = wms[100:]
    for wm in late:
        world = _in_world(wm, wm.local_map.walls.reshape(-1, 2)).reshape(-1, 4)
        mid = (world[:, 0:2] + world[:, 2:4]) / 2
        for side in ([2, 0], [-2, 0], [0, 2], [0, -2]):
            d = np.abs((mid - side) @ np.array(side) / 2)
            assert (d < 0.05).any()
    # corners do not wander: the room's corners (-2, -2) and (2, -2) over the last 200 frames
    for corner in ([-2, -2], [2, -2]):
        track = []
        for wm in wms[200:]:
            c = _in_world(wm, wm.corners)
            track.append(c[np.argmin(np.hypot(*(c - corner).T))])
        assert np.hypot(*(np.array(track) - corner).T).max() < 0.03


def test_a_wall_unseen_for_forget_seconds_is_dropped_at_any_scan_rate():
    """The square's walls, seen for a second, then a scan of one short wall only: after more
    than `forget_seconds` the square is forgotten, within it kept, at 1 Hz as at 20 Hz."""
    from dataclasses import replace

    lone = poly((0.8, -0.3), (0.8, 0.3), closed=False)
    pose = (0.3, -0.2, 0.0)
    for rate in (1.0, 20.0):
        for later, forgotten in ((4.0, False), (7.0, True)):
            p = Perceptor(replace(P, merge=replace(P.merge, forget_seconds=5.0)))
            t = 0.0
            while t <= 1.0:
                p.step(scan_of(SQUARE, pose, t=t), odom(pose, t))
                t += 1.0 / rate
            wm = p.step(scan_of(lone, pose, t=1.0 + later), odom(pose, 1.0 + later))
            ends = _in_world(wm, wm.local_map.walls.reshape(-1, 2))
            far = np.hypot(*ends.T).max() if len(ends) else 0.0
            assert (far < 1.5) == forgotten, (rate, later, far)  # the square's walls reach 2 m out
