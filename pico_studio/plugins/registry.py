"""The loaded plugins and the stages each one registered, and (un)registering a stage.

A plugin (a file, a module, an installed package's entry point) registers stages while it
is imported: `Stage(kind, name, params_cls, help)`. Registering one puts its adapter into the
core registry of its kind (segmenters, door detectors, perceptors, behaviours) and its params
dataclass into the config's plugin area (`perception.plugins`, `behaviour.plugins`). A name
is refused when it is a built-in's, or another plugin's; a plugin's own earlier stage of that
name (the file being reloaded) is replaced.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pico_studio.config.perception_params import (
    DOOR_DETECTOR_NAMES,
    PERCEPTOR_NAMES,
    SEGMENTER_NAMES,
)
from pico_studio.config.plugin_params import BEHAVIOUR_PLUGINS, PERCEPTION_PLUGINS, PluginArea
from pico_studio.core.behaviours import registry as behaviour_registry
from pico_studio.core.perception import plugin_hooks
from pico_studio.core.perception.segment import register_segmenter, unregister_segmenter
from pico_studio.plugins import stages

KINDS = ("segmenter", "door_detector", "perceptor", "behaviour")

# the behaviours that exist before any plugin: a plugin may not take their names
BUILTIN_BEHAVIOURS = frozenset(behaviour_registry.BEHAVIOURS)


@dataclass(frozen=True)
class Stage:
    kind: str  # one of KINDS
    name: str
    target: Callable[..., Any]  # the plugin's function or class
    params_cls: type | None
    help: str
    mode: str = "replace"  # door detectors: "replace" or "add" to the built-in doors

    @property
    def area(self) -> PluginArea:
        return BEHAVIOUR_PLUGINS if self.kind == "behaviour" else PERCEPTION_PLUGINS

    @property
    def config_path(self) -> str | None:
        """Where its params live in the config tree, when it has any."""
        if self.params_cls is None:
            return None
        return f"{self.area.name}.plugins.{self.name}"


@dataclass
class Plugin:
    """One loaded plugin: where it came from and what it registered."""

    key: str  # the path (resolved) or module name it was loaded by
    origin: str  # "file", "module" or "entry point"
    module_name: str
    file: Path | None
    stages: list[Stage] = field(default_factory=list)
    mtime: float | None = None
    error: str | None = None  # the last reload's error (the previous version keeps running)

    def changed(self) -> bool:
        """Is its file newer than when it was loaded?"""
        if self.file is None or self.mtime is None:
            return False
        try:
            return os.stat(self.file).st_mtime_ns != self.mtime
        except OSError:
            return False

    def describe(self) -> str:
        names = ", ".join(f"{s.kind} {s.name}" for s in self.stages) or "no stages"
        return f"{self.key} ({self.origin}): {names}"


LOADED: dict[str, Plugin] = {}
_OWNER: dict[tuple[str, str], str] = {}  # (area, name) -> plugin key


def loaded() -> list[Plugin]:
    return list(LOADED.values())


def builtin_names(kind: str) -> tuple[str, ...]:
    if kind == "segmenter":
        return SEGMENTER_NAMES.builtin
    if kind == "door_detector":
        return DOOR_DETECTOR_NAMES.builtin
    if kind == "perceptor":
        return PERCEPTOR_NAMES.builtin
    return tuple(sorted(BUILTIN_BEHAVIOURS))


def check_name(stage: Stage, key: str) -> None:
    """ValueError when `stage` may not take its name (built-in, or another plugin's)."""
    if stage.kind not in KINDS:
        raise ValueError(f"unknown stage kind {stage.kind!r}")
    if not stage.name.isidentifier():
        raise ValueError(f"{stage.kind} name {stage.name!r} must be a Python identifier (letters, digits, _)")
    if stage.name in builtin_names(stage.kind):
        raise ValueError(f"{stage.kind} name {stage.name!r} clashes with a built-in one; choose another")
    owner = _OWNER.get((stage.area.name, stage.name))
    if owner is not None and owner != key:
        raise ValueError(f"{stage.kind} name {stage.name!r} is taken by the plugin {owner}")


def register(stage: Stage, key: str) -> None:
    """Put the stage into its core registry and its params into the config area."""
    check_name(stage, key)
    if stage.kind == "segmenter":
        register_segmenter(stage.name, stages.segmenter_adapter(stage.name, stage.target, stage.params_cls),
                           replace=True)
    elif stage.kind == "door_detector":
        plugin_hooks.register_door_detector(
            stage.name, stages.door_adapter(stage.name, stage.target, stage.params_cls, stage.mode))
    elif stage.kind == "perceptor":
        plugin_hooks.register_perceptor(stage.name, stages.perceptor_hook(stage.name, stage.target, stage.params_cls))
    else:
        behaviour_registry.register_behaviour(
            stage.name, stages.behaviour_factory(stage.name, stage.target, stage.params_cls),
            stage.help or f"plugin behaviour ({key})")
    if stage.params_cls is not None:
        stage.area.add(stage.name, stage.params_cls, stage.help or f"plugin {stage.kind} {stage.name} ({key})")
    _OWNER[(stage.area.name, stage.name)] = key


def unregister(stage: Stage) -> None:
    if stage.kind == "segmenter":
        unregister_segmenter(stage.name)
    elif stage.kind in ("door_detector", "perceptor"):
        plugin_hooks.unregister(stage.name)
    else:
        behaviour_registry.BEHAVIOURS.pop(stage.name, None)
    stage.area.remove(stage.name)
    _OWNER.pop((stage.area.name, stage.name), None)
