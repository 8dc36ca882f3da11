"""core/geometry.py and LaserData's beam helpers against independent formulas."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pico_studio.core.geometry import (
    compose,
    invert,
    pairwise_distances,
    point_segment_distance,
    point_segment_distance_paired,
    relative,
    segments_cross,
    wrap_angle,
)
from pico_studio.core.io import LaserData


def _matrix(p: tuple[float, float, float]) -> np.ndarray:
    c, s = math.cos(p[2]), math.sin(p[2])
    return np.array([[c, -s, p[0]], [s, c, p[1]], [0.0, 0.0, 1.0]])


def _pose(m: np.ndarray) -> tuple[float, float, float]:
    return (m[0, 2], m[1, 2], math.atan2(m[1, 0], m[0, 0]))


def test_poses_match_homogeneous_matrices() -> None:
    rng = np.random.default_rng(3)
    for _ in range(200):
        p = tuple(float(v) for v in rng.uniform(-7, 7, 3))
        q = tuple(float(v) for v in rng.uniform(-7, 7, 3))
        assert np.allclose(compose(p, q), _pose(_matrix(p) @ _matrix(q)))
        assert np.allclose(invert(p), _pose(np.linalg.inv(_matrix(p))))
        assert np.allclose(relative(p, q), _pose(np.linalg.inv(_matrix(p)) @ _matrix(q)))
        assert all(type(v) is float for v in compose(p, q) + relative(p, q) + invert(p))


def test_wrap_angle_is_half_open_at_minus_pi_for_floats_and_arrays() -> None:
    values = np.array([-math.pi, math.pi, 3 * math.pi, -3 * math.pi, 0.5, 7.0, -7.0])
    arr = wrap_angle(values)
    for v, w in zip(values, arr, strict=True):
        s = wrap_angle(float(v))
        assert isinstance(s, float) and -math.pi < s <= math.pi
        assert s == pytest.approx(w) and math.isclose(math.cos(s), math.cos(v), abs_tol=1e-12)
    assert wrap_angle(-math.pi) == math.pi
    assert isinstance(wrap_angle(np.float64(4.0)), float)


def test_point_segment_distance_all_pairs_and_paired() -> None:
    segs = np.array([[0.0, 0.0, 2.0, 0.0], [1.0, 1.0, 1.0, 1.0]])  # a segment and a point
    pts = np.array([[1.0, 2.0], [-3.0, 4.0], [3.0, 0.0]])
    want = np.array([[2.0, 1.0], [5.0, math.hypot(4, 3)], [1.0, math.hypot(2, 1)]])
    assert np.allclose(point_segment_distance(pts, segs), want)
    assert np.allclose(point_segment_distance((1.0, 2.0), segs), want[:1])
    assert np.allclose(point_segment_distance_paired(pts[:2], segs), [want[0, 0], want[1, 1]])


def test_pairwise_distances() -> None:
    a = np.array([[0.0, 0.0], [3.0, 4.0]])
    b = np.array([[0.0, 0.0], [6.0, 8.0], [3.0, 0.0]])
    assert np.allclose(pairwise_distances(a, b), [[0, 10, 3], [5, 5, 4]])
    assert pairwise_distances(a, np.zeros((0, 2))).shape == (2, 0)


def test_segments_cross() -> None:
    a, b = np.array([0.0, 0.0]), np.array([2.0, 0.0])
    walls = np.array([[1.0, -1.0, 1.0, 1.0],    # crosses
                      [3.0, -1.0, 3.0, 1.0],    # beyond the end
                      [2.0, -1.0, 2.0, 1.0],    # the move ends on it
                      [0.0, 1.0, 2.0, 1.0]])    # parallel
    strict = segments_cross(a, b, walls[:, 0:2], walls[:, 2:4])
    ends = segments_cross(a, b, walls[:, 0:2], walls[:, 2:4], end_on_line=True)
    assert strict.tolist() == [True, False, False, False]
    assert ends.tolist() == [True, False, True, False]


def test_laser_valid_and_points() -> None:
    laser = LaserData(range_min=0.1, range_max=5.0, angle_min=-math.pi / 2, angle_max=math.pi / 2,
                      angle_increment=math.pi / 2, timestamp=0.0,
                      ranges=np.array([1.0, np.nan, 2.0]))
    assert laser.valid.tolist() == [True, False, True]
    assert np.allclose(laser.points, [[0.0, -1.0], [0.0, 2.0]], atol=1e-12)
    odd = LaserData(0.1, 5.0, 0.0, 1.0, 0.5, 0.0, np.array([0.05, np.inf, 5.0]))
    assert odd.valid.tolist() == [False, False, True] and odd.points.shape == (1, 2)
