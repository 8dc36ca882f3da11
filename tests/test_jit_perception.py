"""The perceptor's compiled loops give the answers of their own Python (`.py_func`) on the very
arguments the perceptor passes them on real hospital_2019 scans: identify's while it follows
the robot, the scan stage's, the segmenters', the refit's and the corners' on scans processed
with the default parameters and with variants that take their other branches (merge's:
test_jit_merge.py)."""

from __future__ import annotations

import copy
import itertools
from typing import Any

import numpy as np
import pytest

from pico_studio import jit
from pico_studio.config import Config, with_value
from pico_studio.core.behaviours.registry import Drive
from pico_studio.core.perception import (
    Perceptor,
    corners,
    identify,
    map_proven,
    pcg64,
    scan,
    segment_angle,
    segment_ransac,
    segment_refit,
    segment_split_merge,
)
from pico_studio.core.perception.segment import segment_scan
from pico_studio.json_map import load_map
from pico_studio.session import Session
from pico_studio.sim import Simulator
from pico_studio.sim.sim_config import load_sim_config
from tests.conftest import MAPS
from tests.jit_scenes import hospital_frames, recorded_calls

KERNELS = {identify: ("small_objects", "junctions", "jamb_doors", "loose_gaps", "away_from"),
           map_proven: ("lone_cap_gaps",)}
# on restaurant_2024's tables and partitions (the hospital's turning scans see no bays and
# find no T-opening); group_spans, inside_corners, in_line_spans, wall_shaped and deep_sides judge the bays
# seen through
TABLE_KERNELS = {map_proven: ("bay_gaps",),
                 identify: ("t_openings", "group_spans", "inside_corners", "in_line_spans", "wall_shaped", "deep_sides")}


@pytest.fixture(scope="module")
def calls() -> dict[str, list[tuple]]:
    """Every call of each kernel while a perceptor follows the robot turning on the spot
    for 12 frames at each of 6 free poses (so the local map fuses, merges and connects walls
    it has seen before, and walls drop out of view)."""
    with recorded_calls(KERNELS) as recorded:
        cfg = Config()
        gmap = load_map(MAPS / "hospital_2019.json")
        for first, _, _ in hospital_frames(6):
            sim = Simulator(gmap, cfg.sim, seed=0, initial_pose=first.truth.pose)
            session = Session(sim, behaviour=Drive(0.05, 0.0, 0.4))
            p = Perceptor(cfg.perception)
            for _ in itertools.islice(session.frames(dt=0.05), 12):
                p.step(session.last_laser, session.last_odometry)
    return recorded


# fuse's sin, cos and atan2 are the C library's when compiled and numpy's own routines in its
# Python: they may differ in the last bit (a few 1e-16 m); every other kernel is bit-exact
ATOL = {"fuse": 1e-12}


def _same(a: Any, b: Any, atol: float = 0.0) -> None:
    a, b = (a if isinstance(a, tuple) else (a,)), (b if isinstance(b, tuple) else (b,))
    assert len(a) == len(b)
    for x, y in zip(map(np.asarray, a), map(np.asarray, b), strict=True):
        assert x.dtype == y.dtype and x.shape == y.shape
        if atol and x.dtype.kind == "f":
            np.testing.assert_allclose(x, y, rtol=0, atol=atol)
        else:
            np.testing.assert_array_equal(x, y)  # the same floats, to the last bit


def _answered_alike(kernel: Any, name: str, calls: list[tuple]) -> int:
    """Each recorded call answered by the kernel as by its Python (and its inputs moved alike);
    how many rows the answers held."""
    answered = 0
    for args in calls:
        mine, theirs = copy.deepcopy(args), copy.deepcopy(args)  # connect_walk, fuse move their inputs
        got = kernel(*mine)
        atol = ATOL.get(name, 0.0)
        _same(got, jit.py_func(kernel)(*theirs), atol)
        _same(mine, theirs, atol)  # and moves them alike
        answered += len(args[0]) if got is None else sum(len(x) for x in (got if isinstance(got, tuple) else (got,)))
    return answered


@pytest.mark.parametrize("module,name", [(m, n) for m, names in KERNELS.items() for n in names])
def test_kernel_equals_its_python_on_real_scans(calls: dict[str, list[tuple]], module: Any, name: str):
    assert calls[name], f"{name} was never called on the hospital scans"
    assert _answered_alike(getattr(module, name), name, calls[name]) > 0  # real work, not only empty inputs


def test_doors_found_on_real_scans(calls: dict[str, list[tuple]]):
    """The jamb doors' pipeline is not vacuous: on hospital scans some pairs are doors."""
    assert any(len(out[10]) for out in (identify.jamb_doors(*a) for a in calls["jamb_doors"]))


@pytest.fixture(scope="module")
def table_calls() -> dict[str, list[tuple]]:
    """Every call of the bays' and T-openings' kernels while a perceptor follows the robot turning among
    restaurant_2024's tables for 60 frames."""
    with recorded_calls(TABLE_KERNELS) as recorded:
        cfg = Config()
        sim = Simulator(load_map(MAPS / "restaurant_2024.json"), cfg.sim,
                        load_sim_config(MAPS / "restaurant_2024_sim.json"), seed=0)
        session = Session(sim, behaviour=Drive(0.05, 0.0, 0.4))
        p = Perceptor(cfg.perception)
        for _ in itertools.islice(session.frames(dt=0.05), 60):
            p.step(session.last_laser, session.last_odometry)
    return recorded


@pytest.mark.parametrize("module,name", [(m, n) for m, names in TABLE_KERNELS.items() for n in names])
def test_table_kernels_equal_their_python_on_real_scans(table_calls: dict[str, list[tuple]], module: Any, name: str):
    assert table_calls[name], f"{name} was never called on the restaurant scans"
    assert _answered_alike(getattr(module, name), name, table_calls[name]) > 0  # some found


SCAN_KERNELS = {scan: ("scan_points",), segment_split_merge: ("_douglas_peucker",), segment_angle: ("_walk",),
                segment_ransac: ("_extract",), segment_refit: ("finish_kernel",), corners: ("_spikes", "_vectors")}
# the defaults, and variants taking the other branches: grazing-angle breaks, no resampling, a
# footprint that drops points, the weighted refit with a range-dependent minimum of points
VARIANTS = {"default": {}, "grazing": {"perception.scan.grazing_factor": 10.0, "perception.scan.grazing_max_break": 1.0},
            "no_resampling": {"perception.scan.min_spacing": 0.0},
            "big_footprint": {"perception.proximity.footprint_length": 2.0, "perception.proximity.footprint_width": 2.0},
            "weighted": {"perception.scan.weighted_fit": True, "perception.scan.min_points_per_m": 2.0}}


@pytest.fixture(scope="module")
def scan_calls() -> tuple[dict[str, list[tuple]], dict[str, list]]:
    """Every call of the scan, segmenter, refit and corner kernels while 8 hospital scans are
    processed, segmented by each segmenter and searched for corners, per variant (and the
    scans made, per variant)."""
    made: dict[str, list] = {v: [] for v in VARIANTS}
    with recorded_calls(SCAN_KERNELS) as recorded:
        for variant, changes in VARIANTS.items():
            cfg = Config()
            for path, value in changes.items():
                cfg = with_value(cfg, path, value)
            for _, laser, _ in hospital_frames(8):
                for segmenter in ("split_merge", "angle", "ransac"):
                    p = with_value(cfg, "perception.scan.segmenter", segmenter).perception
                    s, _ = scan.process_scan(laser, p.scan, p.proximity)
                    segment_scan(s, p)
                made[variant].append(s)
                corners.spike_corners(s, p.corners)
                corners.vector_corners(s, p.corners, p.scan.min_spacing)
    return recorded, made


@pytest.mark.parametrize("module,name", [(m, n) for m, names in SCAN_KERNELS.items() for n in names])
def test_scan_and_segment_kernels_equal_their_python_on_real_scans(scan_calls: tuple, module: Any, name: str):
    recorded, _ = scan_calls
    assert len(recorded[name]) >= 8 * len(VARIANTS)
    answered = 0
    for args in recorded[name]:
        mine, theirs = copy.deepcopy(args), copy.deepcopy(args)
        got = getattr(module, name)(*mine)
        _same(got, jit.py_func(getattr(module, name))(*theirs))  # to the last bit
        _same(mine, theirs)
        answered += sum(np.size(x) for x in (got if isinstance(got, tuple) else (got,)))
    assert answered > 0


def test_the_scan_variants_take_their_branches(scan_calls: tuple):
    """The variants are not the defaults again: each changes what the scan stage returns."""
    _, made = scan_calls
    base = made["default"]
    assert all(len(s.points) > 200 and len(s.clusters) >= 2 for s in base)
    grazing = made["grazing"]  # grazing-angle spacing joins some clusters
    assert sum(len(g.clusters) for g in grazing) < sum(len(b.clusters) for b in base)
    assert all(len(k.points) == len(k.valid_xy) for k in made["no_resampling"])
    assert sum(f.valid.sum() for f in made["big_footprint"]) < sum(b.valid.sum() for b in base)
    # each cluster's ends: some seen, some not, and a point kept at both ends of every cluster
    seen = np.concatenate([s.end_seen.ravel() for s in base])
    assert seen.any() and not seen.all()
    for s in base:
        np.testing.assert_array_equal(s.beam[s.clusters[:, 0]] >= 0, True)
        assert (s.clusters[1:, 0] == s.clusters[:-1, 1]).all() and s.clusters[-1, 1] == len(s.points)


@pytest.mark.parametrize("compiled", [True, False])
def test_pcg64_draws_numpys_integers(compiled: bool):
    """RANSAC's draws made inside the compiled loop are numpy's `default_rng(seed).integers`,
    call after call, for bounds from 1 (no draw) to 2^32 (and so are those of its Python)."""
    integers = pcg64.integers if compiled else jit.py_func(pcg64.integers)
    bounds = np.random.default_rng(7).choice([1, 2, 3, 7, 100, 479, 1000, 2**31 + 11, 2**32 - 1, 2**32], size=200)
    for seed in (0, 1, 2**31 - 1):
        state, reference = pcg64.seeded_state(seed), np.random.default_rng(seed)
        for n in bounds.tolist():
            np.testing.assert_array_equal(integers(state, n, 5), reference.integers(0, n, size=5))
        assert pcg64.seeded_state(seed)[1] != state[1]  # the state advanced, the cached seed did not


def test_spikes_are_the_hypot_form_on_real_scans(scan_calls: tuple):
    """The spike kernel measures with cheap lengths, deciding by hypot when a comparison is
    too close to call: its corners are those of the formula with hypot, vectorised."""
    _, made = scan_calls
    c = Config().perception.corners
    found = 0
    for s in (s for scans in made.values() for s in scans):
        p = s.points
        r = np.hypot(p[:, 0], p[:, 1])
        gap = np.hypot(*(p[1:] - p[:-1]).T)
        near = np.where(r[:-1] <= r[1:], np.arange(len(p) - 1), np.arange(1, len(p)))
        hit = (gap > c.spike_gap) & (r[near] < c.spike_max_range)
        want = near[hit]
        want = want[np.append(True, want[1:] != want[:-1])]  # a point between two gaps once
        got = corners._spikes(np.ascontiguousarray(p), c.spike_gap, c.spike_max_range)
        np.testing.assert_array_equal(got, want)
        found += len(got)
    assert found > 20


@pytest.mark.parametrize("tol", [0.05, 0.35, 1.0])
def test_walk_and_vector_corners_decide_as_their_atan2_form(scan_calls: tuple, tol: float):
    """The angle walk and the vector corners test angles by dot products and take the atan2
    only near the threshold (a margin above rounding). With the margin made huge their Python
    takes the atan2 every time: the same walls and corners as the compiled loops."""
    _, made = scan_calls
    mp = pytest.MonkeyPatch()
    mp.setattr(segment_angle, "MARGIN", 10.0)
    mp.setattr(corners, "MARGIN", 1e300)
    try:
        walls = found = 0
        for s in made["default"]:
            pts, cl = np.ascontiguousarray(s.points), s.clusters
            got = segment_angle._walk(pts, cl, 6, tol)
            np.testing.assert_array_equal(got, jit.py_func(segment_angle._walk)(pts, cl, 6, tol))
            vec = corners._vectors(pts, cl, 6, tol)
            _same(vec, jit.py_func(corners._vectors)(pts, cl, 6, tol))
            walls, found = walls + len(got), found + len(vec[0])
        assert walls > 20 and found > 5
    finally:
        mp.undo()
