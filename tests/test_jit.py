"""The compiled loops: where their cache lives, that every one is warmed up, and that each
gives the answers of its own Python (`.py_func`) on real scans of hospital_2019."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from pico_studio import jit
from pico_studio.config import Config
from pico_studio.core.perception import (
    segment_angle,
    segment_ransac,
    segment_refit,
    segment_split_merge,
)
from pico_studio.core.perception.scan import process_scan
from tests.jit_scenes import hospital_scans

PACKAGE = Path(jit.__file__).resolve().parent
P = Config().perception


def test_every_module_with_a_kernel_is_warmed_up():
    users = {
        ".".join(f.relative_to(PACKAGE.parent).with_suffix("").parts)
        for f in PACKAGE.rglob("*.py")
        if f.name != "jit.py" and re.search(r"^from pico_studio\.jit import .*\bkernel\b", f.read_text(), re.M)
    }
    assert users == set(jit.KERNEL_MODULES)
    assert len(jit.kernels()) >= len(users)


def test_cache_folder_rules(tmp_path: Path):
    writable = tmp_path / "pkg"
    digest = jit.source_digest(jit.kernel_sources(writable))
    assert jit.choose_cache_dir({"NUMBA_CACHE_DIR": "/x"}, writable) == "/x"
    assert jit.choose_cache_dir({"PICO_STUDIO_CACHE": "/y"}, writable) == str(Path("/y") / "numba" / digest)
    assert jit.choose_cache_dir({}, writable) == str(writable / "__pycache__" / "numba" / digest)  # beside the sources
    # a package folder nothing can be written in (below a file: fails even for root)
    blocker = tmp_path / "file"
    blocker.write_text("")
    got = jit.choose_cache_dir({"XDG_CACHE_HOME": str(tmp_path / "xdg")}, blocker / "pkg")
    assert got == str(tmp_path / "xdg" / "pico_studio" / "numba" / jit.source_digest(jit.kernel_sources(blocker / "pkg")))
    # and no writable user cache either: a per-user folder in the temp directory
    got = jit.choose_cache_dir({"XDG_CACHE_HOME": str(blocker / "xdg")}, blocker / "pkg")
    assert got is not None and Path(got).parent.name == "numba" and Path(got).is_dir()


def test_changed_kernel_code_gets_a_cache_of_its_own(tmp_path: Path):
    """numba checks a cached kernel against its own file only: a helper changed in another
    module would run old (numba/numba#1833). The folder is named by every kernel module's code."""
    import os
    import time

    pkg = tmp_path / "pkg"
    for f in jit.kernel_sources(pkg):
        f.parent.mkdir(parents=True, exist_ok=True)
        f.write_text("x = 1\n")
    before = jit.choose_cache_dir({}, pkg)
    helper = pkg / "core" / "perception" / "identify_kernels.py"  # a helper's module, not its caller's
    helper.write_text("x = 2\n")
    after = jit.choose_cache_dir({}, pkg)
    assert before is not None and after is not None and before != after
    Path(before).mkdir(parents=True)  # (numba makes them as it writes)
    Path(after).mkdir(parents=True)
    jit.choose_cache_dir({}, pkg)
    assert Path(before).is_dir()  # a day old, and only then, the other version's folder goes
    old = time.time() - 2 * 86400
    os.utime(before, (old, old))
    helper.write_text("x = 3\n")
    newest = jit.choose_cache_dir({}, pkg)
    assert newest is not None and not Path(before).exists() and Path(after).is_dir()


@pytest.fixture(scope="module")
def scans() -> list:
    return [process_scan(laser, P.scan, P.proximity)[0] for laser in hospital_scans(12)]


def _same(a: tuple | np.ndarray, b: tuple | np.ndarray) -> None:
    for x, y in zip(a if isinstance(a, tuple) else (a,), b if isinstance(b, tuple) else (b,), strict=True):
        assert x.dtype == y.dtype and x.shape == y.shape
        np.testing.assert_allclose(x, y, rtol=0, atol=1e-12)


def test_segmenters_compiled_equal_their_python(scans: list):
    for s in scans:
        pts, cl = np.ascontiguousarray(s.points), s.clusters.astype(np.int64)
        pts32 = pts.astype(np.float32)
        eps = P.split_merge.split_distance
        _same(segment_split_merge._douglas_peucker(pts32, cl, eps), jit.py_func(segment_split_merge._douglas_peucker)(pts32, cl, eps))
        a = P.angle
        _same(segment_angle._walk(pts, cl, a.lookahead, a.angle_tolerance),
              jit.py_func(segment_angle._walk)(pts, cl, a.lookahead, a.angle_tolerance))
        r = P.ransac
        args = (r.iterations, r.inlier_distance, r.max_gap_points)
        _same(segment_ransac._extract(pts, cl, segment_ransac.seeded_state(r.seed), *args),
              jit.py_func(segment_ransac._extract)(pts, cl, segment_ransac.seeded_state(r.seed), *args))


def test_split_is_opencvs_douglas_peucker(scans: list):
    """The compiled split returns exactly the vertices cv2.approxPolyDP finds (the earlier
    production path), on real scans and on random noisy polylines."""
    for s in scans:
        np.testing.assert_array_equal(segment_split_merge.split(s.points, s.clusters, P.split_merge),
                                      segment_split_merge.split_opencv(s.points, s.clusters, P.split_merge))
    rng = np.random.default_rng(1)
    for _ in range(100):
        pts = np.cumsum(rng.normal(size=(int(rng.integers(3, 150)), 2)) * 0.05, axis=0)
        cl = np.array([[0, len(pts)]])
        np.testing.assert_array_equal(segment_split_merge.split(pts, cl, P.split_merge),
                                      segment_split_merge.split_opencv(pts, cl, P.split_merge))


def test_finish_compiled_equals_its_python(scans: list):
    sp = P.scan
    for s in scans:
        pieces = segment_split_merge.split(s.points, s.clusters, P.split_merge)
        args = (np.ascontiguousarray(s.points), pieces, s.clusters.astype(np.int64), s.end_seen,
                sp.merge_angle, sp.min_points, sp.min_length, sp.max_rms, sp.seen_margin, sp.seen_points)
        got = segment_refit.finish_kernel(*args)
        assert len(got[0]) >= 3  # real walls came out
        _same(got, jit.py_func(segment_refit.finish_kernel)(*args))


def test_corners_and_laser_motion_compiled_equal_their_python(scans: list):
    from pico_studio.core.perception import corners, laser_motion

    c = P.corners
    k = max(1, int(round(c.vector_step / max(P.scan.min_spacing, 1e-3))))
    found = 0
    previous = None
    for s in scans:
        pts = np.ascontiguousarray(s.points)
        _same(corners._spikes(pts, c.spike_gap, c.spike_max_range), jit.py_func(corners._spikes)(pts, c.spike_gap, c.spike_max_range))
        args = (pts, s.clusters.astype(np.int64), k, c.vector_tolerance)
        got = corners._vectors(*args)
        _same(got, jit.py_func(corners._vectors)(*args))
        found += len(got[0])
        now = pts[got[0]]
        if previous is not None and len(previous) and len(now):
            # the same corners seen from a little further on: a real match and fit
            margs = (previous, previous @ np.array([[0.999, 0.04], [-0.04, 0.999]]) + 0.02, 0.0, 0.0, 0.0, 0.3, 5)
            assert laser_motion._match_and_fit(*margs) == jit.py_func(laser_motion._match_and_fit)(*margs)
            assert laser_motion._match_and_fit(*margs)[3] == len(previous)
        previous = now
    assert found > 10


def test_matcher_compiled_equals_its_python():
    """Refinement, quality and beams-through-walls on real hospital scans from a disturbed
    pose: the compiled loops give their Python's answers, and the refinement finds the pose."""
    from pico_studio.core.localisation import match_kernels as mk
    from pico_studio.core.localisation.distance_field import DistanceField
    from pico_studio.core.localisation.matcher import usable_points
    from tests.jit_scenes import hospital_frames

    frames = hospital_frames(6)
    cfg = Config().localisation
    f = DistanceField.from_segments(frames[0][0].world.segments(), resolution=cfg.field.resolution, margin=cfg.field.margin)
    m = cfg.matcher
    grid = (f.field, f.segment_index, f.x0, f.y0, f.resolution, f.segments, f.normals)
    for sim, laser, _ in frames:
        pts = np.ascontiguousarray(usable_points(laser.points, m.max_range))
        x, y, a = sim.truth.pose
        start = (x + 0.08, y - 0.05, a + 0.04)
        args = (*grid, np.ascontiguousarray(pts[:: m.beam_stride]), *start, m.iterations, m.outlier_distance,
                m.final_outlier_distance, m.huber, m.inlier_distance)
        got = mk.refine_kernel(*args)
        assert got == jit.py_func(mk.refine_kernel)(*args)
        assert abs(got[0] - x) < 0.03 and abs(got[1] - y) < 0.03
        q = (f.field, f.x0, f.y0, f.resolution, pts, got[0], got[1], got[2], m.inlier_distance)
        assert mk.quality_kernel(*q) == jit.py_func(mk.quality_kernel)(*q) > 0.5
        passable = np.zeros(len(f.segments), dtype=bool)
        t = (f.segment_index, f.x0, f.y0, f.resolution, f.segments, f.normals, passable, pts[::8],
             m.ray_step, m.ray_clearance, x + 0.4, y, a + 0.3)
        assert mk.through_kernel(*t) == jit.py_func(mk.through_kernel)(*t)
        coarse = f.coarse(4, 0.3, 40)
        offs = np.random.default_rng(0).integers(-30, 30, size=(3, 40, 2))
        _same(mk.coarse_scores(coarse, offs, 40, 40, 20, 25), jit.py_func(mk.coarse_scores)(coarse, offs, 40, 40, 20, 25))
        xy = np.ascontiguousarray(pts[:50] + (x, y))
        _same(mk.field_distance(f.field, f.x0, f.y0, f.resolution, xy),
              jit.py_func(mk.field_distance)(f.field, f.x0, f.y0, f.resolution, xy))
        _same(mk.field_nearest(f.segment_index, f.x0, f.y0, f.resolution, xy),
              jit.py_func(mk.field_nearest)(f.segment_index, f.x0, f.y0, f.resolution, xy))


def test_whole_perceptor_and_localiser_give_the_same_answers_uncompiled():
    """The perceptor and the localiser on real scans, once compiled and once with every
    kernel swapped for its Python (`jit.uncompiled`): the same world models and poses."""
    from pico_studio.core.localisation import Localiser
    from pico_studio.core.perception import Perceptor
    from tests.jit_scenes import hospital_frames

    cfg = Config()
    frames = hospital_frames(3)
    gmap = frames[0][0].world.map

    def run() -> list:
        out = []
        for sim, laser, odom in frames:
            wm = Perceptor(cfg.perception).step(laser, odom).to_dict()
            wm.pop("timings_ms")
            loc = Localiser(cfg.localisation, gmap, initial_pose=sim.truth.pose)
            out.append((wm, loc.step(laser.points, (0.0, 0.0, 0.0)).pose))
        return out

    fast = run()
    with jit.uncompiled():
        assert segment_refit.finish_kernel is jit.py_func(segment_refit.finish_kernel)
        slow = run()
    assert segment_refit.finish_kernel is not jit.py_func(segment_refit.finish_kernel)
    assert [w for w, _ in fast] == [w for w, _ in slow]  # plain data: bit for bit
    assert all(len(w["current_map"]) >= 3 for w, _ in fast)
    for (_, a), (_, b) in zip(fast, slow, strict=True):
        assert a is not None and np.allclose(a, b, rtol=0, atol=1e-12)


def test_wall_coverage_is_the_sampled_coverage_of_the_scoring():
    """The compiled wall coverage against the scoring's numpy sampling + `covered`, on the
    simulator's visible walls and a perceived local map of real hospital frames."""
    from pico_studio.core.geometry import transform_segments
    from pico_studio.core.perception import Perceptor
    from pico_studio.evaluation import frame_score as scoring
    from pico_studio.evaluation import score_kernels as sk
    from tests.jit_scenes import hospital_frames

    tol = scoring.Tolerances()
    checked = 0
    for sim, laser, odom in hospital_frames(6):
        wm = Perceptor(Config().perception).step(laser, odom)
        walls = transform_segments(np.asarray(wm.local_map.walls, dtype=float), scoring.zero_to_map(wm, sim.truth.pose))
        for segs, targets in ((walls, sim.truth.segments()), (sim.truth.visible_walls(), walls)):
            segs, targets = np.ascontiguousarray(segs), np.ascontiguousarray(targets)
            pts, owner, weight = scoring._samples(segs, tol.sample_step)
            ok = scoring.covered(pts, scoring._dirs(segs)[owner], targets, tol)
            args = (segs, tol.sample_step, targets, tol.wall_distance, math.cos(tol.wall_angle))
            got = sk.wall_coverage(*args)
            assert got == jit.py_func(sk.wall_coverage)(*args)
            np.testing.assert_allclose(got, (weight.sum(), weight[ok].sum()), rtol=1e-12)
            checked += ok.sum() > 0
    assert checked >= 6


def test_raycast_compiled_equals_its_python_and_the_plain_ray_test():
    from pico_studio.json_map.openings import cast_rays
    from pico_studio.sim import raycast
    from tests.jit_scenes import hospital_frames

    frames = hospital_frames(4)
    segs = np.ascontiguousarray(frames[0][0].world.segments())
    fan = raycast.Fan(-2.0, 4.0 / 999, 1000)
    for sim, _, _ in frames:
        x, y, a = sim.truth.pose
        args = (segs, x, y, math.cos(a), math.sin(a), fan.turn, fan.angle_min, fan.increment,
                fan._top, fan._bottom, fan._half_turn)
        ranges, hits = raycast._cast(*args)
        _same((ranges, hits), jit.py_func(raycast._cast)(*args))
        # the plain (rays x segments) test agrees on every tenth beam
        angles = a + fan.angle_min + np.arange(0, 1000, 10) * fan.increment
        np.testing.assert_allclose(ranges[::10], cast_rays((x, y), angles, segs), rtol=1e-9)
        assert (hits[np.isfinite(ranges)] >= 0).all()


def test_scan_on_line_equals_its_python_and_the_vectorised_form(scans: list):
    from pico_studio.core.perception.scan_kernels import on_line

    d = P.scan.grazing_line_distance
    for s in scans:
        xy = np.ascontiguousarray(s.valid_xy)
        got = on_line(xy, d)
        _same(got, jit.py_func(on_line)(xy, d))
        m = len(xy)
        i = np.arange(m - 1)

        def dist(a: np.ndarray, b: np.ndarray, q: np.ndarray) -> np.ndarray:
            u = b - a
            n = np.hypot(u[:, 0], u[:, 1])
            off = np.abs(u[:, 0] * (q - a)[:, 1] - u[:, 1] * (q - a)[:, 0]) / np.maximum(n, 1e-12)
            return np.where(n > 1e-6, off, np.inf)

        fwd = (dist(xy[np.maximum(i - 3, 0)], xy[i], xy[i + 1]) <= d) & (i >= 3)
        bwd = (dist(xy[np.minimum(i + 4, m - 1)], xy[i + 1], xy[i]) <= d) & (i + 4 <= m - 1)
        np.testing.assert_array_equal(got[0], fwd)
        np.testing.assert_array_equal(got[1], bwd)
        assert got[0].sum() > 100  # most neighbours of a wall are on its line


def test_combined_map_and_tracker_loops_compiled_equal_their_python():
    """Every call of the combined map's and the tracker's loops (walls on the map, doors the
    map confirms, usable points, seen-wall counts) during a localising run on hospital_2019:
    compiled as in their Python, and not vacuous (walls matched, doors confirmed, hits)."""
    from pico_studio.core import geometry
    from pico_studio.core.behaviours.registry import Drive
    from pico_studio.core.localisation import (
        combined,
        combined_kernels,
        match_kernels,
        matcher,
        tracker,
    )
    from pico_studio.core.localisation.stage import LocalisingPerceptor
    from pico_studio.evaluation.runner import make_perceptor
    from pico_studio.session import Session
    from pico_studio.sim import Simulator
    from tests.jit_scenes import hospital_frames, recorded_calls

    names = {combined: ("on_map_kernel", "door_matches"), matcher: ("usable_kernel",), tracker: ("seen_hits_kernel",)}
    cfg = Config()
    with recorded_calls(names) as calls:
        first = hospital_frames(1)[0][0]
        sim = Simulator(first.world.map, cfg.sim, seed=0, initial_pose=first.truth.pose)
        perceptor = make_perceptor(cfg, sim.world.map, first.truth.pose, localise=True)
        assert isinstance(perceptor, LocalisingPerceptor)
        for _ in Session(sim, perceptor=perceptor, behaviour=Drive(0.3, 0.0, 0.2)).frames(until=1.5):
            pass
    kernels = {"on_map_kernel": combined_kernels.walls_on_map, "door_matches": geometry.door_matches,
               "usable_kernel": match_kernels.usable_kernel, "seen_hits_kernel": match_kernels.seen_hits_kernel}
    found = {}
    for n, k in kernels.items():
        assert calls[n], n
        outs = [k(*args) for args in calls[n]]
        for args, got in zip(calls[n], outs, strict=True):
            _same(got, jit.py_func(k)(*args))
        found[n] = sum(int(np.sum(o)) for o in outs)
    assert all(found.values()), found  # walls on the map, doors confirmed, points kept, walls hit


def test_search_takes_the_best_grid_poses_in_a_stable_order():
    """The pose search's best-first order (a partial sort) is a stable argsort's first k,
    ties and NaN included."""
    from pico_studio.core.localisation.matcher import best_first

    rng = np.random.default_rng(3)
    for shape, k in (((4, 30, 40), 300), ((2, 5, 5), 50), ((3, 7, 9), 500), ((1, 1, 1), 5)):
        scores = np.round(rng.random(shape), 2).astype(np.float32)  # many ties
        scores.flat[rng.integers(0, scores.size, 3)] = np.nan
        want = np.argsort(scores, axis=None, kind="stable")[:k]
        np.testing.assert_array_equal(best_first(scores, k), want)
