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


def _apart(walls: np.ndarray) -> np.ndarray:
    return np.full((len(walls), 2), -1, dtype=np.int64)  # no wall joins another


def _found(places: list[tuple[float, float]], params=PARAMS, door=DOOR, walls=WALLS, connected=None) -> DoorMemory:
    memory = DoorMemory()
    connected = _apart(walls) if connected is None else connected
    for xy in places:
        doors, kinds, memory = remember(memory, np.array([door]), ["jambs"], walls, connected, None, xy, params)
        assert has_gap(doors, door, 0.01) and kinds == ["jambs"]
    return memory


def _kept(memory: DoorMemory, walls: np.ndarray = WALLS, view=None, params=PARAMS, door=DOOR, connected=None,
          robot=(0.5, -1.0)) -> bool:
    connected = _apart(walls) if connected is None else connected
    doors, kinds, memory = remember(memory, np.zeros((0, 4)), [], walls, connected, view, robot, params)
    assert len(kinds) == len(doors)
    return has_gap(doors, door, 0.01)


def test_a_door_found_from_places_apart_stays_a_door():
    memory = _found([(-0.5, -1.0), (0.2, -1.2), (0.8, -1.4)])
    doors, kinds, after = remember(memory, np.zeros((0, 4)), [], WALLS, _apart(WALLS),
                                   laser_view(SOLID, (1.0, -1.2), 1.57), (1.0, -1.2), PARAMS)
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


def test_a_corridor_mouth_is_forgotten_once_its_side_is_seen():
    # a room (y > 0) whose wall along y 0 ends at P (1.2, 0) and turns there into a corridor's
    # side running 3 m down; the corridor's other side is the room's left wall x 0 running
    # straight on. From the room, the side unseen, the mouth P -> M is a doorway in shape
    mouth = [1.2, 0.0, 0.0, 0.0]
    room, face, side = [5.0, 0.0, 1.2, 0.0], [0.0, 4.0, 0.0, -3.0], [1.2, 0.0, 1.2, -3.0]
    unseen = np.array([room, face])
    memory = _found([(2.0, 1.5), (2.6, 1.8), (3.2, 2.0)], door=mouth, walls=unseen)
    assert _kept(memory, unseen, door=mouth, robot=(3.5, 2.0))  # its side unseen: kept
    seen = np.array([room, face, side])
    joined = np.array([[-1, 2], [-1, -1], [0, -1]], dtype=np.int64)  # P: the room's wall turns into the side
    assert not _kept(memory, seen, door=mouth, connected=joined, robot=(3.5, 2.0))
    assert not _kept(memory, seen, door=mouth, connected=joined, robot=(0.6, -1.5))  # from the corridor too
    # a doorway in a thick wall: its jamb turns into an end cap 0.2 m long, then the wall's other face
    thick = np.array([room, face, [1.2, 0.0, 1.2, -0.2], [1.2, -0.2, 5.0, -0.2]])
    capped = np.array([[-1, 2], [-1, -1], [0, 3], [2, -1]], dtype=np.int64)
    assert _kept(memory, thick, door=mouth, connected=capped, robot=(3.5, 2.0))


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
        args = (found, mem, scans, first, spread, 0.5, -1.0, 0.25, 0.95, 3, 1.0, walls, _apart(walls), 0.1, 0.35,
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
