"""Adapters from a plugin's plain functions and classes to the core registries' shapes.

Each adapter finds the plugin's params in the config section it is handed
(`perception.plugins.<name>`, `behaviour.plugins.<name>`; the declared defaults when that
config was built before the plugin loaded) and contains the plugin's faults: a segmenter that
raises gives that frame split-and-merge's pieces, a door detector the built-in doors (see
`core.perception.plugin_hooks`), a perceptor an empty world model, a behaviour the stop
command — each with a warning in that frame's world model. The loop never dies of user code.
"""

from __future__ import annotations

import copy
import inspect
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from pico_studio.config.perception_params import PerceptionParams
from pico_studio.core.io import STOP, Command, LaserData, OdometryData
from pico_studio.core.perception import plugin_hooks
from pico_studio.core.perception.perceptor import PerceptorState
from pico_studio.core.perception.segment import SEGMENTERS
from pico_studio.core.world_model import WorldModel

FALLBACK_SEGMENTER = "split_merge"


def params_in(area_section: Any, name: str, params_cls: type | None) -> Any:
    """The plugin's params from its area's section, or its declared defaults."""
    if params_cls is None:
        return None
    found = area_section.get(name) if area_section is not None else None
    return found if isinstance(found, params_cls) else params_cls()


def segmenter_adapter(name: str, fn: Callable[..., Any], params_cls: type | None) -> Callable[..., np.ndarray]:
    """`fn(cluster_points (N, 2), params) -> [(first, last), ...]` per cluster, as the
    registry's `(points, clusters, perception_params) -> pieces (S, 2)` over the whole scan."""

    def run(points: np.ndarray, clusters: np.ndarray, perception: PerceptionParams) -> np.ndarray:
        p = params_in(getattr(perception, "plugins", None), name, params_cls)
        out = []
        try:
            for start, end in np.asarray(clusters, dtype=np.int64).tolist():
                got = np.asarray(fn(points[start:end], p), dtype=np.int64).reshape(-1, 2)
                # only well-formed pieces inside this cluster: a sloppy index must not crash refit
                ok = (got[:, 0] >= 0) & (got[:, 0] <= got[:, 1]) & (got[:, 1] < end - start)
                out.append(got[ok] + start)
        except Exception as e:
            plugin_hooks.warn(f"segmenter {name!r} failed on this frame ({type(e).__name__}: {e}); "
                              f"{FALLBACK_SEGMENTER} ran instead")
            return SEGMENTERS[FALLBACK_SEGMENTER](points, clusters, perception)
        if not out:
            return np.zeros((0, 2), dtype=np.int64)
        return np.vstack(out)

    return run


def door_adapter(name: str, fn: Callable[..., Any], params_cls: type | None, mode: str) -> plugin_hooks.DoorDetector:
    """`fn(world_model, params) -> doors (D, 4)` zero frame; mode "add" keeps the built-in ones."""

    def detect(wm: WorldModel, perception: PerceptionParams) -> np.ndarray:
        p = params_in(perception.plugins, name, params_cls)
        doors = np.asarray(fn(wm, p), dtype=float).reshape(-1, 4)
        return np.vstack([wm.doors.reshape(-1, 4), doors]) if mode == "add" else doors

    return detect


@dataclass(frozen=True)
class PluginPerceptorState(PerceptorState):
    """The perceptor state plus the plugin perceptor's own object (copied before each step,
    so the state before a frame stays as it was and the frame can be perceived again)."""

    plugin_name: str = ""
    plugin_object: Any = None


def perceptor_hook(name: str, cls: Callable[..., Any], params_cls: type | None) -> plugin_hooks.PerceptorHook:
    """A class `cls(params)` with `step(laser, odometry) -> WorldModel` as a pure hook."""

    def hook(state: Any, laser: LaserData | None, odometry: OdometryData | None,
             perception: PerceptionParams, builtin: plugin_hooks.Builtin) -> tuple[WorldModel, Any]:
        p = params_in(perception.plugins, name, params_cls)
        old = state.plugin_object if isinstance(state, PluginPerceptorState) and state.plugin_name == name else None
        start = time.perf_counter()
        try:
            obj = copy.deepcopy(old) if old is not None else (cls(p) if params_cls is not None else cls())
            if old is not None and hasattr(obj, "params"):
                obj.params = p  # a slider moved: the object carries on with the new values
            wm = obj.step(laser, odometry)
            if not isinstance(wm, WorldModel):
                raise TypeError(f"step() must return a WorldModel, got {type(wm).__name__}")
        except Exception as e:
            wm = WorldModel(time=state.time, pose=state.locate.pose, zero_pose=state.locate.zero_pose)
            wm.warnings.append(f"perceptor {name!r} failed on this frame ({type(e).__name__}: {e}); state kept")
            return wm, state
        wm.timings_ms.setdefault("total", (time.perf_counter() - start) * 1000.0)
        base = {f: getattr(state, f) for f in PerceptorState.__dataclass_fields__}
        return wm, PluginPerceptorState(**base, plugin_name=name, plugin_object=obj)

    return hook


_FACTORY_KEYWORDS = ("arg", "global_map", "pose")


def behaviour_factory(name: str, cls: Callable[..., Any], params_cls: type | None) -> Callable[..., Any]:
    """`cls(params, [arg=, global_map=, pose=])` as the behaviour registry's factory
    `(arg, settings, global_map, pose) -> behaviour`, its steps made fault-safe."""
    try:
        accepted = set(inspect.signature(cls).parameters)
    except (TypeError, ValueError):
        accepted = set()

    def factory(arg: str, settings: Any, global_map: Any, pose: Any) -> Any:
        p = params_in(getattr(getattr(settings, "behaviour", None), "plugins", None), name, params_cls)
        given = {"arg": arg, "global_map": global_map, "pose": pose}
        kwargs = {k: given[k] for k in _FACTORY_KEYWORDS if k in accepted}
        obj = cls(p, **kwargs) if params_cls is not None else cls(**kwargs)
        return SafeBehaviour(name, obj)

    return factory


class SafeBehaviour:
    """A plugin behaviour whose `step` may raise: that tick sends the stop command, says why
    in the world model's warnings and in `state`, and the next tick tries again."""

    def __init__(self, name: str, inner: Any):
        self.name = name
        self.inner = inner
        self.failure: str | None = None

    def __getattr__(self, attr: str) -> Any:
        # state, target, plan, frame, done, result(), ... are the plugin's own (or the defaults)
        if attr in ("target", "plan"):
            return getattr(self.inner, attr, None)
        if attr == "frame":
            return getattr(self.inner, attr, "zero")
        if attr == "done":
            return getattr(self.inner, attr, False)
        return getattr(self.inner, attr)

    @property
    def state(self) -> str:
        if self.failure is not None:
            return self.failure
        return str(getattr(self.inner, "state", self.name))

    def result(self) -> dict[str, Any]:
        result = getattr(self.inner, "result", None)
        return dict(result()) if callable(result) else {"state": self.state}

    def step(self, world_model: Any, laser: LaserData | None, odometry: OdometryData | None,
             now: float, *, ok: bool = True) -> Command | None:
        try:
            cmd = self.inner.step(world_model, laser, odometry, now, ok=ok)
        except Exception as e:
            self.failure = f"plugin failed ({type(e).__name__})"
            warnings = getattr(world_model, "warnings", None)
            if isinstance(warnings, list):
                warnings.append(f"behaviour {self.name!r} failed on this tick ({type(e).__name__}: {e}); stopped")
            return STOP
        self.failure = None
        return cmd
