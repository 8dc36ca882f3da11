"""Once localised, the map's door openings (`GlobalMap.openings`, what the truth scores
against) confirm door candidates: a candidate across a map door is confirmed, one between two
tables is not (restaurant_2024's door leaves)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.localisation import build_localisation_map, combine
from pico_studio.core.localisation.combined import confirmed_by_map
from pico_studio.json_map import load_map
from pico_studio.json_map.openings import door_openings

PARAMS = load_config(None).localisation
RESTAURANT = Path(__file__).resolve().parents[1] / "examples" / "maps" / "restaurant_2024.json"


def test_a_door_leaf_gives_the_line_across_its_passage():
    leaf = np.array([[3.6, 1.8], [4.6, 1.8], [4.6, 2.0], [3.6, 2.0]])
    line = door_openings(np.zeros((0, 4)), [leaf])[0]
    ends = sorted([tuple(np.round(line[0:2], 6)), tuple(np.round(line[2:4], 6))])
    assert np.allclose(ends, [(3.6, 1.9), (4.6, 1.9)])


def test_an_opening_between_map_walls_is_confirmed_a_table_gap_not():
    walls = np.array([[0.0, 0.0, 2.0, 0.0], [2.9, 0.0, 5.0, 0.0], [2.0, 0.0, 2.0, -0.2]])
    p = PARAMS.combined
    gap = np.array([[2.02, 0.03, 2.88, -0.02]])  # wall corner to wall end
    tee = np.array([[2.0, 0.05, 2.0, 0.95]])  # wall corner to nowhere: no jamb on the far side
    table = np.array([[3.5, 1.5, 4.3, 1.5]])  # two table corners in the room
    got = confirmed_by_map(np.vstack([gap, tee, table]), door_openings(walls), p)
    assert got.tolist() == [True, False, False]


def test_candidates_across_a_map_door_are_confirmed_others_not():
    lmap = build_localisation_map(load_map(str(RESTAURANT)), PARAMS)
    assert len(lmap.openings) >= 1
    on = np.array([[3.62, 1.95, 4.58, 1.9]])  # across the door leaf at (3.6..4.6, 1.8..2.0)
    turned = np.array([[4.1, 1.4, 4.1, 2.4]])  # at the same place, across the leaf's direction
    tables = np.array([[3.41, 4.1, 2.25, 4.25]])  # between a table and a box
    got = confirmed_by_map(np.vstack([on, turned, tables]), lmap.openings, PARAMS.combined)
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
                 map_openings=lmap.openings)
    assert np.allclose(cm.doors, [[3.62, 1.95, 4.58, 1.9], tee])
    assert cm.door_confirmed.tolist() == [True, True] and cm.door_promoted.tolist() == [False, True]
    assert np.allclose(cm.possible_doors, [tables, tee]) and list(cm.possible_door_kind) == ["end_face", "loose_wall"]
    assert cm.possible_door_confirmed.tolist() == [False, True]


def test_the_combined_map_confirms_the_truths_openings_and_only_those():
    """One list of openings: the truth scores against `GlobalMap.openings` and the combined map
    confirms against it. On hospital_2021.png (a heightmap: every outline vertex a corner) the
    gap from the middle block's corner to the corridor wall's face (1.2 m, the corridor going on
    past it) is no opening, and was confirmed by the combined map's old corner-to-wall rule."""
    from pico_studio.config import Config
    from pico_studio.sim import Simulator

    cfg = Config()
    gmap = load_map(str(RESTAURANT.parent / "hospital_2021.png"), cfg.map)
    sim = Simulator(gmap, cfg.sim, seed=0)
    openings = gmap.openings()
    assert len(openings) >= 8 and np.array_equal(sim.truth.door_openings(), openings)
    lmap = build_localisation_map(gmap, PARAMS)
    assert confirmed_by_map(openings, lmap.openings, PARAMS.combined).all()
    corridor = np.array([[-1.7, 1.97, -2.92, 1.94]])
    assert confirmed_by_map(corridor, lmap.openings, PARAMS.combined).tolist() == [False]


def test_the_maps_opening_parameters_are_its_loaders():
    """`load_map(path, cfg.map)` gives the map `cfg.map.openings`: a narrower maximum width
    drops the wider gaps between wall ends from its openings (and so from the truth's and the
    combined map's); the map's door leaf stays an opening whatever its width."""
    from dataclasses import replace

    from pico_studio.config import Config

    cfg = Config()
    wide = load_map(str(RESTAURANT), cfg.map).openings()
    narrow_params = replace(cfg.map, openings=replace(cfg.map.openings, door_max_width=0.9))
    narrow = load_map(str(RESTAURANT), narrow_params).openings()
    widths = np.hypot(wide[:, 2] - wide[:, 0], wide[:, 3] - wide[:, 1])
    assert (widths > 0.9).any() and len(narrow) < len(wide)
    assert all(any(np.allclose(n, w) for w in wide) for n in narrow)
    assert any(np.allclose(n, [3.6, 1.9, 4.6, 1.9]) for n in narrow)  # the door leaf's line


def test_a_jamb_whose_other_side_is_out_of_view_becomes_the_map_opening_at_its_end():
    """restaurant_2024 seeds 7 and 11's missed door: the partition's end (4.8, 1.2) is seen, the
    floor wall's face 1 m below it only as a fragment. The jamb alone (possible kind "jamb", from
    the end a door's greatest width on along the wall) is the door of the map opening at that
    end, leaving its way; a jamb where the map has no opening stays possible, and one where a
    door already stands adds none."""
    lmap = build_localisation_map(load_map(str(RESTAURANT)), PARAMS)
    pose = (1.0, 1.0, 0.0)
    jamb = [4.79, 1.2, 4.79, -0.1]
    nowhere = [2.0, 3.0, 3.3, 3.0]
    opening = [4.7, 1.2, 4.7, 0.2]
    args = (pose, pose, np.zeros((0, 4)), lmap.field, np.zeros(len(lmap.field.segments), dtype=np.int64),
            lmap.n_walls, PARAMS.combined)
    cm = combine(*args, possible_doors=np.array([jamb, nowhere]), possible_door_kind=["jamb", "jamb"],
                 map_openings=lmap.openings)
    assert len(cm.doors) == 1 and confirmed_by_map(cm.doors, np.array([opening]), PARAMS.combined).all()
    assert cm.door_promoted.tolist() == [True] and np.allclose(cm.possible_doors, [nowhere])
    askew = [4.79, 1.2, 5.71, 0.28]  # the same end leaving at 45 degrees to the opening: not its door
    cm = combine(*args, possible_doors=np.array([askew]), possible_door_kind=["jamb"], map_openings=lmap.openings)
    assert len(cm.doors) == 0
    turned = [4.79, 1.2, 6.09, 1.2]  # a wall along y = 1.2 ending there: the opening is its passage's mouth
    cm = combine(*args, possible_doors=np.array([turned]), possible_door_kind=["jamb"], map_openings=lmap.openings)
    assert len(cm.doors) == 1 and confirmed_by_map(cm.doors, np.array([opening]), PARAMS.combined).all()
    cm = combine(*args, doors=np.array([opening]), possible_doors=np.array([jamb]), possible_door_kind=["jamb"],
                 map_openings=lmap.openings)
    assert len(cm.doors) == 1 and cm.door_promoted.tolist() == [False]


def test_a_jambs_opening_is_the_nearest_leaving_its_way():
    from pico_studio.core.localisation.combined import opening_at_jamb

    jamb = np.array([0.0, 0.0, 0.0, -1.3])
    near, farther, across = [0.05, 0.02, 0.05, -0.98], [0.0, 0.25, 0.0, -0.75], [0.0, 0.01, 1.0, 0.01]
    got = opening_at_jamb(jamb, np.array([across, near, farther]), PARAMS.combined)
    assert got is not None and np.allclose(got, near)
    got = opening_at_jamb(jamb, np.array([[0.05, -0.98, 0.05, 0.02]]), PARAMS.combined)  # drawn the other way
    assert got is not None and np.allclose(got, near)
    # no opening leaves along it: the one across its end, a passage's mouth (escape rooms' exits
    # seen from the room, the hallway's far end); none leaving askew
    got = opening_at_jamb(jamb, np.array([across]), PARAMS.combined)
    assert got is not None and np.allclose(got, across)
    assert opening_at_jamb(jamb, np.array([[0.0, 0.01, 0.7, -0.7]]), PARAMS.combined) is None
