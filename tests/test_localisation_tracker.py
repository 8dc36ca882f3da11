"""The tracker on its own: bad scans, dead reckoning through a lost scan, the pure step
function, and the negative evidence of beams through walls."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pico_studio.config import Config
from pico_studio.core.localisation import Localiser, TrackerState, localise
from pico_studio.core.localisation.matcher import beams_through_walls, quality
from pico_studio.json_map import load_json_map
from pico_studio.sim import Simulator

START = (1.5, 0.7, 0.4)  # in the restaurant's start area


@pytest.fixture
def restaurant(maps_dir):
    return load_json_map(maps_dir / "restaurant_2024.json")


def _scan(gmap, pose) -> np.ndarray:
    sim = Simulator(gmap, Config().sim, seed=0, initial_pose=pose)
    sim.advance(0.05)
    return sim.read_laser().points


def test_bad_scans_do_not_raise_and_a_lost_scan_is_dead_reckoned(restaurant):
    loc = Localiser(Config().localisation, restaurant)
    for points in [np.zeros((0, 2)), np.full((1000, 2), np.nan), np.full((10, 2), np.inf)]:
        r = loc.step(points, (0.0, 0.0, 0.0))
        assert r.lost and r.pose is None
    scan = _scan(restaurant, START)
    for _ in range(4):
        r = loc.step(scan, (0.0, 0.0, 0.0))
    assert not r.lost and math.hypot(r.pose[0] - START[0], r.pose[1] - START[1]) < 0.02
    r = loc.step(np.zeros((0, 2)), (0.1, 0.0, 0.0))  # no scan: the odometry carries the pose
    assert r.pose is not None
    moved = math.hypot(r.pose[0] - START[0], r.pose[1] - START[1])
    assert moved == pytest.approx(0.1, abs=0.02)


def test_localise_is_pure(restaurant):
    loc = Localiser(Config().localisation, restaurant)
    scan = _scan(restaurant, START)
    state = TrackerState.initial(len(loc.lmap.field.segments))
    r1, s1 = localise(state, scan, (0.0, 0.0, 0.0), loc.lmap, loc.params)
    r2, s2 = localise(state, scan, (0.0, 0.0, 0.0), loc.lmap, loc.params)
    assert r1 == r2 and state.pose is None and s1.pose == s2.pose is not None


def test_beams_through_walls_tell_a_wrong_pose_from_an_occluded_one(restaurant):
    params = Config().localisation.matcher
    field = Localiser(Config().localisation, restaurant).lmap.field
    scan = _scan(restaurant, START)
    assert beams_through_walls(field, scan, START, params) == 0.0
    assert quality(field, scan, START, params.inlier_distance) > 0.9
    # half the beams cut short (an unmapped obstacle): fewer explained, none through walls
    short = scan.copy()
    short[::2] *= 0.5
    assert quality(field, short, START, params.inlier_distance) < 0.6
    assert beams_through_walls(field, short, START, params) == 0.0
    # the same scan 1 m off: beams go through walls
    assert beams_through_walls(field, scan, (2.5, 1.2, 0.4), params) > 0.2


def test_a_room_of_walls_thinner_than_the_inlier_distance_is_found_on_the_right_side():
    """ward:11's walls are 5 cm thick, less than the matcher's inlier distance: shifted by a
    wall's thickness the scan is as well explained (its beams end on the walls' far faces), so
    refining from the search's grid stopped there, a quarter of the beams through walls, and the
    robot stayed lost in its room. Refined again a step to either side it is found where it is."""
    from pico_studio.evaluation.worlds import make_world

    gmap = make_world("ward:11").map
    pose = (3.95, -2.15, -1.74)  # in a room, by its bed
    loc = Localiser(Config().localisation, gmap, initial_pose=pose)
    scan = _scan(gmap, pose)
    for _ in range(4):
        r = loc.step(scan, (0.0, 0.0, 0.0))
    assert not r.lost and r.pose is not None
    assert math.hypot(r.pose[0] - pose[0], r.pose[1] - pose[1]) < 0.02
    assert beams_through_walls(loc.lmap.field, scan, r.pose, loc.params.matcher) <= 0.05
