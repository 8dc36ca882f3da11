"""Sliders for every config parameter, generated from the config declaration.

`walk(cfg)` yields the sections and parameters in declaration order: each section becomes a
folder, each float/int parameter a slider over its declared range and step (a number box
where the range spans decades: `spans_decades`), each bool a checkbox, each `choices`
parameter a dropdown, each string a text field; the hint is the declared meaning with unit
and range. A change goes through `with_value` (validated like a file); an invalid one is
reverted on the page and reported.

`Tuner` is what a tuner lives with above the sliders: a search over every parameter's path
and meaning (its results are inputs of their own), undo / redo, the parameters changed from
the defaults and from a pinned config A, and the last refused value with the reason.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from typing import Any

import viser

from pico_studio.config import (
    Config,
    ParamInfo,
    ParamSpec,
    SectionInfo,
    changed_params,
    changes,
    params,
    walk,
)
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
        self.extra: dict[str, Any] = {}  # more inputs of some parameters (the search results)
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

    def _add_input(self, gui: viser.GuiApi, info: ParamInfo, label: str | None = None) -> Any:
        spec, hint, label = info.spec, info.spec.describe(), label or info.name
        kind = spec.kind
        if kind == "bool":
            h = gui.add_checkbox(label, bool(info.value), hint=hint)
        elif kind == "choice":
            h = gui.add_dropdown(label, list(spec.choices or ()), initial_value=info.value, hint=hint)
        elif kind == "str":
            h = gui.add_text(label, str(info.value), hint=hint)
        else:
            assert spec.lo is not None and spec.hi is not None
            h = number_input(gui, info, label, hint)
        path = info.path
        on_user(h, lambda event: self._on_change(event, path))  # the server's writes are quiet
        return h

    def show(self, cfg: Config) -> None:
        """Make every input show the value in `cfg` (after import, reset or a rejected edit)."""
        for item in walk(cfg):
            if isinstance(item, ParamInfo):
                for handles in (self.inputs, self.extra):
                    if item.path in handles:
                        handles[item.path].value = item.value


def spans_decades(spec: ParamSpec) -> bool:
    """A range a slider cannot hit a value in: three decades or more (0.001 .. 1 m), or more
    than 5,000 steps (a seed, a beam count): such parameters get a number box."""
    assert spec.lo is not None and spec.hi is not None
    step = spec.step or (1 if spec.kind == "int" else (spec.hi - spec.lo) / 100.0)
    return (spec.lo > 0 and spec.hi / spec.lo >= 1000) or (spec.hi - spec.lo) / step > 5000


def number_input(gui: viser.GuiApi, info: ParamInfo, label: str, hint: str) -> Any:
    """A slider over the declared range, or a number box where the range spans decades."""
    spec = info.spec
    assert spec.lo is not None and spec.hi is not None
    step = _step(info)
    if spec.kind == "int":
        if spans_decades(spec):
            return gui.add_number(label, int(info.value), min=int(spec.lo), max=int(spec.hi), step=int(step), hint=hint)
        return gui.add_slider(label, int(spec.lo), int(spec.hi), int(step), int(info.value), hint=hint)
    if spans_decades(spec):
        return gui.add_number(label, float(info.value), min=float(spec.lo), max=float(spec.hi), step=float(step), hint=hint)
    return gui.add_slider(label, float(spec.lo), float(spec.hi), float(step), float(info.value), hint=hint)


# ----- a config panel a tuner can live in ---------------------------------------------------------


def search(cfg: Config, query: str, limit: int = 15) -> list[ParamInfo]:
    """The parameters whose path or meaning contains every word of `query` (case-insensitive)."""
    words = query.lower().split()
    if not words:
        return []
    found = [p for p in params(cfg) if all(w in f"{p.path} {p.spec.help}".lower() for w in words)]
    return found[:limit]


def diff_markdown(cfg: Config, a: Config | None) -> str:
    """What differs from the defaults, and from config A when one is pinned."""
    lines = []
    changed = changed_params(cfg)
    lines.append(f"**{len(changed)} changed from the defaults**" + (":" if changed else ""))
    lines += [f"- `{p.path}`: {p.value!r} <small>(default {p.spec.default!r})</small>" for p in changed[:40]]
    if len(changed) > 40:
        lines.append(f"- … and {len(changed) - 40} more")
    if a is not None:
        vs_a = changes(a, cfg)
        lines.append(f"\n**{len(vs_a)} differ from A**" + (":" if vs_a else ""))
        lines += [f"- `{c.path}`: A {c.old!r} → {c.new!r}" for c in vs_a[:40]]
    return "\n".join(lines)


class History:
    """Undo / redo of whole-config changes (each edit, import, reset is one step)."""

    def __init__(self, limit: int = 200):
        self.undo_stack: list[Config] = []
        self.redo_stack: list[Config] = []
        self.limit = limit

    def record(self, before: Config, after: Config) -> None:
        if before == after:
            return
        self.undo_stack.append(before)
        del self.undo_stack[:-self.limit]
        self.redo_stack.clear()

    def undo(self, current: Config) -> Config | None:
        if not self.undo_stack:
            return None
        self.redo_stack.append(current)
        return self.undo_stack.pop()

    def redo(self, current: Config) -> Config | None:
        if not self.redo_stack:
            return None
        self.undo_stack.append(current)
        return self.redo_stack.pop()


class Tuner:
    """Search box, undo / redo, the diff view and the last refused value, above the sliders.

    `apply(cfg)` makes a config current (the Config tab's apply); `pinned()` gives config A
    or None. Search results are inputs of their own (full path as label) bound to the same
    parameters as the sliders, so a parameter deep in a folder is changed where it is found."""

    def __init__(self, gui: viser.GuiApi, panel: ConfigPanel, current: Callable[[], Config],
                 apply: Callable[[Config], None], pinned: Callable[[], Config | None],
                 on_change: Callable[[Any, str], None]):
        self.gui, self.panel, self.current, self._apply, self.pinned = gui, panel, current, apply, pinned
        self.history = History()
        self.error = gui.add_markdown("")
        self.undo_redo = gui.add_button_group("History", ("Undo", "Redo"), hint="Undo / redo parameter changes")
        self.undo_redo.on_click(lambda e: self.undo() if e.target.value == "Undo" else self.redo())
        self.query = gui.add_text("Search parameters", "", hint="Words of a parameter's name or meaning, e.g. 'door width'")
        on_user(self.query, lambda e: self.show_results(str(e.target.value)))
        self.results = gui.add_folder("Search results", expand_by_default=True)
        self._result_handles: list[Any] = []
        self._on_change = on_change
        with gui.add_folder("Changed parameters", expand_by_default=False):
            self.diff = gui.add_markdown(diff_markdown(current(), None))
        self._diff_key: Any = None

    def show_results(self, query: str) -> None:
        for h in self._result_handles:
            h.remove()
        self._result_handles = []
        self.panel.extra.clear()
        found = search(self.current(), query)
        with self.results:
            if query.strip() and not found:
                self._result_handles.append(self.gui.add_markdown(f"<small>No parameter matches '{query}'.</small>"))
            for info in found:
                h = self.panel._add_input(self.gui, ParamInfo(info.path, info.spec, info.value), label=info.path)
                self.panel.extra[info.path] = h
                self._result_handles.append(h)

    def record(self, before: Config, after: Config) -> None:
        self.history.record(before, after)

    def undo(self) -> None:
        cfg = self.history.undo(self.current())
        if cfg is not None:
            self._apply(cfg)

    def redo(self) -> None:
        cfg = self.history.redo(self.current())
        if cfg is not None:
            self._apply(cfg)

    def refused(self, path: str, value: Any, problem: str) -> None:
        """Say on the page that `value` for `path` was refused, and why (the input shows the
        valid value again)."""
        self.error.content = f"<span style='color:#c8102e'>**{path} = {value!r} refused**: {problem}</span>"

    def accepted(self) -> None:
        if self.error.content:
            self.error.content = ""

    def refresh(self) -> None:
        cfg, a = self.current(), self.pinned()
        key = (id(cfg), id(a))
        if key != self._diff_key:
            self._diff_key = key
            self.diff.content = diff_markdown(cfg, a)
