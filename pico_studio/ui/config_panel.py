"""Sliders for every config parameter, generated from the config declaration.

`walk(cfg)` yields the sections and parameters in declaration order: each section becomes a
folder, each float/int parameter a slider over its declared range and step, each bool a
checkbox, each `choices` parameter a dropdown, each string a text field; the hint is the
declared meaning with unit and range. A change goes through `with_value` (validated like a
file); an invalid one is reverted on the page and reported.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from typing import Any

import viser

from pico_studio.config import Config, ParamInfo, SectionInfo, walk
from pico_studio.ui.gui_values import on_user

# When a section's values take effect (the rest apply at once, re-processing the frame shown).
APPLIES = {
    "map": "takes effect when a map is loaded",
    "sim": "takes effect on Reset (a new simulator)",
    "sources": "takes effect on Reset (the source is reopened)",
    "behaviour": "takes effect when a behaviour is chosen, or on Reset",
}


def _step(info: ParamInfo) -> float:
    spec = info.spec
    if spec.step is not None:
        return spec.step
    if spec.kind == "int":
        return 1
    assert spec.lo is not None and spec.hi is not None
    return (spec.hi - spec.lo) / 100.0


class ConfigPanel:
    """The GUI inputs of one config tree; `on_change(event, path)` is called on edits."""

    def __init__(
        self,
        gui: viser.GuiApi,
        cfg: Config,
        on_change: Callable[[Any, str], None],
        expand: tuple[str, ...] = ("perception",),
    ):
        self.inputs: dict[str, Any] = {}
        self._on_change = on_change
        folders: dict[str, Any] = {}
        for item in walk(cfg):
            parent = item.path.rsplit(".", 1)[0] if "." in item.path else ""
            ctx = folders.get(parent)
            with ctx if ctx is not None else contextlib.nullcontext():
                if isinstance(item, SectionInfo):
                    top = "." not in item.path
                    folder = gui.add_folder(item.path.rsplit(".", 1)[-1], expand_by_default=top and item.path in expand)
                    with folder:
                        note = APPLIES.get(item.path)
                        gui.add_markdown(f"<small>{item.help}" + (f" — <i>{note}</i>" if note else "") + "</small>")
                    folders[item.path] = folder
                else:
                    self.inputs[item.path] = self._add_input(gui, item)

    def _add_input(self, gui: viser.GuiApi, info: ParamInfo) -> Any:
        spec, hint, label = info.spec, info.spec.describe(), info.name
        kind = spec.kind
        if kind == "bool":
            h = gui.add_checkbox(label, bool(info.value), hint=hint)
        elif kind == "choice":
            h = gui.add_dropdown(label, list(spec.choices or ()), initial_value=info.value, hint=hint)
        elif kind == "str":
            h = gui.add_text(label, str(info.value), hint=hint)
        else:
            assert spec.lo is not None and spec.hi is not None
            if kind == "int":
                h = gui.add_slider(label, int(spec.lo), int(spec.hi), int(_step(info)), int(info.value), hint=hint)
            else:
                h = gui.add_slider(label, float(spec.lo), float(spec.hi), float(_step(info)), float(info.value), hint=hint)
        path = info.path
        on_user(h, lambda event: self._on_change(event, path))  # the server's writes are quiet
        return h

    def show(self, cfg: Config) -> None:
        """Make every input show the value in `cfg` (after import, reset or a rejected edit)."""
        for item in walk(cfg):
            if isinstance(item, ParamInfo) and item.path in self.inputs:
                self.inputs[item.path].value = item.value
