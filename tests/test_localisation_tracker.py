"""Tracking in the global map: convergence from the prior, drift, the lost flag, kidnapping,
a wrong map and bad scans. Scans come from the map's geometry (tests/localisation_scans.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from localisation_scans import scan_from_segments

from pico_studio.core.config import Config, with_value
from pico_studio.core.geometry import compose, relative, wrap_angle
from pico_studio.core.localisation import Localiser
from pico_studio.json_map import load_json_map


def _err(est, true) -> tuple[float, float]:
    return math.hypot(est[0] - true[0], est[1] - true[1]), abs(float(wrap_angle(est[2] - true[2])))


@pytest.fixture
def restaurant(maps_dir):
    return load_json_map(maps_dir / "restaurant_2024.json")


@pytest.fixture
def hospital(maps_dir):
    return load_json_map(maps_dir / "hospital_2019.json")


def _route(start, end, heading, steps):
    return [(start[0] + (end[0] - start[0]) * k / (steps - 1),
             start[1] + (end[1] - start[1]) * k / (steps - 1), heading) for k in range(steps)]


def _drifting_odometry(truth, gain=1.03, turn_gain=1.02, start=(4.0, -1.0, 2.0)):
    """Odometry that starts anywhere and integrates the true increments with gain errors."""
    odom = [start]
    for prev, cur in zip(truth, truth[1:], strict=False):
        d = relative(prev, cur)
        odom.append(compose(odom[-1], (d[0] * gain, d[1] * gain, d[2] * turn_gain)))
    return odom


def test_converges_from_start_area_with_unknown_heading(restaurant):
    cfg = Config()
    loc = Localiser(cfg.localisation, restaurant)
    assert loc.lmap.prior.origin == "start_area" and not loc.lmap.prior.heading_known
    true = (1.3, 0.9, 2.4)  # inside the 1 x 1 m start area, heading far from 0
    rng = np.random.default_rng(1)
    for _ in range(5):
        r = loc.step(scan_from_segments(loc.lmap.field.segments, true, rng), (0.0, 0.0, 0.0))
    assert r.pose is not None and not r.lost
    e_pos, e_head = _err(r.pose, true)
    assert e_pos < 0.03 and e_head < math.radians(1.5)
    assert r.quality > 0.9


def test_tracks_under_drifting_odometry(hospital):
    cfg = Config()
    truth = _route((3.5, 0.6), (3.5, 5.6), math.pi / 2, 120) + _route((3.5, 5.6), (3.5, 5.6), math.pi, 30)
    truth[-30:] = [(3.5, 5.6, float(wrap_angle(math.pi / 2 + k * 0.05))) for k in range(30)]
    odom = _drifting_odometry(truth)
    loc = Localiser(cfg.localisation, hospital, initial_pose=(3.6, 0.5, 1.5))
    rng = np.random.default_rng(2)
    errors = []
    for t, o in zip(truth, odom, strict=True):
        r = loc.step(scan_from_segments(loc.lmap.field.segments, t, rng), o)
        assert r.pose is not None
        errors.append(_err(r.pose, t))
    e = np.array(errors[5:])
    assert np.median(e[:, 0]) < 0.03 and e[:, 0].max() < 0.1
    assert np.median(e[:, 1]) < math.radians(1.0)
    assert not loc.last.lost
    # odometry alone would be off by the 3 % gain over 5 m
    assert math.hypot(*np.subtract(odom[-1][:2], odom[0][:2])) > 5.1


def test_kidnapped_robot_is_flagged_lost_and_recovered(restaurant):
    cfg = Config()
    loc = Localiser(cfg.localisation, restaurant)
    rng = np.random.default_rng(3)
    true = (1.5, 0.8, 1.2)
    odom = (0.0, 0.0, 0.0)
    for _ in range(5):
        loc.step(scan_from_segments(loc.lmap.field.segments, true, rng), odom)
    assert not loc.last.lost
    kicked = compose(true, (0.5 * math.cos(0.7), 0.5 * math.sin(0.7), math.radians(20)))
    flags = []
    for _ in range(200):  # 10 s at 20 Hz; the odometry does not see the kick
        r = loc.step(scan_from_segments(loc.lmap.field.segments, kicked, rng), odom)
        flags.append(r.lost)
        if True in flags and not r.lost:
            break
    assert True in flags, "the kick was never flagged"
    assert not flags[-1], "not recovered within 10 s"
    e_pos, e_head = _err(loc.last.pose, kicked)
    assert e_pos < 0.03 and e_head < math.radians(1.5)


def test_wrong_map_stays_lost_and_never_raises(restaurant, hospital):
    cfg = with_value(Config(), "localisation.search.max_cells", 100000)
    loc = Localiser(cfg.localisation, hospital, initial_pose=(1.5, 0.7, 0.0))  # the wrong file
    rng = np.random.default_rng(4)
    segs = Localiser(cfg.localisation, restaurant).lmap.field.segments
    for _ in range(16):
        r = loc.step(scan_from_segments(segs, (1.5, 0.7, 1.0), rng), (0.0, 0.0, 0.0))
        assert r.lost
        assert r.quality < cfg.localisation.tracker.quality_found


def test_bad_scans_do_not_raise(restaurant):
    loc = Localiser(Config().localisation, restaurant)
    bad = [np.zeros((0, 2)), np.full((1000, 2), np.nan), np.full((10, 2), np.inf)]
    for points in bad:
        r = loc.step(points, (0.0, 0.0, 0.0))
        assert r.lost
    rng = np.random.default_rng(5)
    for _ in range(5):
        r = loc.step(scan_from_segments(loc.lmap.field.segments, (1.5, 0.7, 0.0), rng), (0.0, 0.0, 0.0))
    assert not r.lost
    r = loc.step(np.zeros((0, 2)), (0.1, 0.0, 0.0))  # a lost scan mid-run: dead reckoning
    assert r.pose is not None and abs(r.pose[0] - 1.6) < 0.02
