"""A box coming out from behind something, seen past at one end only, is tracked by that end:
moving, it is a dynamic obstacle and leaves no wall (restaurant_2024's box walks along its own
face half hidden behind a table; merged as a wall, its face smeared into a door jamb)."""

from __future__ import annotations

import dataclasses

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception import Perceptor
from tests.clutter_scenes import box, cast, odometry, room

PARAMS = load_config(None).perception
POSE = (0.0, 0.0, 0.0)
PANEL = np.array([[2.0, -1.5, 2.0, 0.0]])  # hides everything at x = 3 below y = 0


def _run(params, speed: float, frames: int = 10):
    """A 0.5 m box whose face (x = 3) runs from y = -0.15 to 0.35, sliding towards the panel's
    shadow along that face at `speed` m/s (20 Hz): its lower end is always hidden."""
    walls = np.vstack([room(12.0, 10.0) - np.array([2.0, 5.0, 2.0, 5.0]), PANEL])
    p = Perceptor(params)
    wm = None
    for k in range(frames):
        y = 0.1 - speed * 0.05 * k
        laser = dataclasses.replace(cast(np.vstack([walls, box(3.25, y, 0.5)]), POSE), timestamp=k * 0.05)
        wm = p.step(laser, odometry(POSE, k * 0.05))
    return wm


def _box_walls(wm) -> np.ndarray:
    lm = wm.local_map.walls
    return (np.abs(lm[:, 0] - 3.0) < 0.1) & (np.abs(lm[:, 2] - 3.0) < 0.1)


def test_a_half_hidden_box_moving_leaves_no_wall():
    wm = _run(PARAMS, speed=0.5)
    assert len(wm.dynamic_obstacles) == 1
    assert not _box_walls(wm).any()
    whole_only = dataclasses.replace(PARAMS, objects=dataclasses.replace(PARAMS.objects, partly_hidden=False))
    assert _box_walls(_run(whole_only, speed=0.5)).any()  # merged as a wall, smeared


def test_a_half_hidden_box_standing_still_is_merged():
    """Tracked by the end it was seen past, a still box does not move: after `confirm_scans`
    it is a static object, its face in the local map."""
    wm = _run(PARAMS, speed=0.0)
    assert len(wm.dynamic_obstacles) == 0
    assert _box_walls(wm).any()
