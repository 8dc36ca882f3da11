"""Once localised, the map's doors confirm door candidates: a candidate across a map door is
confirmed, one between two tables is not (restaurant_2024's door leaves)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.localisation import build_localisation_map, combine
from pico_studio.core.localisation.combined import confirmed_by_map, map_door_lines
from pico_studio.json_map import load_map

PARAMS = load_config(None).localisation
RESTAURANT = Path(__file__).resolve().parents[1] / "examples" / "maps" / "restaurant_2024.json"


def test_a_door_leaf_gives_the_line_across_its_passage():
    leaf = np.array([[3.6, 1.8], [4.6, 1.8], [4.6, 2.0], [3.6, 2.0]])
    line = map_door_lines([leaf])[0]
    ends = sorted([tuple(np.round(line[0:2], 6)), tuple(np.round(line[2:4], 6))])
    assert np.allclose(ends, [(3.6, 1.9), (4.6, 1.9)])


def test_an_opening_between_map_walls_is_confirmed_a_table_gap_not():
    walls = np.array([[0.0, 0.0, 2.0, 0.0], [2.9, 0.0, 5.0, 0.0], [2.0, 0.0, 2.0, -0.2]])
    p = PARAMS.combined
    gap = np.array([[2.02, 0.03, 2.88, -0.02]])  # wall corner to wall end
    tee = np.array([[2.0, 0.05, 2.0, 0.95]])  # wall corner to nowhere: no jamb on the far side
    table = np.array([[3.5, 1.5, 4.3, 1.5]])  # two table corners in the room
    got = confirmed_by_map(np.vstack([gap, tee, table]), np.zeros((0, 4)), walls, p)
    assert got.tolist() == [True, False, False]


def test_candidates_across_a_map_door_are_confirmed_others_not():
    lmap = build_localisation_map(load_map(str(RESTAURANT)), PARAMS)
    assert len(lmap.door_lines) >= 1
    on = np.array([[3.62, 1.95, 4.58, 1.9]])  # across the door leaf at (3.6..4.6, 1.8..2.0)
    turned = np.array([[4.1, 1.4, 4.1, 2.4]])  # at the same place, across the leaf's direction
    tables = np.array([[3.41, 4.1, 2.25, 4.25]])  # between a table and a box
    walls = lmap.field.segments[: lmap.n_walls]
    got = confirmed_by_map(np.vstack([on, turned, tables]), lmap.door_lines, walls, PARAMS.combined)
    assert got.tolist() == [True, False, False]


def test_a_t_opening_waiting_for_evidence_becomes_a_door_where_the_map_has_one():
    """Possible doors of kind "end_face" (a T-opening on a wall seen short, not yet proven over
    scans) that the map confirms are promoted to doors of the combined map; one the map does not
    confirm, and other possible kinds, stay possible doors."""
    lmap = build_localisation_map(load_map(str(RESTAURANT)), PARAMS)
    pose = (1.0, 1.0, 0.0)  # zero frame = global frame
    tee = [4.6, 1.2, 4.6, 0.2]  # the block's end (4.6..4.8, 1.2) to the floor wall's face
    tables = [3.41, 4.1, 2.25, 4.25]
    possible = np.array([tee, tables, tee])
    cm = combine(pose, pose, np.zeros((0, 4)), lmap.field, np.zeros(len(lmap.field.segments), dtype=np.int64),
                 lmap.n_walls, PARAMS.combined, doors=np.array([[3.62, 1.95, 4.58, 1.9]]),
                 possible_doors=possible, possible_door_kind=["end_face", "end_face", "loose_wall"],
                 map_doors=lmap.door_lines)
    assert np.allclose(cm.doors, [[3.62, 1.95, 4.58, 1.9], tee])
    assert cm.door_confirmed.tolist() == [True, True] and cm.door_promoted.tolist() == [False, True]
    assert np.allclose(cm.possible_doors, [tables, tee]) and list(cm.possible_door_kind) == ["end_face", "loose_wall"]
    assert cm.possible_door_confirmed.tolist() == [False, True]
