"""Door memory: a door found from places a metre apart stays a door, found no more, while it
stays open (door_memory); from one place only, or closed, or its jamb gone, it does not."""

from __future__ import annotations

import dataclasses

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.door_memory import DoorMemory, remember
from tests.clutter_scenes import has_gap, laser_view

PARAMS = load_config(None).perception.identify
WALLS = np.array([[-3.0, 0.0, 0.0, 0.0], [0.9, 0.0, 4.0, 0.0]])  # a corridor wall, a doorway 0.9 m wide
DOOR = [0.0, 0.0, 0.9, 0.0]
SOLID = [[-3.0, 0.0, 0.0, 0.0], [0.9, 0.0, 4.0, 0.0], [-3.0, 3.0, 4.0, 3.0]]  # the room behind it open to y 3


def _found(places: list[tuple[float, float]], params=PARAMS) -> DoorMemory:
    memory = DoorMemory()
    for xy in places:
        doors, kinds, memory = remember(memory, np.array([DOOR]), ["jambs"], WALLS, None, xy, params)
        assert has_gap(doors, DOOR, 0.01) and kinds == ["jambs"]
    return memory


def _kept(memory: DoorMemory, walls: np.ndarray = WALLS, view=None, params=PARAMS) -> bool:
    doors, kinds, memory = remember(memory, np.zeros((0, 4)), [], walls, view, (0.5, -1.0), params)
    assert len(kinds) == len(doors)
    return has_gap(doors, DOOR, 0.01)


def test_a_door_found_from_places_apart_stays_a_door():
    memory = _found([(-0.5, -1.0), (0.2, -1.2), (0.8, -1.4)])
    doors, kinds, after = remember(memory, np.zeros((0, 4)), [], WALLS, laser_view(SOLID, (1.0, -1.2), 1.57),
                                   (1.0, -1.2), PARAMS)
    assert has_gap(doors, DOOR, 0.01) and kinds == ["jambs"]
    assert _kept(after)  # and the scan after


def test_from_one_place_or_too_few_scans_it_is_not():
    assert not _kept(_found([(0.5, -1.0)] * 6))  # a robot turning on the spot
    assert not _kept(_found([(-0.5, -1.0), (0.8, -1.4)]))  # two scans


def test_a_closed_door_or_a_lost_jamb_is_forgotten():
    memory = _found([(-0.5, -1.0), (0.2, -1.2), (0.8, -1.4)])
    assert not _kept(memory, np.vstack([WALLS, [[0.45, -0.3, 0.45, 0.3]]]))  # a wall across it
    assert not _kept(memory, np.vstack([WALLS, [[0.3, 0.02, 0.6, 0.02]]]))  # a wall in it: the leaf closed
    assert not _kept(memory, WALLS[:1])  # its far jamb's wall gone from the local map
    standing = laser_view(SOLID + [[0.2, 0.05, 0.7, 0.05]], (0.5, -1.0), 1.57)  # someone in the doorway
    assert not _kept(memory, view=standing)
    assert _kept(memory, view=laser_view(SOLID, (0.5, -1.0), 1.57))  # nothing there: kept


def test_no_memory_when_off():
    off = dataclasses.replace(PARAMS, door_memory_scans=0)
    assert not _kept(_found([(-0.5, -1.0), (0.2, -1.2), (0.8, -1.4)], off), params=off)


def test_carry_answers_as_its_python():
    from pico_studio import jit
    from pico_studio.core.perception.door_memory_kernels import carry
    from pico_studio.core.perception.identify import _view_arrays

    mem = np.array([DOOR, [0.0, 0.0, 0.0, 1.0], [2.0, 0.0, 2.9, 0.3]])
    scans, first, spread = np.array([5, 1, 4], dtype=np.int64), np.zeros((3, 2)), np.array([1.2, 0.0, 1.4])
    cases = [(found, WALLS, SOLID) for found in (np.zeros((0, 4)), np.array([[0.02, 0.0, 0.9, 0.01]]),
                                                np.array([[5.0, 5.0, 6.0, 5.0]]))]
    # the remembered doors closed by a wall in the doorway, someone standing in it, a jamb gone
    cases += [(np.zeros((0, 4)), np.vstack([WALLS, [[0.3, 0.02, 0.6, 0.02]]]), SOLID),
              (np.zeros((0, 4)), WALLS, SOLID + [[0.2, 0.05, 0.7, 0.05]]), (np.zeros((0, 4)), WALLS[:1], SOLID)]
    kept = []
    for found, walls, solid in cases:
        args = (found, mem, scans, first, spread, 0.5, -1.0, 0.25, 0.95, 3, 1.0, walls, 0.1,
                *_view_arrays(laser_view(solid, (0.5, -1.0), 1.57)))
        got, want = carry(*args), jit.py_func(carry)(*args)
        for a, b in zip(got, want, strict=True):
            np.testing.assert_array_equal(a, b)
        kept.append(got[0].tolist())
    assert kept[0] == [0] and kept[3:] == [[], [], []]  # the doorway open, then closed three ways


def test_the_page_draws_a_remembered_door_apart():
    from pico_studio.core.world_model import WorldModel
    from pico_studio.ui import style
    from pico_studio.ui.scene_data import _door_prims

    wm = WorldModel(doors=np.array([DOOR, [2.0, 0.0, 2.9, 0.0]]), door_kind=["jambs", "bay"],
                    door_remembered=np.array([False, True]))
    colours = _door_prims(wm, (0.0, 0.0, 0.0))["doors"].colors
    assert colours is not None
    assert tuple(colours[0]) == style.DOOR and tuple(colours[1]) == style.DOOR_REMEMBERED
