"""Scoring's `covered`: the pruned pair search equals the brute-force definition."""

from __future__ import annotations

import math

import numpy as np

from pico_studio.evaluation.frame_score import Tolerances, covered


def _brute_force(points: np.ndarray, dirs: np.ndarray, segments: np.ndarray, tol: Tolerances) -> np.ndarray:
    """The definition, every point against every segment."""
    out = np.zeros(len(points), dtype=bool)
    for i, (p, u) in enumerate(zip(points, dirs, strict=True)):
        for x1, y1, x2, y2 in segments:
            a, b = np.array([x1, y1]), np.array([x2, y2])
            ab = b - a
            t = min(max(float((p - a) @ ab / (ab @ ab)), 0.0), 1.0)
            close = np.linalg.norm(p - (a + t * ab)) <= tol.wall_distance
            parallel = abs(float(u @ ab) / np.linalg.norm(ab)) >= math.cos(tol.wall_angle)
            if close and parallel:
                out[i] = True
                break
    return out


def test_covered_equals_its_definition_on_random_scenes() -> None:
    rng = np.random.default_rng(0)
    tol = Tolerances()
    hits = total = 0
    for trial in range(60):
        segs = rng.uniform(0, 5, (int(rng.integers(1, 25)), 4))
        if trial % 3 == 0:
            segs[:, 3] = segs[:, 1]  # axis-aligned walls, as maps have
        n = int(rng.integers(1, 80))
        k = rng.integers(0, len(segs), n)
        t = rng.uniform(-0.1, 1.1, n)
        pts = segs[k, :2] + t[:, None] * (segs[k, 2:] - segs[k, :2]) + rng.normal(0, 0.08, (n, 2))
        d = segs[k, 2:] - segs[k, :2] + rng.normal(0, 0.2, (n, 2))
        dirs = d / np.linalg.norm(d, axis=1)[:, None]
        got = covered(pts, dirs, segs, tol)
        np.testing.assert_array_equal(got, _brute_force(pts, dirs, segs, tol))
        hits += int(got.sum())
        total += n
    assert 0 < hits < total  # the scenes exercise both outcomes
