"""A bay seen through to free space (`identify.bay_deep_rays`, off by default). In a building
without furniture (an escape room) a hallway's mouth whose side wall is seen edge-on is a bay to
the jamb rules (its corner is a short wall turning into the hallway's side, as a table's corner
against a wall), but the rays through it run on down the hallway and out: with the option on it
is a door of kind "bay". The same local walls with a wall 0.7 m behind the gap (the pocket
between a table and a wall) stay a possible bay: the rays end in the gap's shadow."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.identify import View, identify
from pico_studio.core.perception.identify_kernels import ray_hits

PARAMS = load_config(None).perception.identify
ROBOT = (4.54, 2.12)
# escape:10's exit seen from the room: the room's left wall x = 0 with the hallway's mouth from
# y = 2.11 to 3.04; the hallway's upper side seen, its lower side (y = 2.11) edge-on and unseen
TOP = [5.5, 3.64, 0.0, 3.64]
ABOVE = [0.0, 3.64, 0.0, 3.04]  # the room wall above the mouth, from the room's corner
SIDE = [0.0, 3.04, -1.18, 3.04]  # the hallway's upper side, its far end free
BELOW = [0.0, 2.11, 0.0, 0.75]  # the room wall below the mouth, running on out of view
WALLS = np.array([TOP, ABOVE, SIDE, BELOW])
CONNECTED = np.array([[-1, 1], [0, 2], [1, -1], [-1, -1]], dtype=np.int64)
SEEN = np.array([[False, False], [False, False], [False, True], [True, False]])
MOUTH = np.array([0.0, 2.11, 0.0, 3.04])


def _view(solid: list[list[float]]) -> View:
    """The laser at ROBOT (facing the mouth) cast against `solid` walls, 8 m beyond nothing."""
    heading = np.pi
    angles = np.linspace(-2.0, 2.0, 801)
    direction = np.stack([np.cos(angles + heading), np.sin(angles + heading)], axis=1)
    none = np.full(len(angles), -1, dtype=np.int64)
    ranges, _ = ray_hits(np.tile(ROBOT, (len(angles), 1)), direction, np.array(solid, dtype=float), none, none)
    hit = np.isfinite(ranges) & (ranges < 8.0)
    return View(np.where(hit, ranges, 0.0), angles, hit, (ROBOT[0], ROBOT[1], heading))


def _is(gaps: np.ndarray, gap: np.ndarray) -> bool:
    return any(np.allclose(g, gap, atol=1e-6) or np.allclose(g, np.r_[gap[2:], gap[:2]], atol=1e-6) for g in gaps)


def _identify(view: View, params=PARAMS):
    return identify(WALLS, CONNECTED, SEEN, ROBOT, params, view)


HALLWAY = [TOP, ABOVE, SIDE, [0.0, 2.11, -1.18, 2.11], [0.0, 2.11, 0.0, 0.0]]


def test_a_hallways_mouth_seen_through_is_a_door_with_the_option_on():
    view = _view(HALLWAY)
    off = _identify(view)
    assert PARAMS.bay_deep_rays == 0 and len(off.doors) == 0
    assert _is(off.possible_doors[[k == "bay" for k in off.possible_door_kind]], MOUTH)
    on = _identify(view, replace(PARAMS, bay_deep_rays=1))
    assert on.door_kind == ["bay"] and _is(on.doors, MOUTH)
    assert "bay" not in on.possible_door_kind  # the door, not a possible door as well


def test_a_pocket_behind_the_same_walls_stays_a_possible_bay():
    pocket = HALLWAY + [[-0.7, 2.11, -0.7, 3.04]]  # a wall 0.7 m behind the gap: a table's pocket
    on = _identify(_view(pocket), replace(PARAMS, bay_deep_rays=1))
    assert len(on.doors) == 0
    assert _is(on.possible_doors[[k == "bay" for k in on.possible_door_kind]], MOUTH)


def test_without_a_scan_the_local_maps_walls_decide():
    params = replace(PARAMS, bay_deep_rays=1)
    assert identify(WALLS, CONNECTED, SEEN, ROBOT, params, None).door_kind == ["bay"]
    back = np.vstack([WALLS, [[-0.7, 2.11, -0.7, 3.04]]])  # the pocket's back wall in the local map
    out = identify(back, np.vstack([CONNECTED, [[-1, -1]]]), np.vstack([SEEN, [[True, True]]]), ROBOT, params, None)
    assert len(out.doors) == 0


def test_the_unfurnished_example_config_turns_it_on():
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "examples" / "configs" / "unfurnished.yaml"
    assert load_config(path).perception.identify.bay_deep_rays == 1
