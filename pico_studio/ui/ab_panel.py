"""The What-if tab's A/B controls: pin the current config as A, compare it with further
changes (B) over the whole run, swap, drop A, export either; the table of whole-run scores
of A, B and their difference; and the scene's diff overlay.

The overlay (layer "A/B diff", `scene_data.LAYERS`) draws, at the shown frame, what B's world
model adds against A's (`style.DIFF_ADDED`) and what it loses (`style.DIFF_LOST`): walls and
doors as thick lines, corners as dots, matched within the scoring's tolerances
(`evaluation.diff`). Both are the re-judged world models of that frame, so they share a zero
frame; it is placed where the page draws the robot.

The headless state is `ui.whatif.WhatIf` (`StudioApp.whatif`); the Tune tab's "apply as B"
calls `StudioApp.set_b(cfg)`.
"""

from __future__ import annotations

from datetime import datetime
from pathlib import Path
from typing import Any

import numpy as np
import viser

from pico_studio.errors import UserError
from pico_studio.evaluation.rejudge import higher_is_better
from pico_studio.ui.page import Page, Panel, Shown
from pico_studio.ui.scene_data import Prim
from pico_studio.ui.whatif import WhatIf

# overlay key (WhatIf.overlay) -> scene prim
OVERLAY_PRIMS = {
    "walls_added": "diff_walls_added", "walls_lost": "diff_walls_lost",
    "doors_added": "diff_doors_added", "doors_lost": "diff_doors_lost",
    "corners_added": "diff_corners_added", "corners_lost": "diff_corners_lost",
}


def _fmt(v: float | None) -> str:
    if v is None or not np.isfinite(v):
        return "–"
    return f"{v:.3f}" if abs(v) < 100 else f"{v:.0f}"


def table_html(w: WhatIf) -> str:
    """The whole-run totals: B alone, or A | B | B − A (better green, worse red; counts and
    timings uncoloured: neither direction is better)."""
    rows = w.table()
    if not rows:
        return "<small>No whole-run scores yet: change a parameter, or press <i>Re-judge now</i>.</small>"
    both = w.a is not None and w.comparable
    note = "<div><small>A and B are being judged on the same frames…</small></div>" if w.a is not None and not both else ""
    cell = "padding:0 4px;text-align:right"
    head = ["whole run", "A", "B", "B − A"] if both else ["whole run", "B (current)"]
    out = [note, '<table style="font-size:0.75em;border-collapse:collapse;width:100%">',
           "<tr>" + "".join(f'<th style="{cell}">{h}</th>' for h in head) + "</tr>"]
    for name, a, b, d in rows:
        cells = [name] + ([_fmt(a), _fmt(b)] if both else [_fmt(b)])
        if both:
            delta = "–" if d is None else f"{d:+.3f}"
            neutral = name.startswith(("count.", "perceptor.ms")) or d is None or abs(d) < 1e-12
            if not neutral:
                good = (d > 0) == higher_is_better(name)  # type: ignore[operator]
                delta = f"<span style='color:{'#008a3e' if good else '#c8102e'}'>{delta}</span>"
            cells.append(delta)
        out.append("<tr>" + f'<td style="padding:0 4px">{cells[0]}</td>'
                   + "".join(f'<td style="{cell}">{c}</td>' for c in cells[1:]) + "</tr>")
    out.append("</table>")
    return "".join(out)


class ABPanel(Panel):
    name = "ab"

    def __init__(self, page: Page, gui: viser.GuiApi, whatif: WhatIf, export_dir: Path):
        super().__init__(page)
        self.whatif = whatif
        self.export_dir = export_dir
        self.last_export: Path | None = None
        self.rejudge = gui.add_button("Re-judge now", icon=viser.Icon.REFRESH,
                                      hint="Re-judge the whole run with the current config (every change does this too)")
        self.ab = gui.add_button_group("A / B", ("Pin as A", "Swap A/B", "Drop A"),
                                       hint="Pin as A: keep the current config as A; further changes make B")
        self.export = gui.add_button_group("Export", ("Export A", "Export B"), hint="Download a side's config as YAML")
        self.table = gui.add_html(table_html(whatif))
        self.rejudge.on_click(page.guard("re-judge", lambda e: whatif.changed()))
        actions = {"Pin as A": lambda e: self._pin(), "Swap A/B": lambda e: self.do_swap(),
                   "Drop A": lambda e: whatif.drop_a(), "Export A": lambda e: self._export(e, "a"),
                   "Export B": lambda e: self._export(e, "b")}
        for group in (self.ab, self.export):
            group.on_click(page.guard("A/B", lambda e: actions[e.target.value](e)))
        page.hooks["ab_swap"] = self.do_swap
        page.hooks["pinned_a"] = lambda: whatif.a.config if whatif.a is not None else None
        self._table = ""

    def _pin(self) -> None:
        w = self.whatif
        if w.b.judged is None and not w.b.waiting:
            w.changed()
        w.pin_a()

    def do_swap(self) -> None:
        if self.whatif.a is None:
            return
        self.whatif.swap()
        self.page.hooks.get("config_shown", lambda cfg: None)(self.page.studio.cfg)
        self.page.redraw()

    def export_yaml(self, side: str) -> tuple[str, Path]:
        text = self.whatif.export(side)
        stamp = datetime.now().strftime("%Y%m%d-%H%M%S")
        path = (self.export_dir / f"pico_studio_config_{side.upper()}_{stamp}.yaml").resolve()
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        self.last_export = path
        return text, path

    def _export(self, event: viser.GuiEvent, side: str) -> None:
        if side == "a" and self.whatif.a is None:
            raise UserError("pin a config as A first", field="Export A")
        text, path = self.export_yaml(side)
        if event.client is not None:
            event.client.send_file_download(path.name, text.encode("utf-8"), save_immediately=True)
        self.page.notify(event.client, f"config {side.upper()} exported", str(path), color="green")

    def prims(self, shown_time: float | None, robot: Any) -> dict[str, Prim]:
        """The diff overlay's prims at the shown frame (empty without a pinned A)."""
        out = {name: Prim("points" if "corners" in name else "segments",
                          np.zeros((0, 2 if "corners" in name else 4))) for name in OVERLAY_PRIMS.values()}
        if shown_time is None or self.whatif.a is None:
            return out
        for key, arr in self.whatif.overlay(shown_time, robot).items():
            name = OVERLAY_PRIMS[key]
            out[name] = Prim(out[name].kind, np.asarray(arr, dtype=float).reshape(-1, 2 if "corners" in key else 4))
        return out

    def refresh(self, shown: Shown) -> None:
        text = table_html(self.whatif)
        if text != self._table:
            self.table.content = self._table = text
