"""The shared pose helpers on plain floats, against the numpy-based ones they replaced.

`core.geometry.compose` / `relative` once wrapped angles through numpy (`np.mod`, `np.where`,
`float(...)`), about 13x slower per call than the `math`-only copies the simulator kept in
`sim/base.py`. The shared ones are now `math`-only; this prints, per helper, the median time
of one call over repeated runs for the old implementation (reproduced here as the peer) and
the current one, and their ratio. Also the vectorised forms (wrap of 10 000 angles,
point-to-segment distances of 1 point x 400 segments) so a scalar fast path never costs the
array callers, and `transform_points` of 40 points (a local map's corners, about six calls a
frame): the compiled loop against the matmul it replaced.

    python benchmarks/bench_geometry.py
"""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable

import numpy as np

from pico_studio.core.geometry import (
    compose,
    invert,
    point_segment_distance,
    relative,
    transform_points,
    wrap_angle,
)
from pico_studio.jit import warm_up

Pose = tuple[float, float, float]


# ----- the implementation before this change (the peer) --------------------------------------


def old_wrap_angle(a: float | np.ndarray) -> float | np.ndarray:
    w = np.mod(np.asarray(a, dtype=float) + math.pi, 2 * math.pi) - math.pi
    w = np.where(w == -math.pi, math.pi, w)
    return float(w) if np.ndim(w) == 0 else w


def old_compose(p: Pose, q: Pose) -> Pose:
    c, s = math.cos(p[2]), math.sin(p[2])
    return (p[0] + c * q[0] - s * q[1], p[1] + s * q[0] + c * q[1], float(old_wrap_angle(p[2] + q[2])))


def old_invert(p: Pose) -> Pose:
    c, s = math.cos(p[2]), math.sin(p[2])
    return (-c * p[0] - s * p[1], s * p[0] - c * p[1], float(old_wrap_angle(-p[2])))


def old_relative(p: Pose, q: Pose) -> Pose:
    return old_compose(old_invert(p), q)


def old_transform_points(points: np.ndarray, pose: Pose) -> np.ndarray:
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return points @ np.array([[c, -s], [s, c]]).T + np.array(pose[:2])


def old_segment_distances(xy: tuple[float, float], segments: np.ndarray) -> np.ndarray:
    """sim/base.py's single-point copy."""
    a = segments[:, 0:2]
    ab = segments[:, 2:4] - a
    ap = np.asarray(xy) - a
    t = np.minimum(np.maximum((ap * ab).sum(1) / np.maximum((ab * ab).sum(1), 1e-18), 0.0), 1.0)
    d = ap - t[:, None] * ab
    return np.sqrt((d * d).sum(1))


# ----- timing -----------------------------------------------------------------------------------


def per_call_us(fn: Callable[[], object], calls: int, repeats: int = 7) -> float:
    """Median over `repeats` runs of the time of one call, in microseconds."""
    runs = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        runs.append((time.perf_counter() - t0) / calls * 1e6)
    return statistics.median(runs)


def main() -> None:
    rng = np.random.default_rng(0)
    p = (1.0, -2.0, 3.0)
    q = (0.5, 0.25, 1.0)
    angles = rng.uniform(-20, 20, 10_000)
    segs = rng.uniform(-10, 10, (400, 4))
    xy = (0.3, -0.7)
    pts = rng.uniform(-10, 10, (40, 2))
    warm_up()
    # same answers first: the benchmark compares like with like
    assert np.allclose(compose(p, q), old_compose(p, q)) and np.allclose(relative(p, q), old_relative(p, q))
    assert np.allclose(wrap_angle(angles), old_wrap_angle(angles))
    assert np.allclose(point_segment_distance(xy, segs)[0], old_segment_distances(xy, segs))
    assert np.allclose(transform_points(pts, p), old_transform_points(pts, p), rtol=0, atol=1e-12)  # (FMA: last bits)
    cases = [
        ("compose (scalar)", lambda: old_compose(p, q), lambda: compose(p, q), 20_000),
        ("relative (scalar)", lambda: old_relative(p, q), lambda: relative(p, q), 20_000),
        ("invert (scalar)", lambda: old_invert(p), lambda: invert(p), 20_000),
        ("wrap_angle (scalar)", lambda: old_wrap_angle(7.0), lambda: wrap_angle(7.0), 20_000),
        ("wrap_angle (10k array)", lambda: old_wrap_angle(angles), lambda: wrap_angle(angles), 300),
        ("point-segment 1x400", lambda: old_segment_distances(xy, segs),
         lambda: point_segment_distance(xy, segs), 2_000),
        ("transform_points 40", lambda: old_transform_points(pts, p), lambda: transform_points(pts, p), 20_000),
    ]
    print(f"{'helper':<24}{'old us':>10}{'new us':>10}{'old/new':>9}")
    for name, old, new, calls in cases:
        t_old, t_new = per_call_us(old, calls), per_call_us(new, calls)
        print(f"{name:<24}{t_old:>10.3f}{t_new:>10.3f}{t_old / t_new:>8.1f}x")


if __name__ == "__main__":
    main()
