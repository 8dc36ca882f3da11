"""Every behaviour by name, and parsing `name[:args]` as the CLI and the page give it.

    b = make_behaviour("hospital:0,3,1", cfg, global_map, pose=(x, y, a))
    b = make_behaviour("drive:0.3,0,0.2", cfg)
    cmd = b.step(world_model, laser, odometry, now, ok=io.ok())   # the one protocol

`params` is the whole `Config` (a factory reads its section: `cfg.behaviour`, `cfg.ui.wander`)
or, for older callers, just the `BehaviourParams` (wander then runs on its defaults).
`BEHAVIOURS` is a plain dict name -> `Entry(factory, help)`: `register_behaviour` (or a plain
assignment) adds one; the CLI's `--behaviour` and the page's dropdown list it.

Bad input (an unknown name, an argument where none is taken, a cabinet index that does not
exist or whose front is inside a wall) raises `UserError` naming the `--behaviour` field.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from pico_studio.config.behaviour_params import BehaviourParams
from pico_studio.config.ui_params import WanderParams
from pico_studio.core.behaviours.base import Pose
from pico_studio.core.behaviours.escape_room import EscapeRoom
from pico_studio.core.behaviours.hospital import HospitalTour
from pico_studio.core.behaviours.room_finder import RoomFinder
from pico_studio.core.behaviours.wander import Wander
from pico_studio.core.io import STOP, Command, LaserData, OdometryData
from pico_studio.errors import UserError
from pico_studio.json_map import GlobalMap

FIELD = "--behaviour"


class Constant:
    """A behaviour that sends the same command every tick (`drive:VX,VY,VA`, `stop`), or
    nothing at all (`idle`, command None: the source keeps its reference, zero at start)."""

    target = None
    plan = None
    frame = "zero"
    done = False

    def __init__(self, name: str, command: Command | None):
        self.name = name
        self.state = name
        self.command = command

    def step(self, world_model: Any, laser: LaserData | None, odometry: OdometryData | None,
             now: float, *, ok: bool = True) -> Command | None:
        if not ok:
            return STOP if self.command is not None else None
        return self.command

    def result(self) -> dict[str, Any]:
        return {"state": self.state}


def Drive(vx: float, vy: float, va: float) -> Constant:  # noqa: N802 - reads as a class
    """`drive:VX,VY,VA`: the same base reference every tick."""
    return Constant("drive", Command(float(vx), float(vy), float(va)))


@dataclass(frozen=True)
class Settings:
    """What a factory may read: the behaviours' section and the wander's."""

    behaviour: BehaviourParams
    wander: WanderParams


Factory = Callable[[str, Settings, "GlobalMap | None", "Pose | None"], Any]


@dataclass(frozen=True)
class Entry:
    factory: Factory
    help: str
    needs_argument: bool = False  # only `name:ARGS` makes one (a menu without a text field skips it)
    usage: str = ""  # how to spell it with its arguments, e.g. "drive:VX,VY,VA" (default: the name)


def _no_arg(name: str, arg: str) -> None:
    if arg:
        raise UserError(f"{name} takes no argument, got {name}:{arg}", field=FIELD)


def _escape_room(arg: str, s: Settings, m: GlobalMap | None, pose: Pose | None) -> Any:
    _no_arg("escape-room", arg)
    return EscapeRoom(s.behaviour)


def _room_finder(arg: str, s: Settings, m: GlobalMap | None, pose: Pose | None) -> Any:
    _no_arg("room-finder", arg)
    return RoomFinder(s.behaviour)


def parse_indices(arg: str) -> list[int]:
    try:
        order = [int(t) for t in arg.split(",") if t.strip() != ""]
    except ValueError:
        raise UserError(f"hospital takes cabinet indices hospital:I,J,K, got {arg!r}", field=FIELD) from None
    return order


def _hospital(arg: str, s: Settings, m: GlobalMap | None, pose: Pose | None) -> Any:
    if m is None:
        raise UserError("hospital needs a global map (--map)", field=FIELD)
    order = parse_indices(arg) if arg else list(range(len(m.objects)))
    return HospitalTour(s.behaviour, m, order, initial_pose=pose)


def _wander(arg: str, s: Settings, m: GlobalMap | None, pose: Pose | None) -> Any:
    _no_arg("wander", arg)
    return Wander(s.wander)


def _drive(arg: str, s: Settings, m: GlobalMap | None, pose: Pose | None) -> Any:
    try:
        vx, vy, va = (float(p) for p in arg.split(","))
    except ValueError:
        raise UserError(f"drive needs three numbers drive:VX,VY,VA, got {arg!r}", field=FIELD) from None
    if not all(math.isfinite(v) for v in (vx, vy, va)):
        raise UserError(f"drive needs finite numbers, got {arg!r}", field=FIELD)
    return Drive(vx, vy, va)


def _idle(arg: str, s: Settings, m: GlobalMap | None, pose: Pose | None) -> Any:
    _no_arg("idle", arg)
    return Constant("idle", None)


def _stop(arg: str, s: Settings, m: GlobalMap | None, pose: Pose | None) -> Any:
    _no_arg("stop", arg)
    return Constant("stop", STOP)


BEHAVIOURS: dict[str, Entry] = {
    "wander": Entry(_wander, "reactive wall-avoiding wander on the raw laser"),
    "escape-room": Entry(_escape_room, "find the exit of a room and drive out (issue 7)"),
    "room-finder": Entry(_room_finder, "visit the side rooms and count their objects"),
    "hospital": Entry(_hospital, "visit the map's cabinets in that order (needs --map)", usage="hospital[:I,J,K]"),
    "drive": Entry(_drive, "the same base reference every tick", needs_argument=True, usage="drive:VX,VY,VA"),
    "idle": Entry(_idle, "send nothing (the robot stands still)"),
    "stop": Entry(_stop, "send zero velocity every tick"),
}

# how long a run of each is given when the caller does not say (simulated seconds)
DEFAULT_SECONDS = {"escape-room": 120.0, "room-finder": 300.0, "hospital": 400.0}


def register_behaviour(name: str, factory: Factory, help: str = "", *,  # noqa: A002
                       needs_argument: bool = False, usage: str = "") -> None:
    """Add (or replace) a behaviour: `factory(arg, settings, global_map, pose)`."""
    BEHAVIOURS[name] = Entry(factory, help, needs_argument, usage)


def behaviour_name(spec: str) -> str:
    return spec.partition(":")[0].strip()


def is_behaviour(spec: str) -> bool:
    return behaviour_name(spec) in BEHAVIOURS


def behaviour_help() -> str:
    """One line for `--behaviour`'s help: every name (with its argument when it takes one)."""
    return " | ".join(e.usage or n for n, e in BEHAVIOURS.items())


def settings(params: Any) -> Settings:
    """A `Config` or a bare `BehaviourParams` as a factory's `Settings`."""
    if isinstance(params, Settings):
        return params
    if isinstance(params, BehaviourParams):
        return Settings(params, WanderParams())
    return Settings(params.behaviour, params.ui.wander)


def make_behaviour(spec: str, params: Any, global_map: GlobalMap | None = None,
                   pose: Pose | None = None, *, initial_pose: Pose | None = None) -> Any:
    """The behaviour `spec` names, built from `params` (a `Config` or `BehaviourParams`),
    the global map and the robot's map pose now, when known."""
    name, _, arg = spec.partition(":")
    name = name.strip()
    if name not in BEHAVIOURS:
        raise UserError(f"unknown behaviour {name!r}; known: {', '.join(BEHAVIOURS)}", field=FIELD)
    return BEHAVIOURS[name].factory(arg.strip(), settings(params), global_map,
                                    pose if pose is not None else initial_pose)
