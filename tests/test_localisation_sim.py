"""Localisation end to end on the simulator: its laser (occlusion, noise), its uncertain
odometry in a frame that starts anywhere, moving objects, and the true pose to compare."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from localisation_sim import Driver, follow, kick

from pico_studio.config import Config, with_value
from pico_studio.core.localisation import Localiser
from pico_studio.json_map import load_json_map, load_map
from pico_studio.sim import Simulator, load_sim_config

HOSPITAL_ROUTE = [(3.5, 5.4), (5.5, 5.4), (5.5, 3.0), (5.5, 5.4), (3.5, 5.4), (3.5, 0.6)]
RESTAURANT_ROUTE = [(5.4, 3.4), (5.4, 0.8), (3.5, 0.8), (5.4, 0.8), (5.4, 3.4), (3.2, 3.6), (1.5, 3.6)]


def _sim(maps_dir, name, cfg, *, sim_config=None, pose=None, seed=0) -> Simulator:
    sc = load_sim_config(maps_dir / sim_config) if sim_config else None
    if sc is not None:
        sc = dataclasses.replace(sc, uncertain_odom=True)
    return Simulator(load_json_map(maps_dir / f"{name}.json"), cfg.sim, sc, seed=seed, initial_pose=pose)


def _config(gain_error: float = 0.002) -> Config:
    cfg = with_value(Config(), "sim.odometry.random_offset", True)  # odometry frame starts anywhere
    cfg = with_value(cfg, "sim.odometry.uncertain", True)
    return with_value(cfg, "sim.odometry.gain_error", gain_error)


@pytest.mark.parametrize("seed", [0, 1])
def test_converges_from_the_start_area_prior(maps_dir, seed):
    rng = np.random.default_rng(seed)
    # anywhere in the 1 x 1 m start area (centre 1.5, 0.7), any heading
    start = (1.5 + rng.uniform(-0.3, 0.3), 0.7 + rng.uniform(-0.25, 0.25), rng.uniform(-math.pi, math.pi))
    cfg = _config()
    sim = _sim(maps_dir, "restaurant_2024", cfg, pose=start, seed=seed)
    loc = Localiser(cfg.localisation, load_json_map(maps_dir / "restaurant_2024.json"))
    assert loc.lmap.prior.origin == "start_area"
    d = Driver(sim, loc)
    d.drive(1.0)
    assert not d.lost[-1]
    e = np.array(d.errors[-5:])
    assert (e[:, 0] < 0.03).all() and (e[:, 1] < math.radians(1.0)).all()


def test_tracks_under_drifting_odometry_with_moving_object(maps_dir):
    cfg = _config(gain_error=0.02)  # ten times the simulator's default wheel-gain error
    sim = _sim(maps_dir, "restaurant_2024", cfg, sim_config="restaurant_2024_sim.json")
    loc = Localiser(cfg.localisation, load_json_map(maps_dir / "restaurant_2024.json"),
                    initial_pose=(6.0, 3.5, 3.14))
    d = Driver(sim, loc)
    d.drive(40.0, follow(RESTAURANT_ROUTE))
    assert sim.truth.distance > 10.0 and sim.truth.collisions == 0
    e = np.array(d.errors[10:])
    assert not any(d.lost[10:])
    assert np.median(e[:, 0]) < 0.02 and e[:, 0].max() < 0.1
    assert np.median(e[:, 1]) < math.radians(1.0) and e[:, 1].max() < math.radians(3.0)
    # odometry alone went astray by more than the localiser's worst error, many times over
    assert max(d.dead_reckoning) > 5 * e[:, 0].max()


def test_kick_is_flagged_and_recovered_within_ten_seconds(maps_dir):
    cfg = _config()
    sim = _sim(maps_dir, "hospital_2019", cfg, pose=(3.5, 0.6, math.pi / 2))
    loc = Localiser(cfg.localisation, load_json_map(maps_dir / "hospital_2019.json"),
                    initial_pose=(3.5, 0.6, math.pi / 2))
    d = Driver(sim, loc)
    route = follow(HOSPITAL_ROUTE)
    d.drive(8.0, route)
    assert not d.lost[-1] and d.errors[-1][0] < 0.03
    n = len(d.lost)
    kick(sim)
    d.drive(10.0, route)
    after = d.lost[n:]
    assert any(after), "the kick was never flagged"
    first = after.index(True)
    assert first <= 5, "flagged too late"
    recovered = [k for k in range(first, len(after)) if not after[k]]
    assert recovered, "not recovered within 10 s"
    assert not d.lost[-1] and d.errors[-1][0] < 0.03 and d.errors[-1][1] < math.radians(1.0)


def test_wrong_map_is_lost_and_stays_lost(maps_dir):
    cfg = _config()
    sim = _sim(maps_dir, "restaurant_2024", cfg, sim_config="restaurant_2024_sim.json")
    # the hospital's map for the restaurant's world: the wrong file
    loc = Localiser(cfg.localisation, load_json_map(maps_dir / "hospital_2019.json"),
                    initial_pose=(6.0, 3.5, 3.14))
    d = Driver(sim, loc)
    # the route passes a dead end that one scan cannot tell from the hospital's corridor end:
    # found there, it is not confirmed while driving on
    d.drive(20.0, follow(RESTAURANT_ROUTE))
    assert all(d.lost)


def test_heightmap_map_localises(maps_dir):
    # the restaurant as the official simulator's image (+ map_server YAML), vectorised
    cfg = _config()
    gmap = load_map(maps_dir / "restaurant_2024.yaml", cfg.map)
    sim = Simulator(gmap, cfg.sim, load_sim_config(maps_dir / "restaurant_2024_sim.json"), seed=0)
    loc = Localiser(cfg.localisation, gmap, initial_pose=(6.0, 3.5, 3.14))
    d = Driver(sim, loc)
    d.drive(3.0, follow(RESTAURANT_ROUTE))
    assert not d.lost[-1]
    e = np.array(d.errors[5:])
    assert e[:, 0].max() < 0.03 and e[:, 1].max() < math.radians(1.0)
