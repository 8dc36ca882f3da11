"""Every room-finder seed is a world whose start faces no room (seed 000's assumption)."""

from __future__ import annotations

from pico_studio.evaluation.worlds import PANEL, make_world


def _faces_a_room(world) -> bool:
    x, y, _ = world.start
    for room in world.rooms:
        cx, cy = room["centre"]
        # walls 0 and 2 run along x, 1 and 3 along y: the robot's foot on the room's wall
        along, centre = (x, cx) if room["wall"] in (0, 2) else (y, cy)
        if abs(along - centre) <= PANEL / 2 + 0.25:
            return True
    return False


def test_every_seed_has_a_start_facing_no_room():
    # seed 92's first draw put a room on every wall of a small hall: no start faced none, and
    # `rooms:92` was an error; it is drawn again from the seed's next stream
    for seed in range(0, 120):
        world = make_world(f"rooms:{seed}")
        assert 2 <= len(world.rooms) <= 4
        assert not _faces_a_room(world), seed


def test_a_seed_is_the_same_world_every_time():
    a, b = make_world("rooms:92"), make_world("rooms:92")
    assert a.start == b.start and a.rooms == b.rooms
