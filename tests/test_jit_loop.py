"""The rest of the loop's compiled code gives the answers of the numpy it replaced and of its
own `.py_func`: the wander behaviour's clearance, the base's clearance and box test, and
`geometry.transform_points`, on real hospital_2019 scans, poses and local maps."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pico_studio import jit
from pico_studio.config.sim_params import BaseParams
from pico_studio.config.ui_params import WanderParams
from pico_studio.core.behaviours import wander
from pico_studio.core.geometry import _rigid, point_segment_distance, transform_points
from pico_studio.sim import base_kernels
from pico_studio.sim.base import box_hits
from tests.jit_scenes import hospital_frames


def test_wander_clearance_is_the_numpy_it_replaced():
    half_angle = WanderParams().front_half_angle
    sides = 0
    for _, laser, _ in hospital_frames(8):
        ranges = np.asarray(laser.ranges, dtype=float).copy()
        ranges[::37] = np.inf  # no returns, NaN and too-short ones count as range_max
        ranges[5::41] = np.nan
        ranges[9::53] = 0.0
        for r, angle in ((laser.ranges, half_angle), (ranges, half_angle), (ranges, 0.0), (ranges[:501], 1.0)):
            scan = dataclasses.replace(laser, ranges=r)
            got, ref = wander.clearance(scan, angle), wander.clearance_numpy(scan, angle)
            assert got == ref
            args = (np.ascontiguousarray(r, dtype=np.float64), scan.angle_min, scan.angle_increment,
                    scan.range_min, scan.range_max, angle)
            assert wander._clearance(*args) == jit.py_func(wander._clearance)(*args)
            sides += ref.left != ref.right
    assert sides >= 8
    empty = dataclasses.replace(laser, ranges=np.zeros(0, dtype=np.float32))
    assert wander.clearance(empty, half_angle) == wander.clearance_numpy(empty, half_angle)


def _near_wall_poses() -> list[tuple[tuple[float, float, float], np.ndarray]]:
    """Poses of real frames pushed towards their nearest wall in steps, so some boxes touch."""
    out = []
    for sim, _, _ in hospital_frames(8):
        segs = np.ascontiguousarray(sim.world.segments())
        x, y, a = sim.truth.pose
        d = point_segment_distance((x, y), segs)[0]
        k = int(np.argmin(d))
        ax, ay, bx, by = segs[k]
        t = min(max(((x - ax) * (bx - ax) + (y - ay) * (by - ay)) / max((bx - ax) ** 2 + (by - ay) ** 2, 1e-18), 0.0), 1.0)
        cx, cy = ax + t * (bx - ax), ay + t * (by - ay)
        for f in np.linspace(0.0, 1.0, 12):
            out.append(((x + f * (cx - x), y + f * (cy - y), a + f), segs))
    return out


def test_base_clearance_and_box_test_are_the_numpy_they_replaced():
    params = BaseParams()
    hl, hw = params.footprint_length / 2, params.footprint_width / 2
    touching = free = 0
    for pose, segs in _near_wall_poses():
        d = base_kernels.segment_distances(pose[0], pose[1], segs)
        np.testing.assert_array_equal(d, point_segment_distance(pose[:2], segs)[0])
        np.testing.assert_array_equal(d, jit.py_func(base_kernels.segment_distances)(pose[0], pose[1], segs))
        hits = np.flatnonzero(box_hits(pose, hl, hw, segs))
        first = base_kernels.box_first_hit(*pose, hl, hw, segs)
        assert first == (int(hits[0]) if len(hits) else -1)
        assert first == jit.py_func(base_kernels.box_first_hit)(*pose, hl, hw, segs)
        touching += first >= 0
        free += first < 0
    assert touching >= 8 and free >= 8


def test_transform_points_is_the_rotation_and_translation():
    rng = np.random.default_rng(0)
    for n in (0, 1, 7, 60):
        pts = rng.normal(size=(n, 2)) * 10
        pose = (float(rng.normal()), float(rng.normal()), float(rng.uniform(-4, 4)))
        c, s = math.cos(pose[2]), math.sin(pose[2])
        got = transform_points(pts, pose)
        # the matmul it replaced (whose BLAS may fuse a multiply-add: equal to the last bits)
        np.testing.assert_allclose(got, pts @ np.array([[c, -s], [s, c]]).T + np.array(pose[:2]), rtol=0, atol=1e-12)
        np.testing.assert_array_equal(got, jit.py_func(_rigid)(np.ascontiguousarray(pts), pose[0], pose[1], c, s))
        assert got.shape == (n, 2) and got.dtype == np.float64
    assert transform_points(np.array([1.0, 0.0]), (1.0, 2.0, math.pi / 2)).shape == (2,)
    np.testing.assert_allclose(transform_points(np.array([1.0, 0.0]), (1.0, 2.0, math.pi / 2)), [1.0, 3.0], atol=1e-15)
    assert transform_points(np.array([[1, 2]], dtype=np.float32), (0.0, 0.0, 0.0)).dtype == np.float64
