"""Ground truth: visible walls, corners (convex/concave), door openings, visible doors."""

from __future__ import annotations

import math

import numpy as np
import pytest
from sim_helpers import box_map, door_map

from pico_studio.json_map import load_json_map, map_from_dict
from pico_studio.json_map.openings import door_openings, sector_width
from pico_studio.sim import Simulator
from pico_studio.sim.sim_config import sim_config_from_dict


def test_visible_walls_are_the_pieces_the_beams_hit() -> None:
    sim = Simulator(box_map(4.0, 4.0), initial_pose=(2.0, 2.0, 0.0))
    walls = sim.truth.visible_walls()
    src = sim.truth.visible_wall_sources()
    # facing +x with a +-2 rad fan: the right wall whole, parts of the top and bottom walls
    assert sorted(src.tolist()) == [0, 1, 2]
    right = walls[src == 1][0]
    assert right[0] == pytest.approx(4.0) and right[2] == pytest.approx(4.0)
    assert min(right[1], right[3]) < 0.02 and max(right[1], right[3]) > 3.98
    # the top wall (y = 4) is seen from x = 4 back to where the last beam (at +2 rad) hits it
    top = walls[src == 2][0]
    assert top[1] == pytest.approx(4.0) and top[3] == pytest.approx(4.0)
    x_end = 2.0 + 2.0 / math.tan(2.0)
    assert min(top[0], top[2]) == pytest.approx(x_end, abs=0.02)


def test_occluded_wall_parts_are_split() -> None:
    # a short pillar wall in front of the far wall hides its middle
    m = box_map(6.0, 4.0, more_points=[{"x": 3, "y": 1.8}, {"x": 3, "y": 2.2}], more_walls=[[4, 5]])
    sim = Simulator(m, initial_pose=(1.0, 2.0, 0.0))
    src = sim.truth.visible_wall_sources()
    assert (src == 1).sum() == 2  # the far wall x = 6 in two pieces
    assert (src == 4).sum() == 1


def test_sector_width() -> None:
    # two walls leaving a vertex along +x and +y: looking from the quadrant between them -> pi/2
    assert sector_width(np.array([0.0, math.pi / 2]), math.pi / 4) == pytest.approx(math.pi / 2)
    assert sector_width(np.array([0.0, math.pi / 2]), math.pi) == pytest.approx(1.5 * math.pi)
    assert sector_width(np.array([1.0]), 0.0) == pytest.approx(2 * math.pi)


def test_corners_concave_inside_a_room_convex_at_a_wall_end() -> None:
    # a room with a thin wall sticking in from the bottom: its tip is a loose (convex) end
    m = box_map(6.0, 4.0, more_points=[{"x": 4, "y": 0}, {"x": 4, "y": 2}], more_walls=[[4, 5]])
    sim = Simulator(m, initial_pose=(1.0, 3.0, -0.6))
    c = sim.truth.visible_corners()
    found = {(round(p[0], 3), round(p[1], 3)): (bool(v), bool(e)) for p, v, e in zip(c.points, c.convex, c.loose_end, strict=True)}
    assert found[(0.0, 0.0)] == (False, False)  # a room corner: concave
    assert found[(4.0, 2.0)] == (True, True)  # the wall's tip: convex, a loose end
    assert (4.0, 0.0) in found and found[(4.0, 0.0)] == (False, False)  # where it meets the floor wall
    assert (6.0, 0.0) not in found  # hidden behind the thin wall
    assert (0.0, 4.0) not in found  # behind the robot (outside the +-2 rad fan)


def test_door_openings_of_the_hospital() -> None:
    m = load_json_map("examples/maps/hospital_2019.json")
    objects = m.segments_of(np.vstack(m.objects))
    o = door_openings(m.wall_segments, m.door_polygons, obstacles=objects)
    mids = np.round((o[:, :2] + o[:, 2:]) / 2, 2)
    widths = np.hypot(o[:, 2] - o[:, 0], o[:, 3] - o[:, 1])
    expected = {(2.6, 5.6), (5.5, 4.5), (1.25, 2.1), (1.25, 4.1), (2.6, 1.6)}
    assert {tuple(p) for p in mids.tolist()} == expected
    assert np.all((widths > 0.75) & (widths < 0.95))


def test_door_openings_include_map_doors_once() -> None:
    m = load_json_map("examples/maps/restaurant_2024.json")
    o = door_openings(m.wall_segments, m.door_polygons)
    door = m.door_polygons[0]
    c = door.mean(axis=0)
    mids = (o[:, :2] + o[:, 2:]) / 2
    assert np.sum(np.hypot(*(mids - c).T) < 0.3) == 1  # the door, not also its gap again
    assert np.allclose(mids[0], c)


def test_visible_doors_depend_on_the_pose() -> None:
    m = load_json_map("examples/maps/hospital_2019.json")
    sim = Simulator(m, initial_pose=(1.2, 3.0, 0.0))  # middle-left room, facing +x
    vis = sim.truth.visible_doors()
    mids = {tuple(np.round((d[:2] + d[2:]) / 2, 2)) for d in vis}
    # the door below at (1.25, 2.1) is not: its left jamb is at the fan's edge (see test_truth_doors)
    assert mids == {(1.25, 4.1)}
    away = Simulator(m, initial_pose=(4.0, 6.0, 0.0))  # the corridor at the top, facing +x
    mids2 = {tuple(np.round((d[:2] + d[2:]) / 2, 2)) for d in away.truth.visible_doors()}
    assert (1.25, 2.1) not in mids2 and (5.5, 4.5) in mids2


def test_a_closed_door_is_no_visible_opening() -> None:
    # the door map's 1 m gap at x = 5 (y 4..5) holds a closed 0.1 m door: to the laser a wall.
    # Both jambs are seen and the middle is in view, but the leaf is shut across it
    sim = Simulator(door_map(), initial_pose=(3.0, 4.5, 0.0))
    o = sim.truth.door_openings()
    assert len(o) == 1
    assert (sim.truth.jamb_seen_length(o.reshape(2, 2)) >= 0.15).all()
    assert len(sim.truth.visible_doors()) == 0
    # the same map without the door leaf: the gap is a visible opening
    m = door_map()
    bare = Simulator(map_from_dict({"points": [{"x": float(x), "y": float(y)} for x, y in m.points],
                                    "walls": m.walls.tolist()}), initial_pose=(3.0, 4.5, 0.0))
    assert len(bare.truth.visible_doors()) == 1


def test_dynamic_vertices_are_the_door_leaves_and_moving_boxes_now() -> None:
    cfg = sim_config_from_dict({"objects": [{"length": 0.5, "width": 0.5, "trigger_radius": 1.0, "velocity": 0.3,
                                             "init_pose": [8.0, 8.0, 0.0], "final_pose": [8.0, 2.0, 0.0]}]})
    sim = Simulator(door_map(), sim_config=cfg, initial_pose=(2.0, 2.0, 0.0))
    v = {tuple(np.round(p, 3)) for p in sim.truth.dynamic_vertices().tolist()}
    assert {(4.95, 4.0), (5.05, 4.0), (5.05, 5.0), (4.95, 5.0)} <= v  # the closed leaf's corners
    assert {(7.75, 7.75), (8.25, 8.25)} <= v  # the standing box's corners
    assert len(v) == 8
