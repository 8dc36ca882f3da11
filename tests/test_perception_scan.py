"""Scan stage and segmenters on hand-built scans with known walls."""

from __future__ import annotations

import math

import numpy as np
import pytest
from perception_scenes import DOOR_ROOM, SQUARE, poly, scan_of

from pico_studio.config import Config, with_value
from pico_studio.core.geometry import segment_lengths
from pico_studio.core.io import LaserData
from pico_studio.core.perception.corners import spike_corners, vector_corners
from pico_studio.core.perception.scan import beam_angles, process_scan
from pico_studio.core.perception.segment import (
    END_FLOATING,
    END_JOINT,
    END_SEEN,
    refit,
    segment_scan,
)

CFG = Config()
P = CFG.perception


def _segments(walls, pose, segmenter="split_merge", noise=0.01, seed=1):
    params = with_value(CFG, "perception.scan.segmenter", segmenter).perception
    scan, warnings = process_scan(scan_of(walls, pose, noise=noise, seed=seed), params.scan, params.proximity)
    assert warnings == []
    return scan, segment_scan(scan, params)


def _to_world(seg, pose):
    c, s = math.cos(pose[2]), math.sin(pose[2])
    pts = seg.reshape(-1, 2) @ np.array([[c, s], [-s, c]]) + np.array(pose[:2])
    return pts.reshape(-1, 4)


def _on_true_wall(seg_world, walls, tol):
    """Every detected end point lies within tol of some true wall."""
    from pico_studio.core.geometry import point_segment_distance

    d = point_segment_distance(seg_world.reshape(-1, 2), walls).min(axis=1)
    return bool((d < tol).all())


def test_polar_to_cartesian_any_layout():
    laser = LaserData(0.0, 10.0, -math.pi / 2, math.pi / 2, math.pi / 2, 0.0, np.array([1.0, 2.0, 3.0]))
    scan, w = process_scan(laser, P.scan, P.proximity)
    assert w == []
    np.testing.assert_allclose(scan.all_points, [[0, -1], [2, 0], [0, 3]], atol=1e-12)


def test_range_filter_drops_nan_inf_zero_and_out_of_range():
    r = np.array([1.0, np.nan, np.inf, 0.0, 0.04, 11.0, -1.0, 2.0])
    laser = LaserData(0.01, 10.0, -0.35, 0.35, 0.1, 0.0, r)
    scan, _ = process_scan(laser, P.scan, P.proximity)
    np.testing.assert_array_equal(scan.valid, [True, False, False, False, False, False, False, True])


def test_footprint_points_are_not_walls():
    r = np.full(11, 0.05)  # everything inside the 0.2 x 0.4 m footprint
    r[5] = 3.0
    laser = LaserData(0.0, 10.0, -0.5, 0.5, 0.1, 0.0, r)
    scan, _ = process_scan(laser, P.scan, P.proximity)
    assert scan.valid.sum() == 1


def test_mismatched_angle_fields_warn_and_still_place_beams():
    laser = LaserData(0.01, 10.0, -2.0, 1.0, 4 / 999, 0.0, np.full(1000, 2.0))
    angles, w = beam_angles(laser)
    assert len(w) == 1 and "disagree" in w[0]
    assert angles[-1] == pytest.approx(2.0)
    bad = LaserData(0.01, 10.0, -2.0, 2.0, float("nan"), 0.0, np.full(5, 2.0))
    angles, w = beam_angles(bad)
    np.testing.assert_allclose(angles, np.linspace(-2, 2, 5))
    assert "unusable" in w[0]


def test_resampling_keeps_minimum_spacing_and_cluster_ends():
    scan, _ = _segments(SQUARE, (0.0, 0.0, 0.0))
    start, end = scan.clusters[0]
    steps = np.hypot(*np.diff(scan.points[start : end - 1], axis=0).T)
    # one point per min_spacing bin of the arc length: about min_spacing apart, never much closer
    assert np.median(steps) >= 0.6 * P.scan.min_spacing
    assert steps.min() >= 0.2 * P.scan.min_spacing
    assert len(scan.points) < scan.valid.sum()


def test_breaks_at_range_jumps():
    # a box in front of a far wall: the scan is cut at both edges of the box
    walls = np.vstack([poly((3, -3), (3, 3), closed=False), poly((1, -0.3), (1, 0.3), closed=False)])
    scan, segs = _segments(walls, (0.0, 0.0, 0.0))
    assert len(scan.clusters) == 3
    # the box's wall ends were seen (the laser looked past them), the far wall's inner ends not
    box = np.flatnonzero(np.abs(segs.segments[:, 0] - 1.0) < 0.05)
    assert len(box) == 1
    assert (segs.end_kind[box[0]] == END_SEEN).all()


@pytest.mark.parametrize("segmenter", ["split_merge", "angle", "ransac"])
def test_square_room_gives_its_walls(segmenter):
    pose = (0.3, -0.2, 0.4)
    _, segs = _segments(SQUARE, pose, segmenter)
    world = _to_world(segs.segments, pose)
    assert _on_true_wall(world, SQUARE, 0.06)
    # the field of view (229 deg) sees three walls, plus pieces of the fourth at the edges
    long = segment_lengths(world) > 1.0
    assert 3 <= long.sum() <= 4
    assert segment_lengths(world).sum() > 9.0
    # consecutive walls of one cluster meet in a joint
    assert (segs.end_kind == END_JOINT).sum() >= 4


@pytest.mark.parametrize("segmenter", ["split_merge", "angle", "ransac"])
def test_l_corner(segmenter):
    walls = poly((3, -2), (3, 1), (-1, 1), closed=False)  # a concave corner at (3, 1)
    pose = (0.0, 0.0, 0.0)
    _, segs = _segments(walls, pose, segmenter)
    assert len(segs.segments) == 2
    seg = segs.segments
    # the joint is at the corner within a few cm
    joint = seg[0, 2:4] if np.hypot(*(seg[0, 2:4] - [3, 1])) < np.hypot(*(seg[0, 0:2] - [3, 1])) else seg[0, 0:2]
    assert np.hypot(*(joint - [3, 1])) < 0.06
    ang = [math.atan2(s[3] - s[1], s[2] - s[0]) for s in seg]
    assert abs(abs(math.cos(ang[0] - ang[1]))) < 0.05  # perpendicular


def test_refit_is_total_least_squares():
    x = np.linspace(0, 2, 50)
    pts = np.column_stack([x, 0.5 * x + 1.0])
    seg, theta, rms = refit(pts, np.array([[0, 49]]))
    assert theta[0] == pytest.approx(math.atan(0.5))
    assert rms[0] == pytest.approx(0.0, abs=1e-7)
    np.testing.assert_allclose(seg[0], [0, 1, 2, 2], atol=1e-9)


def test_door_gap_gives_two_seen_ends():
    _, segs = _segments(DOOR_ROOM, (0.0, 0.0, math.pi / 2))
    seen = segs.segments.reshape(-1, 2)[(segs.end_kind == END_SEEN).reshape(-1)]
    # in the robot frame (facing +y) the jambs are at (2, +-0.45)
    assert len(seen) == 2
    np.testing.assert_allclose(sorted(seen[:, 1]), [-0.45, 0.45], atol=0.05)
    np.testing.assert_allclose(seen[:, 0], [2.0, 2.0], atol=0.05)


def test_fov_edges_are_floating():
    _, segs = _segments(SQUARE, (0.0, 0.0, 0.0))
    assert segs.end_kind[0, 0] == END_FLOATING
    assert segs.end_kind[-1, 1] == END_FLOATING


def test_spike_and_vector_corners():
    # a box in front of the robot: two outer corners facing it, in a room (inner corners)
    box = poly((1.0, -0.3), (1.4, -0.3), (1.4, 0.3), (1.0, 0.3))
    walls = np.vstack([SQUARE * 1.5, box])
    scan, _ = process_scan(scan_of(walls, (0, 0, 0), noise=0.005), P.scan, P.proximity)
    spikes = spike_corners(scan, P.corners)
    for c in ([1.0, -0.3], [1.0, 0.3]):
        assert np.hypot(*(spikes - c).T).min() < 0.05
    vec, inner = vector_corners(scan, P.corners, P.scan.min_spacing)
    outer_near = vec[~inner]
    inner_near = vec[inner]
    # the room's corners at (3, -3), (3, 3) are inner corners
    for c in ([3, -3], [3, 3]):
        assert np.hypot(*(inner_near - c).T).min() < 0.1
    assert len(outer_near) == 0 or np.hypot(*outer_near.T).min() < 2.0


def test_empty_nan_inf_scans_give_no_segments():
    for r in (np.zeros(0), np.full(1000, np.nan), np.full(1000, np.inf)):
        laser = LaserData(0.01, 10.0, -2.0, 2.0, 4 / 999, 0.0, r)
        scan, w = process_scan(laser, P.scan, P.proximity)
        assert len(w) == 1
        assert len(segment_scan(scan, P).segments) == 0


def test_opencv_split_agrees_with_the_numpy_recursion():
    """Both are the seed's recursion; they may break a tie at a corner differently (float32
    vs float64), so compare what matters: every piece within the split distance of its
    chord, and the same walls after the refit."""
    from pico_studio.core.perception.segment import finish_pieces
    from pico_studio.core.perception.segment_split_merge import split, split_numpy

    walls = np.vstack([SQUARE * 2, poly((1.0, -0.5), (1.6, -0.5), (1.6, 0.5), (1.0, 0.5))])
    for k in range(5):
        scan, _ = process_scan(scan_of(walls, (-0.5, 0.3 * k - 0.6, 0.5 * k), noise=0.01, seed=k), P.scan, P.proximity)
        results = []
        for f in (split, split_numpy):
            pieces = f(scan.points, scan.clusters, P.split_merge)
            for a, b in pieces.tolist():
                p = scan.points[a : b + 1]
                ab = p[-1] - p[0]
                d = np.abs(ab[0] * (p[:, 1] - p[0, 1]) - ab[1] * (p[:, 0] - p[0, 0])) / np.hypot(*ab)
                assert d.max() <= P.split_merge.split_distance + 1e-5
            results.append(finish_pieces(scan, pieces, P).segments)
        a, b = results
        assert a.shape == b.shape and len(a) >= 3
        np.testing.assert_allclose(a, b, atol=0.08)  # an end at a corner may move a point or two


def test_beam_layout_cache_follows_the_layout_and_keeps_warnings():
    """Cos/sin tables are cached per beam layout: a second layout, a bad one in between and a
    repeat of the first each get their own angles and their own warnings."""
    r = np.array([1.0, 2.0, 3.0])
    first = LaserData(0.0, 10.0, -math.pi / 2, math.pi / 2, math.pi / 2, 0.0, r)
    other = LaserData(0.0, 10.0, 0.0, math.pi, math.pi / 2, 0.0, r)
    bad = LaserData(0.0, 10.0, 0.0, 1.0, 0.3, 0.0, r)  # ends at 0.6, not 1.0: warned
    for laser, expect, warned in ((first, [[0, -1], [2, 0], [0, 3]], False),
                                  (other, [[1, 0], [0, 2], [-3, 0]], False),
                                  (bad, None, True), (bad, None, True),
                                  (first, [[0, -1], [2, 0], [0, 3]], False)):
        scan, w = process_scan(laser, P.scan, P.proximity)
        assert bool(w) == warned
        angles, _ = beam_angles(laser)
        np.testing.assert_array_equal(scan.angles, angles)
        pts = scan.all_points
        np.testing.assert_allclose(pts, np.column_stack([r * np.cos(angles), r * np.sin(angles)]), atol=1e-12)
        if expect is not None:
            np.testing.assert_allclose(pts, expect, atol=1e-12)


def _kernel_args(laser: LaserData, p) -> tuple:  # noqa: ANN001
    from pico_studio.core.perception.scan import _layout

    angles, cos, sin, _ = _layout(laser)
    s = p.scan
    return (np.ascontiguousarray(laser.ranges, dtype=np.float64), angles, cos, sin, s.min_range, s.max_range,
            p.proximity.footprint_length / 2, p.proximity.footprint_width / 2, s.break_distance, s.break_slope,
            s.min_spacing, s.grazing_factor, s.grazing_max_break, s.grazing_line_distance)


def test_cheap_step_lengths_decide_as_hypot_does():
    """The scan pass measures steps by sqrt(dx^2 + dy^2) and calls each break and resampling
    bin it could get wrong "uncertain"; it is then run again by hypot. On real scans (with and
    without grazing-angle breaks) both give the same arrays; a min_spacing that puts a point
    exactly on a bin's edge is uncertain, and process_scan then returns hypot's answer."""
    from pico_studio.core.perception.scan_kernels import scan_points
    from tests.jit_scenes import hospital_scans

    grazing = with_value(CFG, "perception.scan.grazing_factor", 10.0).perception
    for laser in hospital_scans(4):
        for p in (P, grazing):
            fast, exact = scan_points(*_kernel_args(laser, p), False), scan_points(*_kernel_args(laser, p), True)
            assert fast[6] and exact[6]
            for a, b in zip(fast[:6], exact[:6], strict=True):
                np.testing.assert_array_equal(a, b)
    laser = hospital_scans(1)[0]
    s = process_scan(laser, P.scan, P.proximity)[0].valid_xy
    edge = float(np.hypot(*(s[1] - s[0])))  # the first step: arc / min_spacing is exactly 1 there
    p = with_value(CFG, "perception.scan.min_spacing", edge).perception
    fast = scan_points(*_kernel_args(laser, p), False)
    assert not fast[6]
    exact = scan_points(*_kernel_args(laser, p), True)
    scan, _ = process_scan(laser, p.scan, p.proximity)
    for a, b in zip((scan.valid, scan.valid_xy, scan.points, scan.beam, scan.clusters, scan.end_seen), exact[:6],
                    strict=True):
        np.testing.assert_array_equal(a, b)


def test_a_beam_that_hit_nothing_reads_below_range_min_and_the_end_beside_it_is_seen():
    """The official simulator's no-return: its range buffer starts at 0 and the noise lifts it to
    [0, noise], below range_min. Such a beam is nothing there, not something nearer: the wall's
    end beside it is seen, whichever the noise's sign (before, a positive reading hid the end on
    half the beams). The laser's own array is left alone."""
    angles = np.linspace(-0.3, 0.3, 61)
    wall = 2.0 / np.cos(angles[:40])  # a wall 2 m ahead, ending at beam 39
    for lifted in (0.0, 0.004, 0.0099):
        ranges = np.concatenate([wall, np.full(21, lifted)])
        laser = LaserData(0.01, 10.0, -0.3, 0.3, 0.01, 0.0, ranges.copy())
        scan, _ = process_scan(laser, P.scan, P.proximity)
        segs = segment_scan(scan, P)
        assert segs.end_kind[-1, 1] == END_SEEN, lifted
        np.testing.assert_array_equal(laser.ranges, ranges)
    # a reading at or past range_min that the perceptor's own filter drops is something nearer
    near = np.concatenate([wall, np.full(21, 0.04)])
    scan, _ = process_scan(LaserData(0.01, 10.0, -0.3, 0.3, 0.01, 0.0, near), with_value(CFG, "perception.scan.min_range", 0.05).perception.scan, P.proximity)
    assert segment_scan(scan, P).end_kind[-1, 1] == END_FLOATING


def test_a_wall_running_out_of_the_lasers_reach_has_a_floating_end():
    """A far wall seen up to the laser's reach (10 m): the beams past its end return nothing
    because the wall went on beyond 10 m, not because it ended (suite:4: the right outer wall
    9.9-10 m off, its end at the reach marked convex, 1.2-1.5 m from any corner, moved along
    the wall for 80 s). Well inside the reach the same end beside nothing is seen."""
    angles = np.linspace(-0.3, 0.3, 61)
    for ahead, kind in ((9.85, END_FLOATING), (8.0, END_SEEN)):
        ranges = ahead / np.cos(angles)  # a wall `ahead` m off, square to the middle beam
        ranges[ranges > 10.0] = 0.0  # out of reach: nothing returned (the simulator's 0)
        gone = ranges == 0.0
        if ahead == 8.0:  # the wall ends at beam 45, nothing beyond
            ranges[46:], gone = 0.0, np.arange(61) >= 46
        assert gone.any() and not gone.all()
        scan, _ = process_scan(LaserData(0.01, 10.0, -0.3, 0.3, 0.01, 0.0, ranges), P.scan, P.proximity)
        segs = segment_scan(scan, P)
        assert segs.end_kind[-1, 1] == kind, ahead


def test_a_grazing_wall_whose_next_beam_would_meet_it_out_of_reach_has_a_floating_end():
    """Seen at a slant, a wall's range grows 0.4 m a beam near 10 m: its last point 9.66 m off
    lies more than the break's margin inside the reach, but the next beam would meet the wall,
    going on, at 10.07 m: nothing returned there says nothing of an end (with the grazing
    allowance that keeps such a wall one cluster)."""
    angles = -0.8003 + 0.01 * np.arange(61)
    ranges = 2.3 / -np.sin(angles)  # the wall y = -2.3, robot at the origin
    ranges[ranges > 10.0] = 0.0
    assert (ranges[-4:] == 0.0).all() and 9.6 < ranges[-5] < 10.0 - 0.12 - 0.02 * 9.7
    params = with_value(CFG, "perception.scan.grazing_factor", 2.0).perception
    laser = LaserData(0.01, 10.0, -0.8003, -0.2003, 0.01, 0.0, ranges)
    scan, _ = process_scan(laser, params.scan, params.proximity)
    assert scan.beam[scan.clusters[-1, 1] - 1] == 56  # the last point in the wall's cluster
    assert segment_scan(scan, params).end_kind[-1, 1] == END_FLOATING
