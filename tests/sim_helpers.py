"""Small synthetic worlds for the simulator tests."""

from __future__ import annotations

from typing import Any

from pico_studio.json_map import GlobalMap, map_from_dict


def box_map(w: float = 10.0, h: float = 10.0, **extra: Any) -> GlobalMap:
    """A closed w x h room with its lower-left corner at the origin; extra keys added as is
    (points for them are appended after the room's four corners, indices 4...)."""
    points = [{"x": 0, "y": 0}, {"x": w, "y": 0}, {"x": w, "y": h}, {"x": 0, "y": h}]
    points += extra.pop("more_points", [])
    data = {"points": points, "walls": [[0, 1], [1, 2], [2, 3], [3, 0]] + extra.pop("more_walls", [])}
    data.update(extra)
    return map_from_dict(data)


def door_map() -> GlobalMap:
    """The 10 x 10 m box split by an inner wall at x = 5 with a 1 m gap (y 4..5) closed by a
    0.1 m thick door."""
    return box_map(
        more_points=[
            {"x": 5, "y": 0}, {"x": 5, "y": 4}, {"x": 5, "y": 5}, {"x": 5, "y": 10},
            {"x": 4.95, "y": 4}, {"x": 5.05, "y": 4}, {"x": 5.05, "y": 5}, {"x": 4.95, "y": 5},
        ],
        more_walls=[[4, 5], [6, 7]],
        doors=[[[8, 9], [9, 10], [10, 11], [11, 8]]],
    )
