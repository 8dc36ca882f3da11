"""The simulator on heightmap images (vectorised by `json_map.load_map`): free-form shapes,
grey doors, the official simulator's config with moving objects."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from pico_studio import json_map
from pico_studio.json_map import load_map
from pico_studio.sim import Simulator, load_sim_config

MAPS = "pico_studio/data/maps/"


def test_hospital_2021_laser_hits_the_image_walls() -> None:
    m = load_map(MAPS + "hospital_2021.png")
    sim = Simulator(m, sim_config=load_sim_config(MAPS + "hospital_2021_sim.json"), seed=3)
    assert len(sim.world.moving) == 2
    assert sim.world.enclosed(sim.truth.pose[:2])
    img = cv2.imread(MAPS + "hospital_2021.png", cv2.IMREAD_GRAYSCALE)
    h, w = img.shape
    frame = json_map.GridFrame.from_dict(m.extra["heightmap"])  # where the image lies in the world
    assert frame is not None
    dark = cv2.erode(img, np.ones((5, 5), np.uint8)) < 50  # within 2 px of a wall pixel
    checked = near = 0
    for heading in (0.0, 2.0, 4.0):
        sim2 = Simulator(m, initial_pose=(*sim.truth.pose[:2], heading), seed=3)
        ranges, hits = sim2.truth.scan_hits()
        static = (hits >= 0) & (hits < len(sim2.world.static))
        ang = sim2.laser.fan.angle_min + np.arange(len(ranges)) * sim2.laser.fan.increment + heading
        x, y = sim2.truth.pose[0] + ranges * np.cos(ang), sim2.truth.pose[1] + ranges * np.sin(ang)
        uv = np.floor(frame.to_pixel(np.column_stack([x[static], y[static]]))).astype(int)
        col, row = uv[:, 0], uv[:, 1]
        inside = (col >= 0) & (col < w) & (row >= 0) & (row < h)
        checked += int(static.sum())
        near += int(dark[row[inside], col[inside]].sum())
    assert checked > 2000 and near / checked > 0.98, near / checked


def test_heightmap_doors_are_sliding_doors() -> None:
    m = load_map(MAPS + "doors_heightmap_example.png")
    assert len(m.doors) == 4
    sim = None
    for side in (1.0, -1.0):  # 0.5 m in front of the first door, on whichever side is free
        door = Simulator(m, seed=1).world.doors[0]
        front = door.center + side * 0.5 * door.normal
        pose = (float(front[0]), float(front[1]), math.atan2(-side * door.normal[1], -side * door.normal[0]))
        sim = Simulator(m, seed=1, initial_pose=pose) if _free(m, pose) else None
        if sim is not None:
            break
    assert sim is not None
    ranges, hits = sim.truth.scan_hits()
    ahead = int(np.argmin(np.abs(sim.laser.fan.angle_min + np.arange(len(ranges)) * sim.laser.fan.increment)))
    assert ranges[ahead] < 0.6  # the closed door, right in front
    sim.open_door()
    sim.advance(door.size / 0.3 + 0.5)
    assert sim.world.doors[0].offset == pytest.approx(sim.world.doors[0].size)
    after, _ = sim.truth.scan_hits()
    assert after[ahead] > 1.0  # the beam now passes through the opening


def _free(m: json_map.GlobalMap, pose: tuple[float, float, float]) -> bool:
    probe = Simulator(m, seed=1)
    return not probe.base.collides(pose, probe.world.segments()).any()


def test_run_on_a_heightmap_with_its_sim_config() -> None:
    from pico_studio.cli import main

    assert main(["run", "--map", MAPS + "restaurant_2024.yaml", "--sim-config", MAPS + "restaurant_2024_sim.json",
                 "--seconds", "3", "--behaviour", "drive:0.2,0,0"]) == 0


def test_heightmap_door_grey_sets_the_sliding_direction() -> None:
    m = load_map(MAPS + "doors_heightmap_example.png")
    assert m.extra["heightmap"]["door_grey"][:2] == [180, 90]
    sim = Simulator(m, seed=1)
    light, dark = sim.world.doors[0], sim.world.doors[1]
    assert abs(light.axis[1]) == pytest.approx(1.0) and abs(dark.axis[1]) == pytest.approx(1.0)  # both along y
    assert light.slide[1] == pytest.approx(-1.0)  # grey >= 128: towards decreasing y, as the emc simulator
    assert dark.slide[1] == pytest.approx(1.0)  # grey < 128: the other way
