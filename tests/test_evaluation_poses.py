"""The eval's random free poses: reachable from the start, clear of walls, inside the map."""

from __future__ import annotations

import numpy as np

from pico_studio.config import Config
from pico_studio.core.geometry import point_segment_distance
from pico_studio.evaluation.poses import random_free_poses, world_free_poses
from pico_studio.evaluation.worlds import make_world
from pico_studio.json_map import GlobalMap
from pico_studio.sim import Simulator


def _poses(spec: str, k: int = 200) -> tuple[np.ndarray, GlobalMap]:
    w = make_world(spec)
    sim = Simulator(w.map, Config().sim, w.sim_config, seed=0, initial_pose=w.start)
    poses = world_free_poses(sim.world, w.start[:2], k, 0.4, np.random.default_rng(0), w.map.bounds)
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


def _box(cx: float, cy: float, half: float) -> np.ndarray:
    c = [(cx - half, cy - half), (cx + half, cy - half), (cx + half, cy + half), (cx - half, cy + half)]
    return np.array([[*c[i], *c[(i + 1) % 4]] for i in range(4)], dtype=float)


def test_a_person_in_a_corridor_neither_closes_it_nor_gets_a_pose():
    """A 1.4 m corridor 8 m long, a 0.4 m person standing in its middle: grown by the 0.4 m
    clearance the person closes it, yet the robot can go round once the person walks on —
    the fill runs past (poses on both sides), and no pose lies within the clearance of them."""
    walls = np.array([[0, 0, 8, 0], [8, 0, 8, 1.4], [8, 1.4, 0, 1.4], [0, 1.4, 0, 0]], dtype=float)
    person = _box(4.0, 0.7, 0.2)
    rng = np.random.default_rng(0)
    blocked = np.array(random_free_poses(np.vstack([walls, person]), (1.0, 0.7), 300, 0.4, rng, (0, 0, 8, 1.4)))
    assert blocked[:, 0].max() < 4.0  # the old way: the person walls off the far half
    poses = np.array(random_free_poses(walls, (1.0, 0.7), 300, 0.4, np.random.default_rng(0), (0, 0, 8, 1.4),
                                       avoid=person))
    assert (poses[:, 0] > 5.0).sum() > 50 and (poses[:, 0] < 3.0).sum() > 50
    assert point_segment_distance(poses[:, :2], person).min() > 0.4 - 0.1


def test_the_eval_draws_past_the_people_in_a_world():
    """slant:0's walking person starts where its corridor, drawn askew, is narrowest: with the
    person as a wall every eval pose lay within 2 m of the start."""
    poses, gmap = _poses("slant:0", k=100)
    assert np.ptp(poses[:, 0]) > 6.0
