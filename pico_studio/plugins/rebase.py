"""A config tree carried over to the current declarations after plugins (re)loaded.

A plugin area's class is rebuilt whenever a plugin is added, removed or reloaded, so a
`Config` made before holds the old classes. `rebase(cfg)` builds the same tree on the
current classes: every value that is still declared and still valid is kept, a plugin's
new parameter starts at its default, a removed one is dropped.
"""

from __future__ import annotations

import dataclasses
from typing import Any, TypeVar

from pico_studio.config.plugin_params import section_class
from pico_studio.config.spec import coerce

T = TypeVar("T")


def rebase(cfg: T) -> T:
    built: T = _build(type(cfg), cfg)
    return built


def _build(cls: Any, old: Any) -> Any:
    kwargs: dict[str, Any] = {}
    for f in dataclasses.fields(cls):
        if old is None or not hasattr(old, f.name):
            continue  # new here: its default
        value = getattr(old, f.name)
        if "pico_studio.section" in f.metadata:
            kwargs[f.name] = _build(section_class(f), value)
            continue
        try:
            kwargs[f.name] = coerce(f.metadata["pico_studio.param"], value)
        except ValueError:
            pass  # its range or choices changed: back to the default
    obj = cls(**kwargs)
    check = getattr(obj, "check", None)
    if check is not None and list(check()):
        return _build(cls, None)  # a cross-field rule now fails: the section's defaults
    return obj
