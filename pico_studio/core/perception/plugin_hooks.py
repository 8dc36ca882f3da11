"""Where user code joins the perceptor: door detectors and whole perceptors by name.

Core cannot import `pico_studio.plugins` (it sits above core), so these registries live
here and the plugin layer fills them; segmenters have theirs in `segment.py`. One call,
`perceive_with_plugins`, runs a frame through them:

- `perception.perceptor: NAME` (not "builtin"): the registered `PerceptorHook` makes the
  whole world model, `hook(state, laser, odometry, params, builtin) -> (wm, state)`, where
  `builtin` is the built-in pipeline (its fallback);
- otherwise the built-in pipeline, then `perception.identify.door_detector: NAME` (not
  "builtin"): `detector(world_model, params) -> doors (D, 4)` in the zero frame replaces
  `world_model.doors` (a plugin that adds to them returns both).

While a frame runs, plugin code may call `warn(text)` (lands in `WorldModel.warnings`) and
`emit(name, array, frame=...)` (lands in `WorldModel.extras`, placed in the zero frame): they
collect into the frame being perceived (a context variable: threads do not mix frames). A
detector that raises keeps the built-in doors and says so in the warnings: the loop goes on.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from contextvars import ContextVar
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pico_studio.config.perception_params import (
    DOOR_DETECTOR_NAMES,
    PERCEPTOR_NAMES,
    PerceptionParams,
)
from pico_studio.core.geometry import transform_points
from pico_studio.core.io import LaserData, OdometryData
from pico_studio.core.world_model import WorldModel

BUILTIN = "builtin"

Builtin = Callable[[Any, "LaserData | None", "OdometryData | None", PerceptionParams], "tuple[WorldModel, Any]"]
PerceptorHook = Callable[[Any, "LaserData | None", "OdometryData | None", PerceptionParams, Builtin],
                         "tuple[WorldModel, Any]"]
DoorDetector = Callable[[WorldModel, PerceptionParams], np.ndarray]

PERCEPTORS: dict[str, PerceptorHook] = {}
DOOR_DETECTORS: dict[str, DoorDetector] = {}


def register_perceptor(name: str, hook: PerceptorHook) -> None:
    """Make `hook` selectable as `perception.perceptor: <name>` (replaces one of that name)."""
    if name in PERCEPTOR_NAMES.builtin:
        raise ValueError(f"{name!r} is the built-in perceptor's name")
    PERCEPTORS[name] = hook
    PERCEPTOR_NAMES.add(name)


def register_door_detector(name: str, detector: DoorDetector) -> None:
    """Make `detector` selectable as `perception.identify.door_detector: <name>`."""
    if name in DOOR_DETECTOR_NAMES.builtin:
        raise ValueError(f"{name!r} is the built-in door detector's name")
    DOOR_DETECTORS[name] = detector
    DOOR_DETECTOR_NAMES.add(name)


def unregister(name: str) -> None:
    """Forget a perceptor or door detector of that name (a plugin unloaded)."""
    if PERCEPTORS.pop(name, None) is not None:
        PERCEPTOR_NAMES.remove(name)
    if DOOR_DETECTORS.pop(name, None) is not None:
        DOOR_DETECTOR_NAMES.remove(name)


@dataclass
class _Notes:
    warnings: list[str] = field(default_factory=list)
    extras: dict[str, tuple[np.ndarray, str]] = field(default_factory=dict)


_NOTES: ContextVar[_Notes | None] = ContextVar("pico_studio_plugin_notes", default=None)


def warn(text: str) -> None:
    """Add a warning to the frame being perceived (nothing outside a frame)."""
    notes = _NOTES.get()
    if notes is not None:
        notes.warnings.append(text)


def emit(name: str, array: Any, frame: str = "robot") -> None:
    """Hand the page an extra named output of this frame: (K, 2) points or (K, 4) segments,
    in the robot frame (`frame="robot"`, as a segmenter sees its points) or the zero frame
    (`"zero"`, as the local map and doors)."""
    if frame not in ("robot", "zero"):
        raise ValueError(f"frame must be 'robot' or 'zero', got {frame!r}")
    a = np.asarray(array, dtype=float)
    if a.ndim != 2 or a.shape[1] not in (2, 4):
        raise ValueError(f"extra {name!r} must be (K, 2) points or (K, 4) segments, got shape {a.shape}")
    notes = _NOTES.get()
    if notes is not None:
        notes.extras[name] = (a.copy(), frame)


def perceive_with_plugins(state: Any, laser: LaserData | None, odometry: OdometryData | None,
                          params: PerceptionParams, builtin: Builtin) -> tuple[WorldModel, Any]:
    """One frame through the selected perceptor and door detector (see the module doc)."""
    notes = _Notes()
    token = _NOTES.set(notes)
    try:
        wm, new_state = _run(state, laser, odometry, params, builtin)
    finally:
        _NOTES.reset(token)
    wm.warnings.extend(notes.warnings)
    for name, (a, frame) in notes.extras.items():
        wm.extras[name] = _to_zero_frame(a, frame, wm.pose)
    return wm, new_state


def _run(state: Any, laser: LaserData | None, odometry: OdometryData | None,
         params: PerceptionParams, builtin: Builtin) -> tuple[WorldModel, Any]:
    if params.perceptor != BUILTIN:
        hook = PERCEPTORS.get(params.perceptor)
        if hook is not None:
            return hook(state, laser, odometry, params, builtin)
        warn(f"perceptor {params.perceptor!r} is not loaded; the built-in one ran")
    wm, new_state = builtin(state, laser, odometry, params)
    name = params.identify.door_detector
    if name != BUILTIN and laser is not None:
        wm.doors = _doors(name, wm, params)
    return wm, new_state


def _doors(name: str, wm: WorldModel, params: PerceptionParams) -> np.ndarray:
    detector = DOOR_DETECTORS.get(name)
    if detector is None:
        warn(f"door detector {name!r} is not loaded; the built-in doors are kept")
        return wm.doors
    start = time.perf_counter()
    try:
        doors = np.asarray(detector(wm, params), dtype=float).reshape(-1, 4)
    except Exception as e:  # user code must not stop the robot: keep the built-in doors
        warn(f"door detector {name!r} failed on this frame ({type(e).__name__}: {e}); built-in doors kept")
        return wm.doors
    ms = (time.perf_counter() - start) * 1000.0
    wm.timings_ms["door_detector"] = ms
    wm.timings_ms["total"] = wm.timings_ms.get("total", 0.0) + ms
    return doors


def _to_zero_frame(a: np.ndarray, frame: str, pose: tuple[float, float, float]) -> np.ndarray:
    if frame == "zero" or len(a) == 0:
        return a
    return transform_points(a.reshape(-1, 2), pose).reshape(len(a), -1)
