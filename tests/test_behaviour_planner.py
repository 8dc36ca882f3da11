"""The A* planner on hand-built maps: it goes round walls, keeps clear, and says when it can't."""

from __future__ import annotations

import numpy as np

from pico_studio.config.behaviour_params import HospitalParams
from pico_studio.core.behaviours.planner import PlanGrid, astar, densify
from pico_studio.core.geometry import point_segment_distance

P = HospitalParams()
BOX = np.array([[0, 0, 4, 0], [4, 0, 4, 3], [4, 3, 0, 3], [0, 3, 0, 0]], dtype=float)


def test_path_goes_round_a_wall_and_keeps_the_inflation_clearance():
    walls = np.vstack([BOX, [[2, 0, 2, 2.2]]])  # a wall from the bottom, a 0.8 m gap at the top
    grid = PlanGrid.from_segments(walls, P)
    path = astar(grid, (1.0, 1.0), (3.0, 1.0))
    assert path is not None
    assert np.allclose(path[0], (1.0, 1.0), atol=P.cell) and np.allclose(path[-1], (3.0, 1.0), atol=P.cell)
    dense = densify(path, 0.02)
    assert dense[:, 1].max() > 2.2  # it had to pass above the wall's end
    assert point_segment_distance(dense, walls).min() >= P.inflation - P.cell


def test_no_path_through_a_closed_wall_or_to_a_goal_inside_the_inflation():
    walls = np.vstack([BOX, [[2, 0, 2, 3]]])
    grid = PlanGrid.from_segments(walls, P)
    assert astar(grid, (1.0, 1.0), (3.0, 1.0)) is None
    assert astar(grid, (1.0, 1.0), (1.0, 0.05)) is None
    assert grid.nearest_free((1.0, 0.05), 0.5) is not None


def test_extra_obstacles_force_a_detour():
    grid = PlanGrid.from_segments(BOX, P)
    straight = astar(grid, (0.8, 1.5), (3.2, 1.5))
    assert straight is not None and np.ptp(densify(straight, 0.05)[:, 1]) < 0.2
    blocked = grid.with_obstacles(np.array([[2.0, 1.5]]), 0.6)
    detour = astar(blocked, (0.8, 1.5), (3.2, 1.5))
    assert detour is not None
    assert np.hypot(*(densify(detour, 0.02) - [2.0, 1.5]).T).min() >= 0.6 - P.cell


def test_compiled_astar_equals_its_python_on_a_real_map(maps_dir):
    from pico_studio.core.behaviours import planner
    from pico_studio.jit import py_func
    from pico_studio.json_map import load_json_map

    grid = PlanGrid.from_map(load_json_map(maps_dir / "restaurant_2024.json"), P)
    free = np.argwhere(~grid.blocked)
    rng = np.random.default_rng(3)
    blocked, penalty = np.ascontiguousarray(grid.blocked), np.ascontiguousarray(grid.penalty)
    lengths = []
    for _ in range(4):
        (sr, sc), (gr, gc) = free[rng.integers(len(free), size=2)]
        got = planner._astar(blocked, penalty, int(sr), int(sc), int(gr), int(gc))
        np.testing.assert_array_equal(got, py_func(planner._astar)(blocked, penalty, int(sr), int(sc), int(gr), int(gc)))
        lengths.append(len(got))
    assert max(lengths) > 20  # real plans across the map


def test_a_hospital_tick_runs_at_most_a_few_plans(maps_dir, monkeypatch):
    """Tables with many unreachable spots: the planning round spreads over ticks (the robot
    stands still meanwhile) instead of running every A* in one tick."""
    from pico_studio.config import Config
    from pico_studio.core.behaviours import hospital
    from pico_studio.json_map import load_json_map

    m = load_json_map(maps_dir / "restaurant_2024.json")
    tour = hospital.HospitalTour(Config().behaviour, m, [0])
    calls: list[int] = []
    monkeypatch.setattr(hospital, "astar", lambda grid, a, b: calls.append(1))  # no spot is reachable
    spots = len(tour.spots[0])
    assert spots > hospital._PLANS_PER_TICK
    ticks = 0
    while tour._state != "gave up" and ticks < 100:
        before = len(calls)
        tour._plan_step((1.0, 1.0, 0.0))
        assert len(calls) - before <= hospital._PLANS_PER_TICK
        ticks += 1
    least = -(-spots // hospital._PLANS_PER_TICK)
    assert len(calls) == spots and least <= ticks <= least + 1  # the last tick may only give up
