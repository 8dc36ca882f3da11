"""The perceptor as a whole: pure, robust to bad input, serialisable, every segmenter, rooms, motion."""

from __future__ import annotations

import json
import math

import numpy as np
from perception_scenes import DOOR_ROOM, SQUARE, odom, poly, scan_of

from pico_studio.config import Config, with_value
from pico_studio.core.io import LaserData, OdometryData
from pico_studio.core.perception import STAGES, Perceptor, PerceptorState, perceive
from pico_studio.core.perception.laser_motion import fit_rigid, laser_motion
from pico_studio.core.perception.rooms import room_content

CFG = Config()
P = CFG.perception


def _laser(r, **kw):
    fields = {"range_min": 0.01, "range_max": 10.0, "angle_min": -2.0, "angle_max": 2.0,
              "angle_increment": 4 / 999, "timestamp": 1.0}
    fields.update(kw)
    return LaserData(ranges=np.asarray(r, dtype=float), **fields)


def test_bad_scans_give_valid_empty_models_with_a_warning():
    p = Perceptor(P)
    bad = [
        _laser([]),
        _laser(np.full(1000, np.nan)),
        _laser(np.full(1000, np.inf)),
        _laser(np.zeros(1000)),
        _laser(np.full(1000, 2.0), angle_increment=float("nan"), angle_max=float("nan")),
    ]
    for laser in bad:
        wm = p.step(laser, OdometryData(0, 0, 0, 1.0))
        assert wm.warnings, laser
        assert wm.current_map.shape == (0, 4)
        assert wm.local_map.walls.shape[1] == 4
        json.dumps(wm.to_dict())


def test_mismatched_angles_still_perceive_with_a_warning():
    good = scan_of(SQUARE, (0, 0, 0))
    bad = LaserData(good.range_min, good.range_max, good.angle_min, 1.0, good.angle_increment, 0.0, good.ranges)
    wm, _ = perceive(PerceptorState.initial(), bad, None, P)
    assert any("disagree" in w for w in wm.warnings)
    assert len(wm.current_map) >= 3


def test_odometry_jump_inside_the_loop_keeps_the_map():
    p = Perceptor(P)
    for k in range(5):
        p.step(scan_of(SQUARE, (0, 0, 0.02 * k), seed=k), odom((0, 0, 0.02 * k)))
    n = len(p.last.local_map.walls)
    wm = p.step(scan_of(SQUARE, (0, 0, 0.1)), odom((40.0, -3.0, 2.0)))
    assert any("jump" in w for w in wm.warnings)
    assert len(wm.local_map.walls) == n
    assert math.hypot(*wm.pose[:2]) < 0.01


def test_perceive_is_pure():
    state = PerceptorState.initial()
    laser = scan_of(SQUARE, (0.1, 0.2, 0.3), noise=0.01)
    before = laser.ranges.copy()
    wm1, s1 = perceive(state, laser, odom((0.1, 0.2, 0.3)), P)
    wm1b, s1b = perceive(state, laser, odom((0.1, 0.2, 0.3)), P)
    np.testing.assert_array_equal(laser.ranges, before)
    np.testing.assert_array_equal(wm1.current_map, wm1b.current_map)
    laser2 = scan_of(SQUARE, (0.1, 0.2, 0.35), noise=0.01, seed=3)
    wm2, _ = perceive(s1, laser2, odom((0.1, 0.2, 0.35)), P)
    wm2b, _ = perceive(s1, laser2, odom((0.1, 0.2, 0.35)), P)
    np.testing.assert_array_equal(wm2.local_map.walls, wm2b.local_map.walls)
    assert s1.local_map.step == 1  # the old state is untouched by the second step


def test_world_model_fields_and_timings():
    p = Perceptor(P)
    wm = p.step(scan_of(SQUARE, (0, 0, 0)), odom((0, 0, 0)))
    assert set(STAGES) <= set(wm.timings_ms)
    assert wm.beam_valid.shape == (1000,) and wm.proximity.shape == (1000,)
    assert wm.points.shape[1] == 2
    d = wm.to_dict()
    for key in ("pose", "zero_pose", "points", "current_map", "local_map", "corners", "corner_convex",
                "doors", "possible_doors", "possible_door_kind", "entrance", "timings_ms", "warnings"):
        assert key in d
    json.dumps(d)


def test_every_segmenter_finds_the_door():
    for name in ("split_merge", "angle", "ransac"):
        params = with_value(CFG, "perception.scan.segmenter", name).perception
        p = Perceptor(params)
        for k in range(10):
            pose = (0.0, 0.0, 1.3 + 0.03 * k)
            wm = p.step(scan_of(DOOR_ROOM, pose, noise=0.01, seed=k), odom(pose))
        assert len(wm.doors) == 1, name


def test_no_odometry_uses_laser_motion():
    p = Perceptor(P)
    box = poly((1.0, -0.5), (1.6, -0.5), (1.6, 0.5), (1.0, 0.5))
    walls = np.vstack([SQUARE * 1.5, box])
    for k in range(10):
        wm = p.step(scan_of(walls, (-0.02 * k, 0.0, 0.0), noise=0.002, seed=k), None)
    assert wm.laser_motion is not None
    assert abs(wm.pose[0] + 0.18) < 0.03 and abs(wm.pose[1]) < 0.03


def test_laser_motion_recovers_a_rigid_motion():
    prev = np.array([[1.0, 0.5], [2.0, -1.0], [0.5, 2.0], [3.0, 1.0]])
    motion = (0.1, -0.05, 0.08)  # the new pose in the old frame
    c, s = math.cos(motion[2]), math.sin(motion[2])
    # the same corners seen from the new pose: q = R^T (p - t)
    cur = (prev - np.array(motion[:2])) @ np.array([[c, -s], [s, c]])
    est, n = laser_motion(prev, cur, None, P.laser_motion)
    assert n == 4
    np.testing.assert_allclose(est, motion, atol=1e-9)
    np.testing.assert_allclose(fit_rigid(prev[:1], cur[:1], 0.08)[:2], motion[:2], atol=1e-9)


def test_room_jump_and_content():
    params = P.rooms
    angles = np.linspace(-2, 2, 1000)
    ranges = np.full(1000, 1.0)
    # two objects in the side view: two bumps of nearer ranges
    side = np.flatnonzero(np.abs(angles - params.side_angle) < 0.4)
    ranges[side[10:30]] = 0.7
    ranges[side[60:80]] = 0.6
    edges, objects = room_content(ranges, angles, np.ones(1000, dtype=bool), params)
    assert edges == 4 and objects == 2
    p = Perceptor(P)
    corridor = np.array([[-5, -0.5, 5, -0.5], [-5, 1.0, 5, 1.0]])
    room = np.array([[-5, -1.7, 5, -1.7], [-5, 1.0, 5, 1.0]])
    p.step(scan_of(corridor, (0, 0, 0)), odom((0, 0, 0)))
    wm = p.step(scan_of(room, (0, 0, 0)), odom((0.05, 0, 0)))
    assert wm.room["room"] and abs(wm.room["jump"] - 1.2) < 0.05
