"""The truth's compiled queries (`sim.truth_kernels`) give the answers of the numpy/Python
they replaced (kept here, verbatim, as the reference) and of their own `.py_func`, on frames
of a wandering robot in hospital_2019 and restaurant_2024."""

from __future__ import annotations

import math
from functools import cache

import numpy as np
import pytest

from pico_studio import jit
from pico_studio.config import Config
from pico_studio.core.behaviours.registry import make_behaviour
from pico_studio.json_map import load_map
from pico_studio.session import Session
from pico_studio.sim import Simulator, truth_kernels
from pico_studio.sim.map_features import Vertices, classify_corners, corner_candidates, sector_width
from pico_studio.sim.raycast import cast_rays
from pico_studio.sim.truth import GroundTruth
from pico_studio.sim.world import KIND_DOOR
from tests.conftest import MAPS


# ----- the Python before compiling (the reference) ------------------------------------------
def reference_jamb_seen_length(truth: GroundTruth, jambs: np.ndarray) -> np.ndarray:
    t = truth._params
    xy, hits = truth._hit_points()
    walls = truth._world.walls
    out = np.zeros(len(jambs))
    on_wall = (hits >= 0) & (hits < len(walls))
    if not on_wall.any() or len(walls) == 0:
        return out
    xy, hits = xy[on_wall], hits[on_wall]
    a, ab = walls[:, 0:2], walls[:, 2:4] - walls[:, 0:2]
    length2 = np.maximum((ab * ab).sum(1), 1e-18)
    for j, p in enumerate(np.asarray(jambs, dtype=float).reshape(-1, 2)):
        u = np.clip(((p - a) * ab).sum(1) / length2, 0.0, 1.0)
        near = np.hypot(*(a + u[:, None] * ab - p).T) <= t.max_wall_thickness / 2 + 1e-3
        close = np.isin(hits, np.flatnonzero(near)) & (np.hypot(*(xy - p).T) <= t.jamb_reach)
        for k in np.unique(hits[close]):
            along = (xy[close & (hits == k)] - a[k]) @ ab[k] / math.sqrt(length2[k])
            out[j] += float(along.max() - along.min())
    return out


def reference_classify_corners(graph: Vertices, viewpoint: tuple[float, float], straight_tolerance: float):
    idx, convex, loose = [], [], []
    for v in corner_candidates(graph, straight_tolerance):
        dirs = graph.directions[v]
        p = graph.points[v]
        toward = math.atan2(viewpoint[1] - p[1], viewpoint[0] - p[0])
        w = sector_width(dirs, toward)
        if abs(w - math.pi) <= straight_tolerance:
            continue
        idx.append(v)
        convex.append(w > math.pi)
        loose.append(len(dirs) == 1)
    return np.array(idx, dtype=np.int64), np.array(convex, dtype=bool), np.array(loose, dtype=bool)


def reference_in_view(truth: GroundTruth, points: np.ndarray, segments: np.ndarray) -> np.ndarray:
    seen = truth._in_fov(points)
    if not seen.any():
        return seen
    x, y, _ = truth.pose
    d = points[seen] - (x, y)
    dist = np.hypot(d[:, 0], d[:, 1])
    free = cast_rays((x, y), np.arctan2(d[:, 1], d[:, 0]), segments)
    seen[seen] = free >= dist - truth._params.visible_tolerance
    return seen


def in_view_args(truth: GroundTruth) -> tuple:
    """`in_view`'s arguments for every vertex of the map against every segment, the
    numpy/`cast_rays` answer it replaced, and which vertices are in the field of view."""
    x, y, a = truth.pose
    p = truth._laser.profile
    points, segs = np.ascontiguousarray(truth._graph.points), np.ascontiguousarray(truth._world.segments())
    args = (points, float(x), float(y), float(a), float(p.range_max), float(p.angle_min), float(p.angle_max),
            segs, float(truth._params.visible_tolerance))
    return args, reference_in_view(truth, points, segs), truth._in_fov(points)


SECONDS = {"hospital_2019.json": 12.0, "restaurant_2024.json": 40.0}
MAP_NAMES = list(SECONDS)


def reference_visible_corners(truth: GroundTruth):
    idx, convex, loose = reference_classify_corners(truth._graph, truth.pose[:2], truth._params.straight_tolerance)
    pts = truth._graph.points[idx]
    seen = reference_in_view(truth, pts, truth._world.segments())
    return pts[seen], convex[seen], loose[seen]


def reference_visible_doors(truth: GroundTruth) -> np.ndarray:
    o = truth._openings
    if len(o) == 0:
        return o.copy()
    segs = truth._world.segments()
    not_doors = segs[truth._world.kinds() != KIND_DOOR]
    seen = reference_in_view(truth, (o[:, :2] + o[:, 2:]) / 2, not_doors)
    seen &= reference_jamb_seen_length(truth, o[:, :2]) >= truth._params.jamb_min_seen
    seen &= reference_jamb_seen_length(truth, o[:, 2:]) >= truth._params.jamb_min_seen
    return o[seen]


# ----- real frames ---------------------------------------------------------------------------
@cache
def wander_frames(map_name: str, every: int = 6) -> list[dict]:
    """Every `every`-th scan of a wandering robot: the truth's inputs and answers then (long
    enough for the robot to pass doors)."""
    seconds = SECONDS[map_name]
    cfg = Config()
    gmap = load_map(MAPS / map_name)
    sim = Simulator(gmap, cfg.sim, seed=1)
    behaviour = make_behaviour("wander", cfg.behaviour, gmap, initial_pose=sim.truth.pose)
    frames: list[dict] = []

    class Grab:
        name = "grab"
        scans = 0

        def on_frame(self, sf) -> None:
            if sf.frame.laser is None:
                return
            Grab.scans += 1
            if Grab.scans % every:
                return
            truth = sim.truth
            o = truth.door_openings()
            jambs = np.concatenate([o[:, :2], o[:, 2:]])
            frames.append({
                "jambs": jambs, "jamb_new": truth.jamb_seen_length(jambs),
                "jamb_ref": reference_jamb_seen_length(truth, jambs),
                "xy_hits": truth._hit_points(), "walls": truth._walls,
                "pose": truth.pose, "graph": truth._graph,
                "doors": truth.visible_doors(), "corners": truth.visible_corners(),
                "doors_ref": reference_visible_doors(truth), "corners_ref": reference_visible_corners(truth),
                "in_view_args": in_view_args(truth),
            })

        def summary(self) -> dict:
            return {}

    Session(sim, behaviour=behaviour, observers=[Grab()]).run(seconds, 0.05)
    return frames




@pytest.mark.parametrize("map_name", MAP_NAMES)
def test_jamb_seen_length_is_the_python_it_replaced(map_name: str):
    frames = wander_frames(map_name)
    assert frames
    seen = 0
    t = Config().sim.truth
    for f in frames:
        np.testing.assert_allclose(f["jamb_new"], f["jamb_ref"], rtol=1e-12, atol=1e-12)
        # the compiled loop and its own Python: the same floats
        xy, hits = f["xy_hits"]
        args = (np.ascontiguousarray(f["jambs"]), xy, np.ascontiguousarray(hits, dtype=np.int64), f["walls"],
                t.max_wall_thickness / 2 + 1e-3, float(t.jamb_reach))
        np.testing.assert_array_equal(truth_kernels.jamb_seen_lengths(*args),
                                      jit.py_func(truth_kernels.jamb_seen_lengths)(*args))
        seen += int((f["jamb_ref"] > 0).sum())
    assert seen >= 10  # the frames do see jambs


@pytest.mark.parametrize("map_name", MAP_NAMES)
def test_corner_classes_are_the_python_they_replaced(map_name: str):
    tol = Config().sim.truth.straight_tolerance
    frames = wander_frames(map_name)
    for f in frames:
        got = classify_corners(f["graph"], f["pose"][:2], tol)
        ref = reference_classify_corners(f["graph"], f["pose"][:2], tol)
        for x, y in zip(got, ref, strict=True):
            assert x.dtype == y.dtype
            np.testing.assert_array_equal(x, y)
        key = ("flat candidates", tol)
        points, cand, starts, dirs = f["graph"].cache[key]
        args = (points, cand, starts, dirs, float(f["pose"][0]), float(f["pose"][1]), tol)
        for x, y in zip(truth_kernels.corner_classes(*args), jit.py_func(truth_kernels.corner_classes)(*args),
                        strict=True):
            np.testing.assert_array_equal(x, y)
    assert sum(len(f["corners"].points) for f in frames) >= 10


@pytest.mark.parametrize("map_name", MAP_NAMES)
def test_whole_queries_are_the_python_they_replaced(map_name: str):
    """visible_doors and visible_corners (every compiled loop together) against the old code."""
    seen = hidden = 0
    for f in wander_frames(map_name):
        np.testing.assert_array_equal(f["doors"], f["doors_ref"])
        for x, y in zip(f["corners"], f["corners_ref"], strict=True):
            np.testing.assert_array_equal(x, y)
        args, ref, fov = f["in_view_args"]
        got = truth_kernels.in_view(*args)
        np.testing.assert_array_equal(got, ref)
        np.testing.assert_array_equal(got, jit.py_func(truth_kernels.in_view)(*args))
        seen += int(got.sum())
        hidden += int((fov & ~got).sum())
    assert seen >= 10 and hidden >= 10  # vertices in view and vertices in the field of view but occluded


def test_the_frames_see_doors():
    assert sum(len(f["doors"]) for f in wander_frames("hospital_2019.json")) >= 3
