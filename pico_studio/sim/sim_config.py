"""The official simulator's config JSON: start pose, odometry/speed-cap switches, moving objects.

    {"initial_pose": [x, y, a], "uncertain_odom": true, "disable_speedcap": false,
     "objects": [{"length": 1.0, "width": 0.5, "init_pose": [x, y, a], "final_pose": [x, y, a],
                  "velocity": 0.6, "trigger_radius": 2.0, "repeat": false}]}

`pico_pose` is the older name of `initial_pose`. Keys the official simulator knows but that do
not apply here (`show_full_map`, `enable_taco`, `provide_internal_pose`, ...) are accepted and
listed in `ignored`. A value of the wrong type is a `SourceError` naming the file and field.

Ranges (errors, because each one made a run that looked fine but meant nothing):
* poses within `MAX_COORDINATE_M` (10 km) of the origin, like map points, and angles within
  +-`MAX_ANGLE` rad;
* an object's `velocity` at most `MAX_OBJECT_SPEED` (10 m/s; the official objects move at
  0.2 - 1 m/s): at 1e12 m/s an object jumps across the map between two laser scans, so the
  scan never sees it; `length`, `width` at most 100 m, `trigger_radius` at most 1 km;
* the start pose inside the map's bounds (plus `START_MARGIN`), checked by
  `check_start_pose` once the map is known: a robot outside the map sees no wall, so a
  perceptor run "scores" P 1.0 R 1.0 on nothing. An error, not a warning: no result from
  such a run is usable. (A start inside a wall is refused by the simulator itself.)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pico_studio.errors import SourceError, short
from pico_studio.json_map.model import MAX_COORDINATE_M
from pico_studio.user_files import read_json

Pose = tuple[float, float, float]
MAX_OBJECT_SPEED = 10.0  # m/s
MAX_OBJECT_SIZE = 100.0  # m
MAX_TRIGGER_RADIUS = 1000.0  # m
MAX_ANGLE = 1000.0  # rad: any angle wraps, but 1e300 has no digits left to wrap
START_MARGIN = 1.0  # m around the map's bounds that still count as "in the map"


@dataclass(frozen=True)
class MovingObjectSpec:
    """A box `length` (along its x) by `width` that drives from init_pose to final_pose."""

    length: float
    width: float
    init_pose: Pose
    final_pose: Pose
    velocity: float
    trigger_radius: float
    repeat: bool


@dataclass(frozen=True)
class SimConfigFile:
    initial_pose: Pose | None = None
    uncertain_odom: bool | None = None
    disable_speedcap: bool | None = None
    objects: tuple[MovingObjectSpec, ...] = ()
    ignored: tuple[str, ...] = ()
    source: Path | None = None
    field_of_pose: str = "initial_pose"  # which key the start pose came from, for error messages


def load_sim_config(path: str | Path) -> SimConfigFile:
    p = Path(path)
    return sim_config_from_dict(read_json(p, SourceError, "a simulator config JSON"), file=p)


def sim_config_from_dict(data: Any, *, file: str | Path | None = None) -> SimConfigFile:
    if not isinstance(data, dict):
        raise SourceError("the top level must be a JSON object", file=file)
    known = {"initial_pose", "pico_pose", "uncertain_odom", "disable_speedcap", "objects"}
    pose_key = "initial_pose" if "initial_pose" in data else "pico_pose"
    pose = _pose(data[pose_key], pose_key, file) if pose_key in data else None
    objects = data.get("objects", [])
    if not isinstance(objects, list):
        raise SourceError(f"must be a list of objects, got {short(objects)}", file=file, field="objects")
    return SimConfigFile(
        initial_pose=pose,
        uncertain_odom=_bool(data, "uncertain_odom", file),
        disable_speedcap=_bool(data, "disable_speedcap", file),
        objects=tuple(_object(o, f"objects[{i}]", file) for i, o in enumerate(objects)),
        ignored=tuple(sorted(k for k in data if k not in known)),
        source=Path(file) if file is not None else None,
        field_of_pose=pose_key,
    )


def sim_config_to_dict(sc: SimConfigFile) -> dict[str, Any]:
    """The JSON form of `sc` (what `sim_config_from_dict` reads back): its start pose, the two
    flags when set, and its moving objects."""
    out: dict[str, Any] = {}
    if sc.initial_pose is not None:
        out["initial_pose"] = [float(v) for v in sc.initial_pose]
    for key in ("uncertain_odom", "disable_speedcap"):
        if getattr(sc, key) is not None:
            out[key] = getattr(sc, key)
    out["objects"] = [{"length": o.length, "width": o.width, "init_pose": list(o.init_pose), "final_pose": list(o.final_pose),
                       "velocity": o.velocity, "trigger_radius": o.trigger_radius, "repeat": o.repeat} for o in sc.objects]
    return out


def _bool(data: dict[str, Any], key: str, file: str | Path | None) -> bool | None:
    if key not in data:
        return None
    v = data[key]
    if not isinstance(v, bool):
        raise SourceError(f"must be true or false, got {short(v)}", file=file, field=key)
    return v


def _number(
    v: Any, where: str, file: str | Path | None, *, lo: float | None = None, strict: bool = False,
    hi: float | None = None, unit: str = "m",
) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise SourceError(f"must be a finite number, got {short(v)}", file=file, field=where)
    try:
        v = float(v)
    except OverflowError:  # a JSON integer of hundreds of digits
        raise SourceError("must be a finite number, got an integer too large for one", file=file, field=where) from None
    if not math.isfinite(v):
        raise SourceError(f"must be a finite number, got {short(v)}", file=file, field=where)
    if lo is not None and (v <= lo if strict else v < lo):
        raise SourceError(f"must be {'>' if strict else '>='} {lo:g}, got {short(v)}", file=file, field=where)
    if hi is not None and v > hi:
        raise SourceError(f"must be at most {hi:g} {unit}, got {v:g}", file=file, field=where)
    return v


def _pose(v: Any, where: str, file: str | Path | None) -> Pose:
    if not isinstance(v, list) or len(v) != 3:
        raise SourceError(f"must be a list [x, y, a], got {short(v)}", file=file, field=where)
    x, y = (_number(c, f"{where}[{i}]", file, lo=-MAX_COORDINATE_M, hi=MAX_COORDINATE_M) for i, c in enumerate(v[:2]))
    a = _number(v[2], f"{where}[2]", file, lo=-MAX_ANGLE, hi=MAX_ANGLE, unit="rad")
    return (x, y, a)


def _object(o: Any, where: str, file: str | Path | None) -> MovingObjectSpec:
    if not isinstance(o, dict):
        raise SourceError(f"must be an object, got {short(o)}", file=file, field=where)
    required = ("length", "width", "init_pose", "final_pose", "velocity", "trigger_radius")
    for key in required:
        if key not in o:
            raise SourceError("missing key", file=file, field=f"{where}.{key}")
    repeat = o.get("repeat", False)
    if not isinstance(repeat, bool):
        raise SourceError(f"must be true or false, got {short(repeat)}", file=file, field=f"{where}.repeat")
    return MovingObjectSpec(
        length=_number(o["length"], f"{where}.length", file, lo=0.0, strict=True, hi=MAX_OBJECT_SIZE),
        width=_number(o["width"], f"{where}.width", file, lo=0.0, strict=True, hi=MAX_OBJECT_SIZE),
        init_pose=_pose(o["init_pose"], f"{where}.init_pose", file),
        final_pose=_pose(o["final_pose"], f"{where}.final_pose", file),
        velocity=_number(
            o["velocity"], f"{where}.velocity", file, lo=0.0, strict=True, hi=MAX_OBJECT_SPEED, unit="m/s"
        ),
        trigger_radius=_number(o["trigger_radius"], f"{where}.trigger_radius", file, lo=0.0, hi=MAX_TRIGGER_RADIUS),
        repeat=repeat,
    )



def check_start_pose(
    pose: Pose, bounds: tuple[float, float, float, float], config: SimConfigFile, *, explicit: bool
) -> None:
    """SourceError when a start pose given by the user (`explicit`: an argument, else the
    sim config's) lies outside the map's bounds plus `START_MARGIN`; a start the map chose
    itself (its start area) is not checked."""
    if not explicit and config.initial_pose is None:
        return
    x0, y0, x1, y1 = bounds
    x, y = pose[0], pose[1]
    m = START_MARGIN
    if x0 - m <= x <= x1 + m and y0 - m <= y <= y1 + m:
        return
    dx = max(x0 - x, x - x1, 0.0)
    dy = max(y0 - y, y - y1, 0.0)
    raise SourceError(
        f"start pose ({x:g}, {y:g}) is {math.hypot(dx, dy):.3g} m outside the map "
        f"(x {x0:g} .. {x1:g}, y {y0:g} .. {y1:g}): the robot would see no wall and every "
        "score would be meaningless",
        file=None if explicit else config.source,
        field="initial_pose" if explicit else config.field_of_pose,
    )
