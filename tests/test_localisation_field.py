"""The global map's distance field and the prior."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pico_studio.config import Config, with_value
from pico_studio.core.geometry import point_segment_distance
from pico_studio.core.localisation import DistanceField, initial_prior
from pico_studio.core.localisation.distance_field import map_segments
from pico_studio.json_map import load_json_map


@pytest.fixture
def restaurant(maps_dir):
    return load_json_map(maps_dir / "restaurant_2024.json")


def test_field_matches_exact_segment_distance(restaurant):
    params = Config().localisation.field
    field = DistanceField.from_map(restaurant, params)
    rng = np.random.default_rng(0)
    p = rng.random((3000, 2)) * [7.0, 5.0]
    exact = point_segment_distance(p, field.segments)
    assert np.abs(field.distance(p) - exact.min(axis=1)).max() < params.resolution
    # the nearest segment is the nearest one, or one just as near within a cell
    k = field.nearest_segment(p)
    assert (exact[np.arange(len(p)), k] - exact.min(axis=1)).max() < 2.5 * params.resolution


def test_field_off_the_grid_is_far_and_has_no_segment(restaurant):
    field = DistanceField.from_map(restaurant, Config().localisation.field)
    far = np.array([[100.0, 100.0], [-50.0, 2.0]])
    assert (field.distance(far) > 1.0).all()
    assert (field.nearest_segment(far) == -1).all()


def test_map_segments_put_walls_first_and_respect_the_switches(restaurant):
    params = Config().localisation.field
    segs = map_segments(restaurant, params)
    assert np.allclose(segs[: len(restaurant.walls)], restaurant.wall_segments)
    n_objects = sum(len(p) for p in restaurant.objects)
    n_doors = sum(len(p) for p in restaurant.doors)
    assert len(segs) == len(restaurant.walls) + n_objects + n_doors
    cfg = with_value(Config(), "localisation.field.doors_as_walls", False)
    assert len(map_segments(restaurant, cfg.localisation.field)) == len(segs) - n_doors


def test_prior_from_start_area_given_pose_and_whole_map(restaurant, maps_dir):
    params = Config().localisation.prior
    p = initial_prior(restaurant, params)
    assert p.origin == "start_area" and (p.x, p.y) == pytest.approx((1.5, 0.7))
    assert (p.half_x, p.half_y) == pytest.approx((0.5, 0.5)) and not p.heading_known

    given = initial_prior(restaurant, params, pose=(6.0, 3.5, 3.14))
    assert given.origin == "pose" and given.half_x == params.position_uncertainty
    assert given.heading_known and given.a == 3.14  # a sim config's pose gives the heading

    cfg = with_value(Config(), "localisation.prior.source", "pose")
    assert not initial_prior(restaurant, cfg.localisation.prior).heading_known
    cfg = with_value(cfg, "localisation.prior.heading_known", True)
    known = initial_prior(restaurant, cfg.localisation.prior)
    assert known.origin == "pose" and known.heading_known
    assert known.heading_range == pytest.approx(cfg.localisation.prior.heading_uncertainty)

    hospital = load_json_map(maps_dir / "hospital_2019.json")  # no start area
    whole = initial_prior(hospital, params)
    assert whole.origin == "map" and whole.heading_range == pytest.approx(math.pi)
    x0, y0, x1, y1 = hospital.bounds
    assert whole.half_x == pytest.approx((x1 - x0) / 2)


def test_doors_are_passable_for_the_through_walls_check(restaurant):
    field = DistanceField.from_map(restaurant, Config().localisation.field)
    n_doors = sum(len(p) for p in restaurant.doors)
    assert field.passable is not None and field.passable.sum() == n_doors
    assert field.passable[-n_doors:].all() and not field.passable[: len(restaurant.walls)].any()


def test_a_point_just_behind_a_thin_walls_near_face_is_fitted_to_that_face():
    """A wall 3.8 cm thick (a heightmap's band: near face y = 0.044, far face y = 0.006, the
    grid's nodes 2 cm apart on the far face) and a square wall: scan points on the near face
    with +-1 cm of range noise. The node nearest a point 0.5 cm behind the near face is
    labelled with the far face; the fit takes the nearest of the four nodes' segments by exact
    distance, so it stays on the true pose (it was 1-2 cm off)."""
    from pico_studio.core.localisation.matcher import refine

    segs = np.array([[0.0, 0.044, 3.0, 0.044], [3.0, 0.044, 3.0, 0.006], [3.0, 0.006, 0.0, 0.006],
                     [0.0, 0.006, 0.0, 0.044], [0.0, 0.044, 0.0, 3.0]])
    field = DistanceField.from_segments(segs, resolution=0.02, margin=2.0)
    rng = np.random.default_rng(3)
    pose = (1.0, 1.0, 0.0)
    floor = np.c_[rng.uniform(0.2, 2.8, 400), 0.044 + rng.uniform(-0.01, 0.01, 400)]
    side = np.c_[rng.uniform(-0.01, 0.01, 200), rng.uniform(0.2, 2.8, 200)]
    pts = np.vstack([floor, side]) - pose[:2]  # the robot faces +x: its frame is the map's, shifted
    m = refine(field, pts, pose, Config().localisation.matcher)
    assert math.hypot(m.pose[0] - pose[0], m.pose[1] - pose[1]) < 0.002 and abs(m.pose[2]) < 0.002
