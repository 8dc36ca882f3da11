"""Pose from the laser: jump limits that scale with time, scan-to-local-map matching, and the
real-log agreement score rising on a stretch of the Intel log."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pico_studio.config import load_config
from pico_studio.core.geometry import invert, transform_points
from pico_studio.core.io import OdometryData
from pico_studio.core.perception.locate import LocateState, locate
from pico_studio.core.perception.scan_match import match_scan
from pico_studio.evaluation.agreement import sample_segments
from pico_studio.evaluation.reference_map import ReferenceMap
from tests.recording_helpers import intel_agreement

PARAMS = load_config(None).perception
ROOM = np.array([[0, 0, 6, 0], [6, 0, 6, 4], [6, 4, 0, 4], [0, 4, 0, 0], [2, 0, 2, 1.5]], dtype=float)


def _scan_of(walls: np.ndarray, pose: tuple[float, float, float], n: int = 360) -> np.ndarray:
    """Robot-frame points where beams from `pose` hit `walls` (a plain ray cast)."""
    ang = np.linspace(-math.pi, math.pi, n, endpoint=False) + pose[2]
    d = np.column_stack([np.cos(ang), np.sin(ang)])
    a, e = walls[:, 0:2], walls[:, 2:4] - walls[:, 0:2]
    o = np.array(pose[:2])
    den = d[:, None, 0] * e[None, :, 1] - d[:, None, 1] * e[None, :, 0]
    ao = a[None] - o
    safe = np.where(np.abs(den) > 1e-12, den, 1.0)
    t = (ao[..., 0] * e[None, :, 1] - ao[..., 1] * e[None, :, 0]) / safe
    u = (ao[..., 0] * d[:, None, 1] - ao[..., 1] * d[:, None, 0]) / safe
    t = np.where((np.abs(den) > 1e-12) & (t > 0) & (u >= 0) & (u <= 1), t, np.inf).min(axis=1)
    hit = np.isfinite(t)
    return transform_points(o + t[hit, None] * d[hit], invert(pose))


def test_jump_limit_grows_with_the_time_between_readings():
    p = PARAMS.locate
    s, _, _ = locate(LocateState(), OdometryData(0.0, 0.0, 0.0, 0.0), p)
    # 1.5 m in 3 s (a slow log): real motion, kept
    s2, step, warn = locate(s, OdometryData(1.5, 0.0, 0.0, 3.0), p)
    assert not warn and step == pytest.approx((1.5, 0.0, 0.0)) and s2.pose[0] == pytest.approx(1.5)
    # 1.5 m in 0.05 s: a jump, re-anchored
    s3, step, warn = locate(s, OdometryData(1.5, 0.0, 0.0, 0.05), p)
    assert warn and step is None and s3.pose == (0.0, 0.0, 0.0)


def test_corrected_pose_carries_over_to_the_next_reading():
    p = PARAMS.locate
    s, _, _ = locate(LocateState(), OdometryData(5.0, 1.0, 0.3, 0.0), p)
    s, _, _ = locate(s, OdometryData(5.5, 1.0, 0.3, 0.5), p)
    s = s.corrected((0.4, 0.1, 0.05))
    s, step, _ = locate(s, OdometryData(5.5, 1.0, 0.3, 1.0), p)  # no motion since
    assert s.pose == pytest.approx((0.4, 0.1, 0.05)) and step == pytest.approx((0, 0, 0), abs=1e-9)


def test_scan_match_corrects_a_poor_odometry_pose():
    true = (3.0, 2.5, 0.4)
    pts = _scan_of(ROOM, true)
    odo = (3.15, 2.4, 0.48)
    m = match_scan(pts, ROOM, odo, (0.8, 0.0, 0.3), PARAMS.scan_match)
    assert m.accepted and m.quality > 0.9
    assert math.hypot(m.pose[0] - true[0], m.pose[1] - true[1]) < 0.02 and abs(m.pose[2] - true[2]) < 0.01


def test_scan_match_leaves_good_odometry_alone():
    true = (3.0, 2.5, 0.4)
    m = match_scan(_scan_of(ROOM, true), ROOM, true, (0.1, 0.0, 0.0), PARAMS.scan_match)
    assert m.pose == pytest.approx(true, abs=1e-6) and m.quality > 0.9  # matching moves it nowhere


def test_scan_match_keeps_a_corridor_s_free_direction():
    corridor = np.array([[-20, 0, 20, 0], [-20, 1.5, 20, 1.5]], dtype=float)
    true = (0.0, 0.75, 0.0)
    odo = (0.3, 0.9, 0.0)  # 0.3 m off along the corridor (unobservable), 0.15 m across
    m = match_scan(_scan_of(corridor, true), corridor, odo, (1.0, 0.0, 0.0), PARAMS.scan_match)
    assert m.accepted and abs(m.pose[1] - true[1]) < 0.02 and abs(m.pose[0] - odo[0]) < 0.05


def test_reference_map_and_agreement_on_a_built_room():
    ref = ReferenceMap()
    for pose in ((3.0, 2.5, 0.0), (4.0, 1.0, 1.0), (1.0, 3.0, -2.0)):
        ref.add_scan(_scan_of(ROOM, pose, 1440), pose)
    on_wall = sample_segments(ROOM, 0.05)
    assert (ref.distance(on_wall) <= 0.1).mean() > 0.95
    assert (ref.distance(on_wall + [0.5, 0.5]) <= 0.1).mean() < 0.2  # a ghost half a metre off


def test_intel_stretch_agreement_rises(recordings_dir):
    """The first 100 scans (about 5 minutes) of the Intel corrected log: with the old fixed
    1 m / 1 rad jump limits, no laser correction and walls kept for ever the local map is
    mostly ghosts."""
    old = dataclasses.replace(
        PARAMS, locate=dataclasses.replace(PARAMS.locate, jump_speed=0.0, jump_turn_rate=0.0),
        scan_match=dataclasses.replace(PARAMS.scan_match, enabled=False),
        merge=dataclasses.replace(PARAMS.merge, forget_seconds=0.0))
    before, after = intel_agreement(old, 100), intel_agreement(PARAMS, 100)
    assert before < 0.2 and after > before + 0.2


def test_the_whole_intel_log_agrees_once_unseen_walls_are_forgotten_in_time():
    """All 910 scans (one every 2.9 s): walls kept for ever drift with the pose into ghosts;
    forgotten after `forget_seconds` of not being seen, the local map stays true."""
    never = dataclasses.replace(PARAMS, merge=dataclasses.replace(PARAMS.merge, forget_seconds=0.0))
    assert intel_agreement(never, 910) < 0.7 < 0.8 <= intel_agreement(PARAMS, 910)
