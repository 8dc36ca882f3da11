"""Ground-truth corners where map polygons abut: a wall rectangle's corner on another's face
(a T-junction, an L of two rectangles, a few mm apart or exactly) is concave on the room side,
and the far corners stay convex (`json_map.openings.vertex_graph`'s abutting vertices)."""

from __future__ import annotations

import numpy as np
import pytest

from pico_studio.json_map.openings import vertex_graph
from pico_studio.sim.map_features import classify_corners

TOL = 0.15  # TruthParams.straight_tolerance's default


def rect(x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    return np.array([[x0, y0, x1, y0], [x1, y0, x1, y1], [x1, y1, x0, y1], [x0, y1, x0, y0]], dtype=float)


def classes(segments: np.ndarray, viewpoint: tuple[float, float], abut: float = 0.03) -> dict[tuple[float, float], bool]:
    """{corner (rounded to mm): convex} as seen from `viewpoint`."""
    graph = vertex_graph(segments, abut=abut)
    idx, convex, _ = classify_corners(graph, viewpoint, TOL)
    return {(round(float(graph.points[v, 0]), 3), round(float(graph.points[v, 1]), 3)): bool(c) for v, c in zip(idx, convex, strict=True)}


@pytest.mark.parametrize("gap", [0.0, 0.004, 0.02, 0.03])  # 0.03: the tolerance itself
def test_t_junction_of_wall_rectangles_is_concave_on_the_room_side(gap: float) -> None:
    # a long wall along the bottom, a wall standing on its top face (or `gap` short of it)
    segs = np.vstack([rect(0.0, 0.0, 4.0, 0.2), rect(2.0, 0.2 + gap, 2.2, 3.0)])
    c = classes(segs, (3.0, 1.0))
    assert c[(2.2, round(0.2 + gap, 3))] is False  # the room's corner between the two walls
    assert c[(2.2, 3.0)] is True  # the standing wall's far end
    assert c[(4.0, 0.2)] is True  # the long wall's end
    c = classes(segs, (1.0, 1.0))  # the same from the other room
    assert c[(2.0, round(0.2 + gap, 3))] is False


def test_t_junction_needs_the_tolerance() -> None:
    # without abutting (a gap wider than the tolerance) the corner is the standing wall's convex corner
    segs = np.vstack([rect(0.0, 0.0, 4.0, 0.2), rect(2.0, 0.26, 2.2, 3.0)])
    assert classes(segs, (3.0, 1.0))[(2.2, 0.26)] is True


def test_l_of_two_wall_rectangles() -> None:
    # an upright wall and a horizontal one whose end cap lies on the upright's right face
    segs = np.vstack([rect(0.0, 0.0, 0.2, 3.0), rect(0.2, 0.0, 3.0, 0.2)])
    c = classes(segs, (1.5, 1.5))
    assert c[(0.2, 0.2)] is False  # the L's inner corner
    assert c[(3.0, 0.2)] is True and c[(0.2, 3.0)] is True  # the two arms' ends
    # the shared bottom corner, seen from below: the bottom face runs straight on, no corner
    assert (0.2, 0.0) not in classes(segs, (1.5, -1.0))


def test_overlapping_faces_see_the_free_sector() -> None:
    # a wall rectangle whose bottom edge runs along another's top face (collinear overlap)
    segs = np.vstack([rect(0.0, 0.0, 4.0, 0.2), rect(1.0, 0.2, 3.0, 0.5)])
    c = classes(segs, (3.5, 1.0))
    assert c[(3.0, 0.2)] is False  # the step's foot, on the room side: concave
    assert c[(3.0, 0.5)] is True  # the step's top corner
