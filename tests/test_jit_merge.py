"""Merge's compiled passes give the answers of their own Python on the very arguments the
perceptor passes them on real hospital_2019 scans, and the local map they build is the one
the all-Python merge builds; likewise the objects', entrance's and rooms' compiled loops."""

from __future__ import annotations

import copy
import itertools
from typing import Any

import numpy as np
import pytest

from pico_studio import jit
from pico_studio.config import Config
from pico_studio.core.behaviours.registry import Drive
from pico_studio.core.perception import Perceptor, entrance, merge, merge_kernels, objects, rooms
from pico_studio.core.perception.scan import process_scan
from pico_studio.core.perception.segment import segment_scan
from pico_studio.json_map import load_map
from pico_studio.session import Session
from pico_studio.sim import Simulator
from tests.conftest import MAPS
from tests.jit_scenes import hospital_frames, recorded_calls

PASSES = ("fold_in", "merge_similar", "see_through", "trim_through", "connect", "drop_mask", "compact", "shown_walls")
# fuse's sin, cos and atan2 (inside fold_in) are the C library's when compiled and numpy's
# own routines in its Python: they may differ in the last bit (a few 1e-16 m); every other
# pass is bit-exact
ATOL = {"fold_in": 1e-12}


def _turning_robot(frames: int = 20) -> list[Perceptor]:
    """A perceptor following the robot driving a tight circle from each of 6 free poses (so
    the local map fuses, merges and connects walls it has seen before, and walls drop out)."""
    cfg = Config()
    gmap = load_map(MAPS / "hospital_2019.json")
    out = []
    for first, _, _ in hospital_frames(6):
        sim = Simulator(gmap, cfg.sim, seed=0, initial_pose=first.truth.pose)
        session = Session(sim, behaviour=Drive(0.2, 0.0, 0.6))
        p = Perceptor(cfg.perception)
        for _ in itertools.islice(session.frames(dt=0.05), frames):
            p.step(session.last_laser, session.last_odometry)
        out.append(p)
    return out


@pytest.fixture(scope="module")
def calls() -> dict[str, list[tuple]]:
    """Every call of each pass while the robot turns."""
    with recorded_calls({merge: PASSES}) as recorded:
        _turning_robot()
    return recorded


def _same(a: Any, b: Any, atol: float = 0.0) -> None:
    a, b = (a if isinstance(a, tuple) else (a,)), (b if isinstance(b, tuple) else (b,))
    assert len(a) == len(b)
    for x, y in zip(a, b, strict=True):
        if not isinstance(x, np.ndarray):
            assert x == y
            continue
        assert x.dtype == y.dtype and x.shape == y.shape
        if atol and x.dtype.kind == "f":
            np.testing.assert_allclose(x, y, rtol=0, atol=atol)
        else:
            np.testing.assert_array_equal(x, y)  # the same floats, to the last bit


@pytest.mark.parametrize("name", PASSES)
def test_pass_equals_its_python_on_real_scans(calls: dict[str, list[tuple]], name: str):
    compiled = getattr(merge, name)
    assert calls[name], f"{name} was never called on the hospital scans"
    answered = 0
    for args in calls[name]:
        mine, theirs = copy.deepcopy(args), copy.deepcopy(args)  # passes move their inputs in place
        got = compiled(*mine)
        with jit.uncompiled():  # the pass and every kernel it calls as plain Python
            want = getattr(merge, name)(*theirs)
        atol = ATOL.get(name, 0.0)
        _same(got, want, atol)
        _same(mine, theirs, atol)  # and moves them alike
        answered += len(args[0]) if got is None else sum(np.size(x) for x in (got if isinstance(got, tuple) else (got,)))
    assert answered > 0  # real work, not only empty inputs


def test_passes_do_real_work(calls: dict[str, list[tuple]]):
    """Not vacuous: on the hospital scans walls are fused, connected and dropped (merged:
    below, they rarely are on these short runs)."""
    fused = [fold_args for fold_args in calls["fold_in"] if len(fold_args[0]) and len(fold_args[6])]
    assert any((merge_kernels.associate(a[0], a[6], a[10], a[11], a[12]) >= 0).any() for a in fused)
    assert any((merge.connect(*copy.deepcopy(a))[0] >= 0).any() for a in calls["connect"])
    assert any(not merge.drop_mask(*a).all() for a in calls["drop_mask"])


def _split(args: tuple) -> tuple:
    """merge_similar's arguments with every wall also seen as a second piece: its far half,
    1 cm off its line, seen once — what a wall seen in two pieces leaves in the local map."""
    walls, hits, last_seen, missed, seen_end, end_weight, viewpoint, *rest = copy.deepcopy(args)
    d = walls[:, 2:4] - walls[:, 0:2]
    normal = np.column_stack([-d[:, 1], d[:, 0]]) / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-12)[:, None]
    half = np.hstack([walls[:, 0:2] + 0.5 * d, walls[:, 2:4] + 0.1 * d]) + 0.01 * np.hstack([normal, normal])
    k = len(walls)
    return (np.vstack([walls, half]), np.concatenate([hits, np.ones(k)]), np.concatenate([last_seen, last_seen]),
            np.concatenate([missed, np.zeros(k, dtype=np.int64)]), np.vstack([seen_end, seen_end]),
            np.vstack([end_weight, np.zeros((k, 2))]), np.vstack([viewpoint, viewpoint + 1.0]), *rest)


def test_walls_seen_in_two_pieces_merge_alike(calls: dict[str, list[tuple]]):
    """Real local maps with every wall doubled by an overlapping piece: the pieces are
    absorbed (fewer walls), compiled as in the all-Python merge."""
    merged = 0
    for args in calls["merge_similar"][::10]:
        split = _split(args)
        got = merge.merge_similar(*copy.deepcopy(split))
        with jit.uncompiled():
            want = merge.merge_similar(*copy.deepcopy(split))
        _same(got, want)
        merged += len(split[0]) - len(got[0])
    assert merged > 0


def test_local_map_equals_the_all_python_merge():
    """The whole run's local maps, compiled vs every loop as its Python: the same walls."""
    fast = _turning_robot(10)
    with jit.uncompiled():
        slow = _turning_robot(10)
    for a, b in zip(fast, slow, strict=True):
        sa, sb = a.state.local_map, b.state.local_map
        assert len(sa.walls) > 0
        np.testing.assert_allclose(sa.walls, sb.walls, rtol=0, atol=1e-9)
        for field in ("hits", "last_seen", "missed", "seen_end", "connected"):
            np.testing.assert_array_equal(getattr(sa, field), getattr(sb, field))


def test_small_stages_equal_their_python_on_real_scans():
    """Objects' candidate boxes, the entrance and the side room's beams: compiled as in
    their Python, scan by scan of the circling robot (and some found)."""
    cfg = Config().perception
    seen = {"objects": 0, "entrance": 0, "side": 0, "edges": 0}
    for _, laser, _ in hospital_frames(6):
        scan, _ = process_scan(laser, cfg.scan, cfg.proximity)
        segs = segment_scan(scan, cfg)
        args = (scan.points, scan.clusters, scan.end_seen, cfg.objects.min_points, cfg.objects.max_size, 0.3, -0.2, 0.7,
                cfg.objects.partly_hidden)
        _same(objects.candidate_boxes(*args), jit.py_func(objects.candidate_boxes)(*args))
        seen["objects"] += len(objects.candidate_boxes(*args)[0])
        e = cfg.entrance
        eargs = (np.ascontiguousarray(segs.segments), e.parallel_tolerance, e.min_gap, e.max_gap,
                 e.hallway_min_width, e.hallway_max_width)
        got, want = entrance.scan_entrance(*eargs), jit.py_func(entrance.scan_entrance)(*eargs)
        assert got[0] == want[0] and got[1:] == pytest.approx(want[1:], abs=1e-12)  # atan2: libm vs numpy
        seen["entrance"] += got[0] != 0
        r = cfg.rooms
        for side in (r.side_angle, -r.side_angle, 0.0):
            rargs = (scan.ranges, scan.angles, scan.valid, side)
            _same(rooms._side_beam(*rargs), jit.py_func(rooms._side_beam)(*rargs))
            seen["side"] += not np.isnan(rooms._side_beam(*rargs))
            eargs2 = (*rargs, r.content_half_angle, r.edge_jump, r.edge_skip)
            _same(rooms._edges(*eargs2), jit.py_func(rooms._edges)(*eargs2))
            seen["edges"] += rooms._edges(*eargs2)
    assert all(seen.values()), seen
