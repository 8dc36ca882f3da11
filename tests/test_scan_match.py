"""The scan-to-local-map pose correction (point-to-line ICP, scan_match.py): it holds the
pose on a real log, keeps a corridor's free direction at odometry, and leaves bad input to
odometry with quality 0."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pico_studio import jit
from pico_studio.config import load_config
from pico_studio.core.geometry import invert, transform_points
from pico_studio.core.io import LaserData, OdometryData
from pico_studio.core.perception import Perceptor
from pico_studio.core.perception import scan_match_kernels as kn
from pico_studio.core.perception.scan_match import _settings, match_scan
from tests.clutter_scenes import cast
from tests.recording_helpers import intel_agreement

PARAMS = load_config(None).perception
SM = PARAMS.scan_match
CORRIDOR = np.array([[-30, 0, 30, 0], [-30, 1.6, 30, 1.6]], dtype=float)
ROOM = np.array([[0, 0, 6, 0], [6, 0, 6, 4], [6, 4, 0, 4], [0, 4, 0, 0], [2, 0, 2, 1.5]], dtype=float)


def _cast(walls: np.ndarray, pose: tuple[float, float, float], n: int = 360) -> np.ndarray:
    """Ranges (n,) of beams all round from `pose` onto `walls` (beam i at -pi + 2 pi i / n);
    inf: no hit within 30 m."""
    return cast(walls, pose, n, max_range=30.0).ranges


def _points(walls: np.ndarray, pose: tuple[float, float, float], n: int = 360) -> np.ndarray:
    r = _cast(walls, pose, n)
    ang = np.linspace(-math.pi, math.pi, n, endpoint=False) + pose[2]
    hit = np.isfinite(r)
    world = np.column_stack([pose[0] + r[hit] * np.cos(ang[hit]), pose[1] + r[hit] * np.sin(ang[hit])])
    return transform_points(world, invert(pose))


def _laser(ranges: np.ndarray, angle_min: float, increment: float, stamp: float) -> LaserData:
    return LaserData(0.05, 30.0, angle_min, angle_min + increment * (len(ranges) - 1), increment, stamp,
                     np.asarray(ranges, dtype=float))


def test_corridor_cross_track_corrected_along_track_held_to_odometry():
    true = (0.0, 0.8, 0.05)
    odo = (0.4, 0.95, 0.0)  # 0.4 m along (unobservable), 0.15 m across, 0.05 rad off
    m = match_scan(_points(CORRIDOR, true), CORRIDOR, odo, (1.0, 0.0, 0.0), SM)
    assert m.accepted and m.observable == 2
    assert abs(m.pose[1] - true[1]) < 0.01 and abs(m.pose[2] - true[2]) < 0.005
    assert m.pose[0] == pytest.approx(odo[0], abs=1e-6)  # not slid along the corridor


def test_a_room_pins_every_direction():
    true = (3.0, 2.5, 0.4)
    m = match_scan(_points(ROOM, true), ROOM, (3.12, 2.4, 0.46), (0.8, 0.0, 0.3), SM)
    assert m.accepted and m.observable == 3 and m.quality > 0.95
    assert math.hypot(m.pose[0] - true[0], m.pose[1] - true[1]) < 0.005 and abs(m.pose[2] - true[2]) < 0.002


def test_implausible_correction_is_refused():
    """Odometry that claims to be good (a tiny step) while the walls say 0.5 m elsewhere: the
    correction is many sigmas off, so the pose stays odometry's."""
    true = (3.0, 2.5, 0.4)
    tight = dataclasses.replace(SM, max_sigmas=5.0)
    odo = (3.3, 2.1, 0.4)
    m = match_scan(_points(ROOM, true), ROOM, odo, (0.01, 0.0, 0.0), tight)
    assert not m.accepted and m.pose == odo


@pytest.mark.parametrize("points", [np.zeros((0, 2)), np.full((100, 2), np.nan)])
def test_bad_points_leave_the_odometry_pose_with_quality_zero(points):
    odo = (1.0, 2.0, 0.3)
    m = match_scan(points, ROOM, odo, (0.5, 0.0, 0.0), SM)
    assert not m.accepted and m.pose == odo and m.quality == 0.0


def test_bad_scan_in_the_perceptor_keeps_odometry_and_reports_quality_zero():
    p = Perceptor(PARAMS)
    angles = np.linspace(-math.pi, math.pi, 360, endpoint=False)
    for i in range(3):
        pose = (0.2 * i, 0.8, 0.0)
        p.step(_laser(_cast(CORRIDOR, pose), float(angles[0]), float(angles[1] - angles[0]), float(i)),
               OdometryData(*pose, float(i)))
    for ranges in (np.full(360, np.nan), np.full(360, np.inf)):
        odo = (0.9, 0.85, 0.02)
        wm = p.step(_laser(ranges, float(angles[0]), float(angles[1] - angles[0]), 4.0), OdometryData(*odo, 4.0))
        assert not wm.pose_corrected and wm.pose_correction_quality == 0.0
        assert wm.pose == pytest.approx((0.9, 0.05, 0.02))  # odometry, in the zero frame of the first reading


def test_perceptor_walking_a_corridor_with_drifting_odometry_holds_the_cross_track():
    """A 270-degree laser walking down a corridor; odometry over-reads the forward motion by
    10 % and drifts sideways 8 cm a step (more than inlier_distance). The cross-track error is corrected every step, the
    along-track one is odometry's (the walls say nothing about it)."""
    p = Perceptor(PARAMS)
    fov = 1.5 * math.pi
    n = 541
    odo = (0.0, 0.8, 0.0)
    for i in range(15):
        true = (0.3 * i, 0.8, 0.0)
        if i:
            odo = (odo[0] + 0.33, odo[1] + 0.08, 0.0)
        laser = dataclasses.replace(cast(CORRIDOR, true, n, fov, max_range=30.0), timestamp=float(i))
        wm = p.step(laser, OdometryData(*odo, float(i)))
        assert abs(wm.pose[1] - 0.0) < 0.01  # the zero frame starts at the first pose
        assert wm.pose[0] == pytest.approx(odo[0], abs=1e-3)  # 3 cm a step over-read, not slid
        if i >= 2:
            assert wm.pose_corrected


def test_fit_kernel_compiled_equals_its_python():
    pts = _points(ROOM, (3.0, 2.5, 0.4))
    pts[::17] = np.nan  # skipped by both
    args = (pts, ROOM, np.array([3.1, 2.4, 0.45]), np.array([0.2, 0.2, 0.1]), _settings(SM))
    x, info = kn.fit_pose(*args)
    x_py, info_py = jit.py_func(kn.fit_pose)(*args)
    np.testing.assert_allclose(x, x_py, atol=1e-12)
    np.testing.assert_allclose(info, info_py, atol=1e-12)
    assert info[0] > 0.95


def test_intel_stretch_agreement_rises_with_the_correction(recordings_dir):
    """The first 120 scans (about 6 minutes, a 180-degree laser, a scan every ~3 s) of the Intel
    corrected log: with the correction the local map lies where the building is."""
    off = dataclasses.replace(PARAMS, scan_match=dataclasses.replace(SM, enabled=False))
    before, after = intel_agreement(off, 120), intel_agreement(PARAMS, 120)
    assert after > before + 0.2 and after > 0.45
