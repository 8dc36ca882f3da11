"""Bays: a door's shape the jamb rules refuse. A side room's mouth between two 1 m pieces of a
thin wall looks, in the local map alone, exactly like the bay between two tables standing by a
wall (each piece with its sides is a block's front and sides). The perceptor makes no door of
it but a possible door of kind "bay"; once localised, the combined map makes it a door where
the global map's walls have an opening there (rooms:5), and leaves it possible where they have
none (furniture). A hallway's far end (two parallel walls' ends, the gap across both) is a bay
too: the truth's passage mouth."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.localisation import build_localisation_map, combine
from pico_studio.core.localisation.combined import confirmed_by_map
from pico_studio.core.perception.identify import identify
from pico_studio.evaluation.worlds import make_world
from pico_studio.json_map import load_map

CONFIG = load_config(None)
RESTAURANT = Path(__file__).resolve().parents[1] / "examples" / "maps" / "restaurant_2024.json"
PARAMS = CONFIG.perception.identify

# rooms:5's wall x = 6.415 seen from the main room (x < 6.415): a 1 m wall piece between two
# 1 m deep side rooms, each turning at a convex corner into a side room's wall
SIDE_ROOM = ([[6.415, 0.0, 6.415, 1.192], [6.415, 1.192, 7.2, 1.192],  # the piece below, its side running in
              [6.415, 2.192, 6.415, 3.204], [6.415, 2.192, 7.0, 2.192],  # the piece between the rooms, its sides
              [6.415, 3.204, 7.1, 3.204]],
             [[-1, 1], [0, -1], [3, 4], [2, -1], [2, -1]],
             [[False, False], [False, False], [False, False], [False, False], [False, False]])
ROBOT = (4.6, 1.8)
MOUTH = [6.415, 1.192, 6.415, 2.192]


def _identify(walls: list[list[float]], connected: list[list[int]], seen: list[list[bool]],
              robot: tuple[float, float], params=PARAMS):
    return identify(np.array(walls, dtype=float), np.array(connected, dtype=np.int64), np.array(seen, dtype=bool),
                    robot, params)


def _has(gaps: np.ndarray, gap: list[float]) -> bool:
    g = np.asarray(gap)
    return any(np.allclose(p, g, atol=1e-6) or np.allclose(p, np.r_[g[2:], g[:2]], atol=1e-6) for p in gaps)


def test_a_side_rooms_mouth_between_block_corners_is_a_possible_bay():
    out = _identify(*SIDE_ROOM, ROBOT)
    assert len(out.doors) == 0  # the jambs are a block's corners: no door from the local map alone
    bays = out.possible_doors[[k == "bay" for k in out.possible_door_kind]]
    assert _has(bays, MOUTH)
    off = _identify(*SIDE_ROOM, ROBOT, replace(PARAMS, bay_doors=False))
    assert "bay" not in off.possible_door_kind


def test_a_wall_across_the_mouth_leaves_no_bay():
    walls, connected, seen = SIDE_ROOM
    across = [[6.3, 1.7, 6.6, 1.7]]  # something standing in the mouth, crossing it
    out = _identify(walls + across, connected + [[-1, -1]], seen + [[True, True]], ROBOT)
    assert not _has(out.possible_doors, MOUTH)


def test_a_hallways_far_end_is_a_bay():
    """escape:2's exit: a hallway 0.93 m wide, its two 1.1 m walls ending free (seen) side by
    side; the gap across their ends is the passage's mouth."""
    walls = [[3.78, 2.02, 4.88, 2.02], [3.78, 2.95, 4.88, 2.95]]
    out = _identify(walls, [[-1, -1], [-1, -1]], [[False, True], [False, True]], (6.0, 3.6))
    assert len(out.doors) == 0
    bays = out.possible_doors[[k == "bay" for k in out.possible_door_kind]]
    assert _has(bays, [4.88, 2.02, 4.88, 2.95])
    # the two walls pointing opposite ways (a staggered pair, not a passage) make none
    flipped = [[3.78, 2.02, 4.88, 2.02], [5.98, 2.95, 4.88, 2.95]]
    out = _identify(flipped, [[-1, -1], [-1, -1]], [[False, True], [False, True]], (6.0, 3.6))
    assert not _has(out.possible_doors[[k == "bay" for k in out.possible_door_kind]], [4.88, 2.02, 4.88, 2.95])


def test_the_map_makes_a_bay_a_door_where_its_walls_open_and_not_among_furniture():
    lmap = build_localisation_map(make_world("rooms:5").map, CONFIG.localisation)
    pose = (0.0, 0.0, 0.0)  # zero frame = global frame
    furniture = [2.0, 3.0, 2.0, 4.0]  # the same shape in the open room: between two tables
    possible = np.array([MOUTH, furniture])
    cm = combine(pose, pose, np.zeros((0, 4)), lmap.field, np.zeros(len(lmap.field.segments), dtype=np.int64),
                 lmap.n_walls, CONFIG.localisation.combined, doors=np.zeros((0, 4)), possible_doors=possible,
                 possible_door_kind=["bay", "bay"], map_openings=lmap.openings)
    assert np.allclose(cm.doors, [MOUTH]) and cm.door_promoted.tolist() == [True]
    assert np.allclose(cm.possible_doors, [furniture]) and cm.possible_door_confirmed.tolist() == [False]


def test_a_gap_along_a_thick_walls_face_is_no_map_opening():
    """restaurant_2024's thick walls: from a map wall's corner to a point on the same block's
    face, along it (the local map's wall broke there), both ends lie on map walls but the gap is
    no opening: its middle is on a wall. The T-opening by the block at x = 4.6..4.8 is one."""
    lmap = build_localisation_map(load_map(str(RESTAURANT)), CONFIG.localisation)
    gaps = np.array([[2.1, 2.0, 2.0, 1.5], [3.0, 2.0, 2.1, 2.0], [4.7, 1.2, 4.7, 0.2]])
    got = confirmed_by_map(gaps, lmap.openings, CONFIG.localisation.combined)
    assert got.tolist() == [False, False, True]
