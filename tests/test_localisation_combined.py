"""The combined map: local walls in the global frame, matched or not; map walls seen."""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config import Config
from pico_studio.core.geometry import compose, invert, transform_segments
from pico_studio.core.localisation import Localiser, combine
from pico_studio.core.localisation.combined import zero_to_global
from pico_studio.json_map import load_json_map
from pico_studio.sim import Simulator


def test_local_walls_are_carried_into_the_global_frame_and_tagged(maps_dir):
    m = load_json_map(maps_dir / "restaurant_2024.json")
    cfg = Config().localisation
    loc = Localiser(cfg, m)
    global_pose = (1.5, 0.7, 0.4)
    zero_pose = (2.0, -1.0, 1.1)  # the same robot pose in the odometry's zero frame
    to_zero = compose(zero_pose, invert(global_pose))
    on_map = m.wall_segments[:3]
    person = np.array([[2.5, 1.0, 2.5, 1.3]])  # free space in the map: not on it
    local = transform_segments(np.vstack([on_map, person]), to_zero)
    doors = transform_segments(np.array([[3.6, 1.9, 4.6, 1.9]]), to_zero)

    seen = np.zeros(len(loc.lmap.field.segments), dtype=np.int64)
    seen[1] = cfg.combined.seen_hits
    cm = combine(global_pose, zero_pose, local, loc.lmap.field, seen, len(m.walls), cfg.combined,
                 doors=doors, possible_doors=None, possible_door_kind=[])
    assert np.allclose(cm.walls, np.vstack([on_map, person]), atol=1e-9)
    assert cm.wall_matched.tolist() == [True, True, True, False]
    assert cm.map_wall_seen.shape == (len(m.walls),) and cm.map_wall_seen.tolist().count(True) == 1
    assert np.allclose(cm.doors, [[3.6, 1.9, 4.6, 1.9]], atol=1e-9)
    assert cm.possible_doors.shape == (0, 4)
    assert set(cm.to_dict()) >= {"walls", "wall_matched", "map_wall_seen", "doors"}


def test_zero_to_global_maps_the_robot_onto_itself():
    g, z = (1.0, 2.0, 0.5), (-3.0, 0.2, -1.0)
    t = zero_to_global(g, z)
    assert np.allclose(compose(t, z), g)


def test_walls_in_view_become_seen_while_tracking(maps_dir):
    m = load_json_map(maps_dir / "restaurant_2024.json")
    cfg = Config()
    loc = Localiser(cfg.localisation, m)
    sim = Simulator(m, cfg.sim, seed=0, initial_pose=(1.5, 0.7, math.pi / 2))
    assert loc.combined((0.0, 0.0, 0.0), np.zeros((0, 4))) is None  # nothing before a fix
    for _ in range(6):
        sim.advance(0.05)
        loc.step(sim.read_laser().points, (0.0, 0.0, 0.0))
    cm = loc.combined((0.0, 0.0, 0.0), np.zeros((0, 4)))
    assert cm is not None
    assert 0 < cm.map_wall_seen.sum() < len(m.walls)  # walls in view seen, hidden ones not
