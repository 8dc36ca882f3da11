"""Init / Locate with both odometry forms, jumps and wrap-around; close proximity."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pico_studio.config import Config
from pico_studio.core.geometry import compose, relative
from pico_studio.core.io import LaserData, OdometryData
from pico_studio.core.perception.locate import LocateState, locate
from pico_studio.core.perception.proximity import proximity_flags
from pico_studio.core.perception.scan import process_scan

P = Config().perception


def _run(readings):
    state = LocateState()
    out = []
    for r in readings:
        state, _, w = locate(state, r, P.locate)
        out.append((state.pose, w))
    return state, out


def test_absolute_first_reading_is_zero_pose():
    start = (12.0, -3.0, 2.5)
    path = [start, compose(start, (0.1, 0.0, 0.05)), compose(start, (0.2, 0.05, 0.1))]
    state, out = _run([OdometryData(*p, 0.0) for p in path])
    assert state.zero_pose == start
    assert out[0][0] == (0.0, 0.0, 0.0)
    np.testing.assert_allclose(out[2][0], (0.2, 0.05, 0.1), atol=1e-12)


def test_delta_form_accumulates_from_the_first_reading():
    deltas = [(5.0, 5.0, 1.0), (0.1, 0.0, 0.1), (0.1, 0.0, 0.1)]  # the first: motion before zero
    state, out = _run([OdometryData(*d, 0.0, form="delta") for d in deltas])
    expected = compose((0.1, 0.0, 0.1), (0.1, 0.0, 0.1))
    np.testing.assert_allclose(state.pose, expected, atol=1e-12)
    assert out[0][0] == (0.0, 0.0, 0.0)


def test_wrap_around_is_a_small_step():
    a = [3.1, -3.1, -3.05]
    state, out = _run([OdometryData(1.0, 1.0, x, 0.0) for x in a])
    assert all(w == [] for _, w in out)
    assert state.pose[2] == pytest.approx(-3.05 - 3.1 + 2 * math.pi)


def test_absolute_jump_is_warned_and_re_anchored():
    readings = [OdometryData(0.0, 0.0, 0.0, 0), OdometryData(0.1, 0.0, 0.0, 0),
                OdometryData(50.0, 7.0, 1.0, 0), OdometryData(50.1, 7.0, 1.0, 0)]
    state, out = _run(readings)
    assert "jump" in out[2][1][0]
    np.testing.assert_allclose(out[2][0], (0.1, 0.0, 0.0), atol=1e-12)
    # after re-anchoring, motion continues from where the robot was
    step = relative((50.0, 7.0, 1.0), (50.1, 7.0, 1.0))
    np.testing.assert_allclose(out[3][0], compose((0.1, 0.0, 0.0), step), atol=1e-12)


def test_delta_jump_is_ignored_with_a_warning():
    readings = [OdometryData(0, 0, 0, 0, "delta"), OdometryData(0.1, 0, 0, 0, "delta"),
                OdometryData(9.0, 0, 0, 0, "delta")]
    state, out = _run(readings)
    assert "jump" in out[2][1][0]
    np.testing.assert_allclose(state.pose, (0.1, 0, 0))


def test_non_finite_odometry_is_ignored():
    state, out = _run([OdometryData(0, 0, 0, 0), OdometryData(float("nan"), 0, 0, 0)])
    assert "not finite" in out[1][1][0]
    assert state.pose == (0.0, 0.0, 0.0)


def test_proximity_flags_beams_inside_radius_not_footprint():
    # beams at 0, 0.3, ..., 1.5 rad; beam 0 (0.05 m ahead) and beam 5 (0.1 m to the left) lie
    # inside the 0.2 x 0.4 m footprint: the robot itself, not an obstacle
    r = np.array([0.05, 0.3, 0.34, 0.36, 2.0, 0.1])
    laser = LaserData(0.01, 10.0, 0.0, 1.5, 0.3, 0.0, r)
    scan, _ = process_scan(laser, P.scan, P.proximity)
    flags = proximity_flags(scan.ranges, scan.valid, P.proximity)
    np.testing.assert_array_equal(flags, [False, True, True, False, False, False])
