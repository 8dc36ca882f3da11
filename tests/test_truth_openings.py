"""Truth door openings: passage mouths (a corridor opening into a room or the outside) count,
room corners and lines along walls do not."""

from __future__ import annotations

import numpy as np
import pytest

from pico_studio.evaluation.worlds import escape_world
from pico_studio.json_map import load_map
from pico_studio.json_map.openings import door_openings
from pico_studio.sim import Simulator


def _unit(seg: np.ndarray) -> np.ndarray:
    d = seg[2:] - seg[:2]
    return d / np.hypot(*d)


@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_an_escape_corridor_has_an_opening_at_each_end(seed: int) -> None:
    w = escape_world(seed)
    o = Simulator(w.map, initial_pose=w.start).truth.door_openings()
    exit_ = w.map.finish_segments[0]
    width = np.hypot(*(exit_[2:] - exit_[:2]))
    assert len(o) == 2
    mids = (o[:, :2] + o[:, 2:]) / 2
    at_exit = np.hypot(*(mids - (exit_[:2] + exit_[2:]) / 2).T) < 1e-6
    assert at_exit.sum() == 1  # the corridor's far end, onto the open outside
    mouth = o[~at_exit][0]  # where the corridor meets the room
    assert np.hypot(*(mouth[2:] - mouth[:2])) == pytest.approx(width)
    assert abs(float(_unit(mouth) @ _unit(exit_))) == pytest.approx(1.0)
    # its two ends are wall corners of the room (vertices of the map), not points in the air
    for end in (mouth[:2], mouth[2:]):
        assert np.hypot(*(w.map.points - end).T).min() < 1e-9


def test_the_escape_room_image_has_its_corridor_mouth_and_exit() -> None:
    m = load_map("examples/maps/escape_room.png")
    o = door_openings(m.wall_segments, m.door_polygons)
    widths = np.hypot(o[:, 2] - o[:, 0], o[:, 3] - o[:, 1])
    mids = (o[:, :2] + o[:, 2:]) / 2
    assert len(o) == 2
    assert np.allclose(widths, 0.64, atol=0.03)
    assert np.allclose(mids[:, 0], mids[0, 0], atol=0.02)  # one above the other: one corridor


def test_a_room_corner_is_not_a_mouth() -> None:
    # a 4 x 4 room with a 0.9 m doorway in its right wall, near the top corner: the corner
    # and the doorway's jamb are 0.9-1.3 m apart but no passage runs between them
    pts = [(0, 0), (4, 0), (4, 2.6), (4, 3.5), (4, 4), (0, 4)]
    segs = np.array([[*pts[0], *pts[1]], [*pts[1], *pts[2]], [*pts[3], *pts[4]], [*pts[4], *pts[5]], [*pts[5], *pts[0]]],
                    dtype=float)
    o = door_openings(segs)
    mids = np.round((o[:, :2] + o[:, 2:]) / 2, 3)
    assert mids.tolist() == [[4.0, 3.05]]  # the doorway (two loose ends), nothing else


def test_a_corridor_joining_a_hall_has_a_mouth_and_a_closed_corridor_has_none() -> None:
    # a 0.8 m corridor from y = 0 (closed there) up into a 4 x 3 hall at y in [3, 6]
    segs = np.array([
        (1.6, 0, 2.4, 0), (1.6, 0, 1.6, 3), (2.4, 0, 2.4, 3),  # the corridor, closed at the bottom
        (1.6, 3, 0, 3), (0, 3, 0, 6), (0, 6, 4, 6), (4, 6, 4, 3), (4, 3, 2.4, 3),  # the hall
    ], dtype=float)
    o = door_openings(segs)
    mids = np.round((o[:, :2] + o[:, 2:]) / 2, 3).tolist()
    assert mids == [[2.0, 3.0]]


@pytest.mark.parametrize("depth, mouth", [(0.7, False), (0.83, False), (1.2, True)])
def test_a_niche_between_two_blocks_is_no_mouth_a_passage_as_wide_is(depth: float, mouth: bool) -> None:
    """restaurant_2024.png: two tables against the top wall, their outlines fused with the wall's,
    0.6 m apart and 0.7 m deep: a niche (straight in from its mouth closed within `mouth_depth`,
    0.9 m, all across), no door; so is a suite's (tables 0.8 m deep 3 cm off the wall: 0.83 m,
    a door to the truth of every suite drawn as a heightmap while `mouth_depth` was 0.8); the
    same gap running 1.2 m deep (a side room's short passage) is a mouth."""
    top = 4.0
    y = top - depth  # the blocks' fronts
    # one outline, as a heightmap traces it: the room 0..6 by 0..y, the blocks' fronts along y
    # from its side walls to the gap, the niche 2.7..3.3 up to the top wall
    segs = np.array([
        (0, 0, 6, 0), (6, 0, 6, y), (0, y, 0, 0),
        (6, y, 3.3, y), (3.3, y, 3.3, top), (3.3, top, 2.7, top), (2.7, top, 2.7, y), (2.7, y, 0, y),
    ], dtype=float)
    o = door_openings(segs)
    mids = np.round((o[:, :2] + o[:, 2:]) / 2, 3).tolist()
    assert mids == ([[3.0, y]] if mouth else [])
    assert door_openings(segs, mouth_depth=0.0).shape == (1, 4)  # with no depth asked, a mouth either way


def test_vertex_pairs_a_doors_width_apart_come_in_chunks_as_from_the_whole_matrix():
    """The passage mouths' candidate pairs (`openings._pairs_within`) are read a few hundred
    rows of the distance matrix at a time — a heightmap's thousands of vertices never need the
    whole (V x V) matrix — in the order the whole matrix gave: nearest first, ties row-major."""
    import numpy as np

    from pico_studio.json_map.openings import _pairs_within

    rng = np.random.default_rng(4)
    pts = np.round(rng.uniform(0.0, 6.0, size=(700, 2)), 1)  # rounded: many equal distances
    diff = pts[None, :, :] - pts[:, None, :]
    dist = np.hypot(diff[..., 0], diff[..., 1])
    whole = sorted(map(tuple, np.argwhere(np.triu((dist >= 0.5) & (dist <= 1.5), 1))), key=lambda ij: dist[ij])
    got = _pairs_within(pts, 0.5, 1.5, chunk=64)
    assert [(i, j) for i, j, _ in got] == [(int(i), int(j)) for i, j in whole]
    assert all(d == dist[i, j] for i, j, d in got) and len(got) > 1000


def _poly(*pts: tuple[float, float]) -> list[list[float]]:
    return [[*pts[i], *pts[(i + 1) % len(pts)]] for i in range(len(pts))]


@pytest.mark.parametrize("slant", [0.0, 0.2, -0.2])
def test_a_doorway_between_thick_walls_with_askew_caps(slant: float) -> None:
    """A 0.1 m thick wall along y in [0, 0.1] with a 1 m doorway; its caps askew by `slant`
    (x shifts slant * y: a sheared drawing, 11 degrees) and a partition standing on the right
    jamb's corner, so that cap is no wall end of its own. The left cap's end points along
    its wall: straight ahead 1 m on is the right jamb (along its cap's normal the ray passes
    below it)."""
    s = slant * 0.1
    left = _poly((0.0, 0.0), (2.0, 0.0), (2.0 + s, 0.1), (0.0 + s, 0.1))
    right = _poly((3.0, 0.0), (5.0, 0.0), (5.0 + s, 0.1), (3.0 + s, 0.1))
    partition = _poly((3.0 + s, 0.1), (3.1 + s, 0.1), (3.1 + s, 3.0), (3.0 + s, 3.0))
    o = door_openings(np.array(left + right + partition, dtype=float))
    assert len(o) == 1
    mid, width = (o[0, :2] + o[0, 2:]) / 2, np.hypot(*(o[0, 2:] - o[0, :2]))
    assert mid == pytest.approx([2.5 + s / 2, 0.05], abs=0.01)
    assert width == pytest.approx(1.0, abs=0.01)
    assert abs(float(_unit(o[0])[1])) < 0.01  # along the wall


def test_a_blobs_end_keeps_its_caps_normal() -> None:
    """A thick end whose two faces diverge (a heightmap's blob, 40 degrees apart) points
    along its cap's normal: the mean of its faces would aim the ray askew."""
    blob = _poly((0.0, 0.0), (2.0, 0.0), (2.0, 0.2), (0.0, 1.5))
    wall = [[3.0, -1.0, 3.0, 1.5]]
    o = door_openings(np.array(blob + wall, dtype=float))
    assert len(o) == 1
    assert o[0].tolist() == pytest.approx([2.0, 0.1, 3.0, 0.1], abs=1e-3)
