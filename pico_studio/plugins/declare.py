"""The decorators a plugin file uses: `segmenter`, `door_detector`, `perceptor`, `behaviour`.

Each registers one stage while the file is being loaded (`load_plugin`), or, when a module
is imported by hand, under that module's name. A refused name (a built-in's, another
plugin's) raises `ValueError` at the decorator's line, which the loader reports as the
plugin's one-line error.
"""

from __future__ import annotations

from collections.abc import Callable
from contextvars import ContextVar
from typing import Any, TypeVar

from pico_studio.plugins import registry
from pico_studio.plugins.registry import Stage

F = TypeVar("F", bound=Callable[..., Any])

# the plugin being loaded: its key and the stages it registered so far
_LOADING: ContextVar[tuple[str, list[Stage]] | None] = ContextVar("pico_studio_plugin_loading", default=None)


def loading(key: str) -> tuple[Any, list[Stage]]:
    """Start collecting the stages `key` registers; `done(token)` stops."""
    stages: list[Stage] = []
    return _LOADING.set((key, stages)), stages


def done(token: Any) -> None:
    _LOADING.reset(token)


def _declare(kind: str, name: str, params_cls: type | None, help: str, mode: str = "replace") -> Callable[[F], F]:  # noqa: A002
    def decorate(target: F) -> F:
        current = _LOADING.get()
        if current is None:  # imported by hand, not through load_plugin: the module is the key
            key, stages = str(getattr(target, "__module__", name)), None
        else:
            key, stages = current
        stage = Stage(kind, name, target, params_cls, help, mode)
        if stages is not None and any(s.name == name and s.area is stage.area for s in stages):
            raise ValueError(f"this plugin declares {name!r} twice; each stage needs its own name")
        registry.register(stage, key)
        if stages is not None:
            stages.append(stage)
        else:
            plugin = registry.LOADED.setdefault(key, registry.Plugin(key, "module", key, None))
            plugin.stages = [s for s in plugin.stages if s.name != name or s.kind != kind] + [stage]
        return target

    return decorate


def segmenter(name: str, params: type | None = None, *, help: str = "") -> Callable[[F], F]:  # noqa: A002
    """`fn(points (N, 2), params) -> [(first, last), ...]`: one cluster's resampled points in
    the robot frame, scan order -> inclusive index pairs, one per wall piece. Selected by
    `perception.scan.segmenter: <name>`; the pipeline refits and filters the pieces."""
    return _declare("segmenter", name, params, help)


def door_detector(name: str, params: type | None = None, *, help: str = "",  # noqa: A002
                  mode: str = "replace") -> Callable[[F], F]:
    """`fn(world_model, params) -> doors (D, 4)` in the zero frame, from the world model of
    this frame (`local_map.walls`, `local_map.endpoint_property`, `corners`, `pose`, ...).
    `mode="replace"` replaces the built-in doors, `"add"` adds to them. Selected by
    `perception.identify.door_detector: <name>`."""
    if mode not in ("replace", "add"):
        raise ValueError(f"door_detector mode must be 'replace' or 'add', got {mode!r}")
    return _declare("door_detector", name, params, help, mode)


def perceptor(name: str, params: type | None = None, *, help: str = "") -> Callable[[F], F]:  # noqa: A002
    """A class `cls(params)` with `step(laser, odometry) -> WorldModel` (a `params` attribute,
    when it has one, follows slider changes). Selected by `perception.perceptor: <name>`."""
    return _declare("perceptor", name, params, help)


def behaviour(name: str, params: type | None = None, *, help: str = "") -> Callable[[F], F]:  # noqa: A002
    """A class `cls(params, [arg=, global_map=, pose=])` with the behaviour protocol
    `step(world_model, laser, odometry, now, *, ok=True) -> Command | None` and, for the page,
    `state` (and optionally `target`, `plan`, `frame`, `done`, `result()`). Chosen by
    `--behaviour <name>[:ARG]` and in the page's behaviour list."""
    return _declare("behaviour", name, params, help)
