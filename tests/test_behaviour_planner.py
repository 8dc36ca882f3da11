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
