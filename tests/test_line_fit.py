"""Range-weighted line fit (Pfister et al. 2003) and the walls' line covariance (segment_refit)."""

from __future__ import annotations

import math

import numpy as np

from pico_studio import jit
from pico_studio.core.perception import segment_refit

SIGMA0, PER_M = 0.005, 0.01


def _wall(rng: np.random.Generator, x: float, y0: float, y1: float, n: int) -> np.ndarray:
    """Points of the wall x = `x` for y in [y0, y1], each with noise growing with its range."""
    y = np.linspace(y0, y1, n)
    p = np.column_stack([np.full(n, x), y])
    r = np.hypot(p[:, 0], p[:, 1])
    return p + rng.normal(size=(n, 2)) * (SIGMA0 + PER_M * r)[:, None]


def _fit(pts: np.ndarray, weighted: bool) -> tuple:
    pieces = np.array([[0, len(pts) - 1]], dtype=np.int64)
    clusters = np.array([[0, len(pts)]], dtype=np.int64)
    seen = np.zeros((1, 2), dtype=np.bool_)
    return segment_refit.finish_kernel(pts, pieces, clusters, seen, 0.1, 2, 0.0, 10.0, 0.05, 3,
                                       SIGMA0, PER_M, weighted, 0.0)


def _errors(seg: np.ndarray, x: float) -> tuple[float, float]:
    """(angle error, distance error at y = 0) of a fitted segment against the wall x = `x`."""
    dx, dy = seg[2] - seg[0], seg[3] - seg[1]
    angle = abs(math.atan2(dx, dy))
    angle = min(angle, math.pi - angle)  # undirected: the wall runs along y
    x_at0 = seg[0] - dx * seg[1] / dy
    return angle, abs(x_at0 - x)


def test_weighted_fit_beats_the_plain_one_on_a_long_sparse_wall():
    # a wall 2 m away running out to 12 m along it: its far points are ten times noisier
    rng = np.random.default_rng(7)
    wins_a = wins_d = 0
    err_w = err_u = 0.0
    trials = 200
    for _ in range(trials):
        pts = _wall(rng, 2.0, 0.0, 12.0, 25)
        aw, dw = _errors(_fit(pts, True)[0][0], 2.0)
        au, du = _errors(_fit(pts, False)[0][0], 2.0)
        wins_a += aw < au
        wins_d += dw < du
        err_w += aw
        err_u += au
    assert wins_a > 0.6 * trials and wins_d > 0.6 * trials
    assert err_w < 0.8 * err_u  # the mean angle error drops by a fifth at least


def test_covariance_grows_with_range():
    # the same wall (same length, points, noise model) near and far
    rng = np.random.default_rng(3)
    near = _fit(_wall(rng, 1.0, -0.5, 0.5, 20), True)[5][0]
    far = _fit(_wall(rng, 8.0, -0.5, 0.5, 20), True)[5][0]
    assert far[0] > 4 * near[0]  # var(alpha)
    assert far[1] > 4 * near[1]  # var(rho)
    assert near[0] > 0 and near[1] > 0
    # and the Hessian form's cross term: a wall centred at y = 0 has rho independent of alpha
    assert abs(near[2]) < 0.1 * math.sqrt(near[0] * near[1]) + 1e-9


def test_plain_fit_is_the_weighted_one_with_unit_weights():
    rng = np.random.default_rng(5)
    pts = _wall(rng, 3.0, -2.0, 4.0, 40)
    plain = _fit(pts, False)
    flat = segment_refit.finish_kernel(pts, np.array([[0, 39]]), np.array([[0, 40]]), np.zeros((1, 2), dtype=np.bool_),
                                       0.1, 2, 0.0, 10.0, 0.05, 3, SIGMA0, 0.0, True, 0.0)
    np.testing.assert_allclose(plain[0], flat[0], atol=1e-12)


def test_minimum_points_grows_with_range():
    rng = np.random.default_rng(2)
    for x, kept in ((1.0, True), (6.0, False)):
        pts = _wall(rng, x, -0.5, 0.5, 8)
        out = segment_refit.finish_kernel(pts, np.array([[0, 7]]), np.array([[0, 8]]),
                                          np.zeros((1, 2), dtype=np.bool_), 0.1, 5, 0.0, 10.0, 0.05, 3,
                                          SIGMA0, PER_M, True, 1.0)  # 5 + 1/m: 6 at 1 m, 11 at 6 m
        assert (len(out[0]) == 1) == kept


def test_compiled_equals_its_python():
    rng = np.random.default_rng(11)
    py = jit.py_func(segment_refit.finish_kernel)
    for _ in range(20):
        pts = np.vstack([_wall(rng, 2.0 + rng.uniform(0, 6), -1.0, 3.0, 30),
                         _wall(rng, 9.0, 3.0, 6.0, 15)[:, ::-1]])
        args = (pts, np.array([[0, 29], [30, 44]]), np.array([[0, 30], [30, 45]]), np.zeros((2, 2), dtype=np.bool_),
                0.1, 4, 0.0, 10.0, 0.05, 3, SIGMA0, PER_M, True, 0.5)
        got, want = segment_refit.finish_kernel(*args), py(*args)
        assert len(got) == len(want) == 6
        for g, w in zip(got, want, strict=True):  # the same up to rounding (numba may fuse w * x * x)
            assert g.dtype == w.dtype and g.shape == w.shape
            np.testing.assert_allclose(g, w, rtol=1e-9, atol=1e-12)
