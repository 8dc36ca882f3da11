"""Behaviour names -> factories, and parsing `name[:args]` as the CLI and the UI give it.

    b = make_behaviour("hospital:0,3,1", cfg.behaviour, global_map, initial_pose=(x, y, a))
    b = make_behaviour("escape-room", cfg.behaviour)

Bad input (an unknown name, an argument where none is taken, a cabinet index that does not
exist or whose front is inside a wall) raises `UserError` naming the `--behaviour` field.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from pico_studio.config.behaviour_params import BehaviourParams
from pico_studio.core.behaviours.base import BehaviourBase, Pose
from pico_studio.core.behaviours.escape_room import EscapeRoom
from pico_studio.core.behaviours.hospital import HospitalTour
from pico_studio.core.behaviours.room_finder import RoomFinder
from pico_studio.errors import UserError
from pico_studio.json_map import GlobalMap

FIELD = "--behaviour"


def _no_arg(name: str, arg: str) -> None:
    if arg:
        raise UserError(f"{name} takes no argument, got {name}:{arg}", field=FIELD)


def _escape_room(arg: str, params: BehaviourParams, m: GlobalMap | None, pose: Pose | None) -> BehaviourBase:
    _no_arg("escape-room", arg)
    return EscapeRoom(params)


def _room_finder(arg: str, params: BehaviourParams, m: GlobalMap | None, pose: Pose | None) -> BehaviourBase:
    _no_arg("room-finder", arg)
    return RoomFinder(params)


def parse_indices(arg: str) -> list[int]:
    try:
        order = [int(t) for t in arg.split(",") if t.strip() != ""]
    except ValueError:
        raise UserError(f"hospital takes cabinet indices hospital:I,J,K, got {arg!r}", field=FIELD) from None
    return order


def _hospital(arg: str, params: BehaviourParams, m: GlobalMap | None, pose: Pose | None) -> BehaviourBase:
    if m is None:
        raise UserError("hospital needs a global map (--map)", field=FIELD)
    order = parse_indices(arg) if arg else list(range(len(m.objects)))
    return HospitalTour(params, m, order, initial_pose=pose)


Factory = Callable[[str, BehaviourParams, "GlobalMap | None", "Pose | None"], BehaviourBase]

BEHAVIOURS: dict[str, Factory] = {
    "escape-room": _escape_room,
    "room-finder": _room_finder,
    "hospital": _hospital,
}

# how long a run of each is given when the caller does not say (simulated seconds)
DEFAULT_SECONDS = {"escape-room": 120.0, "room-finder": 300.0, "hospital": 400.0}


def behaviour_name(spec: str) -> str:
    return spec.partition(":")[0].strip()


def is_behaviour(spec: str) -> bool:
    return behaviour_name(spec) in BEHAVIOURS


def make_behaviour(spec: str, params: BehaviourParams, global_map: GlobalMap | None = None,
                   initial_pose: Pose | None = None) -> Any:
    name, _, arg = spec.partition(":")
    name = name.strip()
    if name not in BEHAVIOURS:
        raise UserError(f"unknown behaviour {name!r}; known: {', '.join(BEHAVIOURS)}", field=FIELD)
    return BEHAVIOURS[name](arg.strip(), params, global_map, initial_pose)
