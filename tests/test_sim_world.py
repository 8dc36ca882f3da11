"""Doors and moving objects of the simulated world."""

from __future__ import annotations

import numpy as np
import pytest
from sim_helpers import box_map, door_map

from pico_studio.sim import Simulator, sim_config_from_dict


def ahead(sim: Simulator) -> float:
    scan = sim.read_laser()
    assert scan is not None
    return float(scan.ranges[int(np.argmin(np.abs(scan.angles)))])


def test_door_opens_only_when_asked_from_in_front() -> None:
    sim = Simulator(door_map(), initial_pose=(4.1, 4.5, 0.0))
    assert abs(ahead(sim) - 0.85) <= 0.0101  # the closed door
    sim.advance(10.0)  # not asked: stays closed
    assert abs(ahead(sim) - 0.85) <= 0.0101
    sim.open_door()
    sim.advance(1.0)  # sliding at 0.3 m/s along the wall: still in the way after 1 s
    assert sim.world.doors[0].offset == pytest.approx(0.3)
    sim.advance(3.0)  # fully open after 1 m / 0.3 m/s
    assert sim.world.doors[0].offset == sim.world.doors[0].size
    assert abs(ahead(sim) - 5.9) <= 0.0101  # now the beam reaches the far wall


def test_door_does_not_open_when_asked_from_too_far_or_beside_it() -> None:
    for pose in [(3.5, 4.5, 0.0), (4.1, 7.0, 0.0), (4.1, 2.5, 0.0)]:
        sim = Simulator(door_map(), initial_pose=pose)
        sim.open_door()
        sim.advance(5.0)
        assert sim.world.doors[0].offset == 0.0, pose
    # from the other side it opens too (a door has two fronts)
    sim = Simulator(door_map(), initial_pose=(5.9, 4.5, np.pi))
    sim.open_door()
    sim.advance(5.0)
    assert sim.world.doors[0].offset > 0.0


def test_closed_door_is_solid() -> None:
    sim = Simulator(door_map(), initial_pose=(4.0, 4.5, 0.0))
    sim.send_base_reference(0.5, 0.0, 0.0)
    sim.advance(3.0)
    assert sim.truth.pose[0] < 4.95 and sim.truth.collisions == 1
    assert sim.truth.collision_events[0].kind == "door"


def obj_config(**changes: object) -> dict:
    o = {"length": 0.5, "width": 0.5, "init_pose": [5.0, 8.0, 0.0], "final_pose": [5.0, 2.0, 0.0],
         "velocity": 0.5, "trigger_radius": 2.0, "repeat": False}
    o.update(changes)
    return {"objects": [o]}


def test_moving_object_waits_for_the_trigger_then_moves() -> None:
    far = Simulator(box_map(), sim_config=sim_config_from_dict(obj_config()), initial_pose=(2.0, 5.0, 0.0))
    far.advance(3.0)
    assert tuple(far.world.moving[0].pos) == (5.0, 8.0)
    near = Simulator(box_map(), sim_config=sim_config_from_dict(obj_config()), initial_pose=(3.5, 8.0, 0.0))
    near.advance(2.0)
    assert near.world.moving[0].pos[1] < 8.0 - 0.8  # triggered and moving away at 0.5 m/s
    near.advance(20.0)
    assert tuple(near.world.moving[0].pos) == (5.0, 2.0) and near.world.moving[0].finished
    # the laser sees it where it is
    ranges, hits = near.truth.scan_hits()
    assert (near.world.kinds()[hits[hits >= 0]] == 3).any()


def test_moving_object_pauses_while_the_robot_is_close() -> None:
    sim = Simulator(box_map(), sim_config=sim_config_from_dict(obj_config(trigger_radius=5.0)), initial_pose=(5.0, 3.5, 0.0))
    obj = sim.world.moving[0]
    sim.advance(10.0)
    assert obj.paused and not obj.finished
    y_paused = obj.pos[1]
    assert abs(y_paused - 3.5) < obj.safety_radius + 0.05
    sim.advance(5.0)
    assert obj.pos[1] == y_paused  # stays while the robot stays
    assert sim.truth.collisions == 0
    sim.send_base_reference(0.5, 0.0, 0.0)  # robot drives off along x
    sim.advance(3.0)
    sim.send_base_reference(0.0, 0.0, 0.0)
    sim.advance(10.0)
    assert not obj.paused and obj.finished and tuple(obj.pos) == (5.0, 2.0)


def test_repeating_object_shuttles() -> None:
    sim = Simulator(box_map(), sim_config=sim_config_from_dict(obj_config(repeat=True, trigger_radius=20.0)), initial_pose=(1.0, 1.0, 0.0))
    obj = sim.world.moving[0]
    ys = []
    for _ in range(300):
        sim.advance(0.1)
        ys.append(obj.pos[1])
    ys = np.array(ys)
    assert ys.min() < 2.2 and ys.max() > 7.8  # reached both ends
    assert not obj.finished
    turns = np.sum(np.diff(np.sign(np.diff(ys))) != 0)
    assert turns >= 2


def test_free_form_room_of_many_segments() -> None:
    # a round room of radius 3 m drawn with 720 short segments, as a vectorised heightmap is
    from pico_studio.json_map import map_from_dict

    k = 720
    ang = np.arange(k) * 2 * np.pi / k
    pts = [{"x": float(3 * np.cos(a)), "y": float(3 * np.sin(a))} for a in ang]
    m = map_from_dict({"points": pts, "walls": [[i, (i + 1) % k] for i in range(k)]})
    sim = Simulator(m)
    assert np.hypot(*sim.truth.pose[:2]) < 0.1  # the start is the centre: farthest from the wall
    scan = sim.read_laser()
    assert scan is not None
    off = np.hypot(*sim.truth.pose[:2])  # ranges differ from the radius by at most the offset
    assert np.all(np.abs(scan.ranges - 3.0) < 0.01 + off + 3 * (1 - np.cos(np.pi / k)) + 1e-9)
    sim.send_base_reference(0.5, 0.0, 0.0)
    sim.advance(10.0)
    assert sim.truth.collisions == 1 and 2.8 < np.hypot(*sim.truth.pose[:2]) < 3.0
    assert len(sim.truth.visible_corners().points) == 0  # a smooth wall has no corners


def test_truth_lists_doors_and_moving_objects_where_they_are() -> None:
    sim = Simulator(door_map(), sim_config=sim_config_from_dict(obj_config(trigger_radius=9.0)), initial_pose=(4.1, 4.5, 0.0))
    (outline, opened), = sim.truth.doors()
    assert not opened and np.allclose(outline.mean(axis=0), (5.0, 4.5))
    sim.open_door()
    sim.advance(1.0)
    (outline, opened), = sim.truth.doors()
    assert opened and np.hypot(*(outline.mean(axis=0) - (5.0, 4.5))) == pytest.approx(0.3)
    (box,) = sim.truth.moving_objects()
    assert box.shape == (4, 2) and box.mean(axis=0)[1] == pytest.approx(8.0 - 0.5)


def test_json_door_slides_towards_decreasing_coordinate() -> None:
    sim = Simulator(door_map(), initial_pose=(4.1, 4.5, 0.0))
    sim.open_door()
    sim.advance(5.0)
    (outline, _), = sim.truth.doors()
    assert outline[:, 1].max() == pytest.approx(4.0)  # slid down (-y) by its 1 m size
