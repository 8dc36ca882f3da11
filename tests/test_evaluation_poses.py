"""The eval's random free poses: reachable from the start, clear of walls, inside the map."""

from __future__ import annotations

import numpy as np

from pico_studio.config import Config
from pico_studio.core.geometry import point_segment_distance
from pico_studio.evaluation.poses import random_free_poses
from pico_studio.evaluation.worlds import make_world
from pico_studio.json_map import GlobalMap
from pico_studio.sim import Simulator


def _poses(spec: str, k: int = 200) -> tuple[np.ndarray, GlobalMap]:
    w = make_world(spec)
    sim = Simulator(w.map, Config().sim, w.sim_config, seed=0, initial_pose=w.start)
    poses = random_free_poses(sim.world.segments(), w.start[:2], k, 0.4, np.random.default_rng(0), w.map.bounds)
    return np.array(poses), w.map


def test_poses_stay_inside_a_room_whose_exit_is_open():
    """escape:2's exit corridor opens to the outside: the fill used to run round the building
    (32 of 50 eval poses outside it, where the map has nothing to localise against)."""
    poses, gmap = _poses("escape:2")
    x0, y0, x1, y1 = gmap.bounds
    assert len(poses) == 200
    assert ((poses[:, 0] >= x0) & (poses[:, 0] <= x1) & (poses[:, 1] >= y0) & (poses[:, 1] <= y1)).all()
    # ...and clear of every wall by about the clearance (a grid cell's rounding)
    d = point_segment_distance(poses[:, :2], gmap.wall_segments).min(axis=1)
    assert d.min() > 0.4 - 0.1
