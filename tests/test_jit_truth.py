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
from pico_studio.json_map.openings import Vertices, cast_rays, sector_width
from pico_studio.session import Session
from pico_studio.sim import Simulator, truth_kernels
from pico_studio.sim.map_features import classify_corners, corner_candidates
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
        near = np.hypot(*(a + u[:, None] * ab - p).T) <= truth._world.map.opening_params.max_wall_thickness / 2 + 1e-3
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


def corners_args(truth: GroundTruth) -> tuple:
    """`corners_in_view`'s arguments now (the candidate corners classified from the pose)."""
    idx, convex, loose = classify_corners(truth._graph, truth.pose[:2], truth._params.straight_tolerance)
    return (np.ascontiguousarray(truth._graph.points), idx, convex, loose, *truth._view(),
            np.ascontiguousarray(truth._world.segments()), float(truth._params.visible_tolerance))


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
    seen &= ~truth._shut((o[:, :2] + o[:, 2:]) / 2)  # plain Python in both: no door leaf shut across it
    return o[seen]


def reference_hit_points(truth: GroundTruth) -> tuple[np.ndarray, np.ndarray]:
    laser = truth._laser
    pose = laser.last_pose
    n = len(laser.true_hits)
    angles = laser.fan.angle_min + np.arange(n) * laser.fan.increment + pose[2]
    r = laser.true_ranges
    return np.column_stack([pose[0] + r * np.cos(angles), pose[1] + r * np.sin(angles)]), laser.true_hits


def reference_visible_pieces(truth: GroundTruth) -> tuple[np.ndarray, np.ndarray]:
    xy, hits = reference_hit_points(truth)
    n = len(hits)
    change = np.flatnonzero(np.diff(hits) != 0) + 1
    starts = np.concatenate([[0], change])
    stops = np.concatenate([change, [n]]) - 1
    keep = (hits[starts] >= 0) & (stops - starts + 1 >= truth._params.min_wall_beams)
    starts, stops = starts[keep], stops[keep]
    return np.column_stack([xy[starts], xy[stops]]), hits[starts]


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
                "xy_hits": truth._hit_points(), "walls": truth._walls, "scan": truth._scan(),
                "hit_points_ref": reference_hit_points(truth), "pieces": truth._visible_pieces(),
                "pieces_ref": reference_visible_pieces(truth),
                "pose": truth.pose, "graph": truth._graph,
                "doors": truth.visible_doors(), "corners": truth.visible_corners(),
                "doors_ref": reference_visible_doors(truth), "corners_ref": reference_visible_corners(truth),
                "in_view_args": in_view_args(truth), "corners_args": corners_args(truth),
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
        args = (np.ascontiguousarray(f["jambs"]), *f["scan"], f["walls"], Config().map.openings.max_wall_thickness / 2 + 1e-3,
                float(t.jamb_reach))
        np.testing.assert_array_equal(truth_kernels.jamb_seen_lengths(*args),
                                      jit.py_func(truth_kernels.jamb_seen_lengths)(*args))
        seen += int((f["jamb_ref"] > 0).sum())
    assert seen >= 10  # the frames do see jambs


@pytest.mark.parametrize("map_name", MAP_NAMES)
def test_hit_points_and_visible_pieces_are_the_numpy_they_replaced(map_name: str):
    min_beams = Config().sim.truth.min_wall_beams
    pieces = 0
    for f in wander_frames(map_name):
        for got, ref in zip(f["xy_hits"], f["hit_points_ref"], strict=True):
            np.testing.assert_array_equal(got, ref)
        for got, ref in zip(f["pieces"], f["pieces_ref"], strict=True):
            np.testing.assert_array_equal(got, ref)
            assert got.dtype == ref.dtype
        scan = f["scan"]
        np.testing.assert_array_equal(truth_kernels.beam_ends(*scan[:6]), jit.py_func(truth_kernels.beam_ends)(*scan[:6]))
        for got, ref in zip(truth_kernels.hit_runs(*scan, min_beams), jit.py_func(truth_kernels.hit_runs)(*scan, min_beams),
                            strict=True):
            np.testing.assert_array_equal(got, ref)
        pieces += len(f["pieces"][0])
    assert pieces >= 50


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
        fast, slow = truth_kernels.corners_in_view(*f["corners_args"]), jit.py_func(truth_kernels.corners_in_view)(*f["corners_args"])
        for x, y, ref in zip(fast, slow, f["corners_ref"], strict=True):
            np.testing.assert_array_equal(x, y)
            np.testing.assert_array_equal(x, ref)
            assert x.dtype == ref.dtype
    assert seen >= 10 and hidden >= 10  # vertices in view and vertices in the field of view but occluded


def test_the_frames_see_doors():
    assert sum(len(f["doors"]) for f in wander_frames("hospital_2019.json")) >= 3


# ----- scoring's compiled loops (evaluation/score_kernels) -----------------------------------
def reference_match_points(a: np.ndarray, b: np.ndarray, radius: float) -> list[tuple[int, int]]:
    if len(a) == 0 or len(b) == 0:
        return []
    d = np.hypot(*(a[:, None, :] - b[None, :, :]).transpose(2, 0, 1))
    pairs: list[tuple[int, int]] = []
    used_a, used_b = set(), set()
    for flat in np.argsort(d, axis=None, kind="stable").tolist():
        i, j = divmod(flat, len(b))
        if d[i, j] > radius:
            break
        if i in used_a or j in used_b:
            continue
        pairs.append((i, j))
        used_a.add(i)
        used_b.add(j)
    return pairs


def reference_doors_match(found: np.ndarray, truth: np.ndarray, tol) -> np.ndarray:
    def dirs(segments: np.ndarray) -> np.ndarray:
        d = segments[:, 2:4] - segments[:, 0:2]
        return d / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-12)[:, None]

    if len(found) == 0 or len(truth) == 0:
        return np.zeros((len(found), len(truth)), dtype=bool)
    mf = (found[:, 0:2] + found[:, 2:4]) / 2
    mt = (truth[:, 0:2] + truth[:, 2:4]) / 2
    close = np.hypot(*(mf[:, None, :] - mt[None, :, :]).transpose(2, 0, 1)) <= tol.door_distance
    parallel = np.abs(dirs(found) @ dirs(truth).T) >= math.cos(tol.door_angle)
    return close & parallel


@cache
def perceived_frames() -> list[tuple]:
    """(map-frame corners, doors, local-map wall ends, truth) of a perceptor on real frames."""
    from pico_studio.core.geometry import transform_points, transform_segments
    from pico_studio.core.perception import Perceptor
    from pico_studio.evaluation.frame_score import zero_to_map
    from tests.jit_scenes import hospital_frames

    out = []
    for sim, laser, odom in hospital_frames(8):
        wm = Perceptor(Config().perception).step(laser, odom)
        z = zero_to_map(wm, sim.truth.pose)
        corners = np.ascontiguousarray(transform_points(np.asarray(wm.corners, dtype=float).reshape(-1, 2), z))
        doors = np.ascontiguousarray(transform_segments(np.asarray(wm.doors, dtype=float).reshape(-1, 4), z))
        ends = np.ascontiguousarray(transform_segments(np.asarray(wm.local_map.walls, dtype=float), z).reshape(-1, 2))
        out.append((corners, doors, ends, sim.truth))
    return out


def test_corner_pairs_are_the_python_they_replaced():
    from pico_studio.evaluation import score_kernels as sk
    from pico_studio.evaluation.frame_score import Tolerances, match_points

    radius = Tolerances().corner_distance
    paired = 0
    for corners, _, _, truth in perceived_frames():
        seen = np.ascontiguousarray(truth.visible_corners().points)
        for a, b, r in ((corners, seen, radius), (corners, seen, 1.0), (seen, corners, 3.0)):
            ref = reference_match_points(a, b, r)
            assert match_points(a, b, r) == ref
            ia, ib = sk.match_nearest(a, b, r)
            pa, pb = jit.py_func(sk.match_nearest)(a, b, r)
            np.testing.assert_array_equal(ia, pa)
            np.testing.assert_array_equal(ib, pb)
            paired += len(ref)
    assert paired >= 30
    # equal distances: taken in (i, j) order (the stable sort), the same compiled and not
    a, b = np.array([[0.0, 0.0], [2.0, 0.0]]), np.array([[1.0, 0.0]])
    assert match_points(a, b, 1.5) == [(0, 0)] == reference_match_points(a, b, 1.5)
    assert [p.tolist() for p in jit.py_func(sk.match_nearest)(a, b, 1.5)] == [[0], [0]]


def test_door_matches_and_nearest_vertices_are_the_numpy_they_replaced():
    from pico_studio.core.geometry import door_matches, pairwise_distances
    from pico_studio.evaluation import score_kernels as sk
    from pico_studio.evaluation.frame_score import Tolerances, doors_match

    tol = Tolerances()
    cos_angle = math.cos(tol.door_angle)
    matched = 0
    for corners, doors, ends, truth in perceived_frames():
        openings = np.ascontiguousarray(truth.door_openings())
        for found, true in ((doors, openings), (openings, openings), (openings[:, [2, 3, 0, 1]].copy(), openings)):
            ref = reference_doors_match(found, true, tol)
            np.testing.assert_array_equal(doors_match(found, true, tol), ref)
            args = (found, true, tol.door_distance, cos_angle)
            np.testing.assert_array_equal(door_matches(*args), jit.py_func(door_matches)(*args))
            matched += int(ref.sum())
        vertices = np.ascontiguousarray(truth._graph.points)
        for points in (ends, corners):
            got = sk.nearest_distances(points, vertices)
            np.testing.assert_array_equal(got, pairwise_distances(points, vertices).min(axis=1))
            np.testing.assert_array_equal(got, jit.py_func(sk.nearest_distances)(points, vertices))
    assert matched >= 20


def reference_wall_coverage(segments: np.ndarray, step: float, targets: np.ndarray, r: float, cos_angle: float):
    """The wall coverage's definition, sample by sample against every target (score_kernels'
    module docstring), summed in the same order."""
    total = ok = 0.0
    for ax, ay, bx, by in segments:
        dx, dy = bx - ax, by - ay
        length = math.hypot(dx, dy)
        n = max(math.ceil(length / step), 1)
        w = length / n
        u = np.array([dx, dy]) / max(length, 1e-12)
        for k in range(n):
            t = (k + 0.5) / n
            p = np.array([ax + t * dx, ay + t * dy])
            total += w
            for tx1, ty1, tx2, ty2 in targets:
                a, ab = np.array([tx1, ty1]), np.array([tx2 - tx1, ty2 - ty1])
                len2 = max(ab @ ab, 1e-18)
                if abs(u[0] * ab[0] / math.sqrt(len2) + u[1] * ab[1] / math.sqrt(len2)) < cos_angle:
                    continue
                s = min(max(((p - a) @ ab) / len2, 0.0), 1.0)
                if np.hypot(*(p - a - s * ab)) <= r:
                    ok += w
                    break
    return total, ok


def test_wall_coverage_is_its_definition_sample_by_sample():
    from pico_studio.evaluation import score_kernels as sk
    from pico_studio.evaluation.frame_score import Tolerances

    tol = Tolerances()
    cos_angle = math.cos(tol.wall_angle)
    partly = 0
    for _, _, ends, truth in perceived_frames()[:4]:
        walls = np.ascontiguousarray(ends.reshape(-1, 4))
        for segs, targets in ((walls, np.ascontiguousarray(truth.segments())), (np.ascontiguousarray(truth.visible_walls()), walls)):
            args = (segs, tol.sample_step, targets, tol.wall_distance, cos_angle)
            got = sk.wall_coverage(*args)
            assert got == pytest.approx(reference_wall_coverage(*args), rel=1e-12, abs=1e-12)
            assert got == jit.py_func(sk.wall_coverage)(*args)
            partly += 0 < got[1] < got[0]
    assert partly >= 4
