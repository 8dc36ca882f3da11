"""The What-if tab's plots: the whole run re-judged with the current config, over time.

One uPlot chart (viser's `add_uplot`) per group of `rejudge.SERIES` — scores per frame (wall /
corner / door precision and recall, `local_map.agreement`), pose errors, counts, per-stage
ms, localisation quality and lost — with config A's series beside B's (dashed) when one is
pinned. Clicking a series' name in a chart's legend hides or shows it (uPlot's own legend);
the group checkboxes hide whole charts. Beside them: re-judge progress and why a figure is
absent (no truth, no map).

The cursor line at the timeline position and click-to-jump are a few lines of JavaScript in
each tab (viser 1.1.1 has no server-side events for uPlot): a draw hook on every chart draws
a vertical line at the time the server last sent, and a click on a chart writes its time into
the "Go to t" number box, whose update the server handles like any other input.
"""

from __future__ import annotations

import json
import math
import time
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
import viser

from pico_studio.evaluation.rejudge import SERIES, Judged
from pico_studio.ui import style
from pico_studio.ui.browser_js import run_js
from pico_studio.ui.clock import is_replay, recording_position, start_time
from pico_studio.ui.gui_values import on_user
from pico_studio.ui.page import Page, Panel, Shown, TabState
from pico_studio.ui.whatif import WhatIf

RGB = tuple[int, int, int]
CURSOR_HZ = 10.0  # at most this many cursor moves per second per tab


@dataclass(frozen=True)
class Group:
    key: str
    title: str
    series: tuple[tuple[str, RGB], ...]  # (series name, colour); "ms.*" = every stage
    scale: tuple[float, float] | None = None  # fixed y range, None: auto


_C = (style.OI_BLUE, style.OI_ORANGE, style.OI_GREEN, style.OI_VERMILLION, style.OI_PURPLE, style.OI_SKY,
      (120, 120, 120), style.OI_BLACK, (125, 85, 45), (0, 60, 100), (150, 130, 0), (170, 0, 110))

GROUPS: tuple[Group, ...] = (
    Group("scores", "Scores per frame", (
        ("walls.precision", _C[0]), ("walls.recall", _C[5]), ("corners.precision", _C[1]),
        ("corners.recall", _C[10]), ("doors.precision", _C[2]), ("doors.recall", _C[9]),
        ("local_map.agreement", _C[4])), (0.0, 1.0)),
    Group("pose", "Pose error (m)", (("pose.error_m", _C[3]), ("localisation.error_m", _C[0]))),
    Group("counts", "Counts", (("count.walls", _C[0]), ("count.corners", _C[1]), ("count.doors", _C[2]),
                               ("count.possible_doors", _C[3]))),
    Group("timing", "Per-stage ms", (("ms.*", _C[0]),)),
    Group("localisation", "Localisation", (("localisation.quality", _C[2]), ("localisation.lost", _C[3])), (0.0, 1.0)),
)


def _css(rgb: RGB) -> str:
    return f"rgb({rgb[0]},{rgb[1]},{rgb[2]})"


def group_series(group: Group, judged: Judged | None) -> list[tuple[str, RGB]]:
    """The series of `group` that `judged` has (the stages for "ms.*"), with colours."""
    if judged is None:
        return []
    out = []
    for name, colour in group.series:
        if name == "ms.*":
            stages = [k for k in judged.series if k.startswith("ms.")]
            out += [(k, _C[i % len(_C)]) for i, k in enumerate(sorted(stages, key=lambda k: (k == "ms.total", k)))]
        elif name in judged.series:
            out.append((name, colour))
    return out


def chart_data(group: Group, b: Judged | None, a: Judged | None, t0: float) -> tuple[tuple[np.ndarray, ...], tuple[dict[str, Any], ...]]:
    """(data, series) for one chart: x = seconds since `t0`, then B's series, then A's
    (dashed) when `a` is judged on the same frames. NaN where a frame has no value; a B
    re-judged part of the way (`complete` False) is drawn over A's whole run."""
    names = group_series(group, b)
    with_a = a is not None and b is not None and len(a.times) >= len(b.times) and (
        len(a.times) == len(b.times) or not b.complete)
    x = (a.times - t0) if with_a else ((b.times - t0) if b is not None else np.zeros(0))  # type: ignore[union-attr]
    n = len(x)
    data: list[np.ndarray] = [np.asarray(x, dtype=np.float64)]
    series: list[dict[str, Any]] = [{"label": "t (s)"}]
    for name, colour in names:
        col = np.full(n, np.nan)
        values = np.asarray(b.series[name], dtype=np.float64)  # type: ignore[union-attr]
        col[:len(values)] = values[:n]
        data.append(col)
        series.append({"label": name, "stroke": _css(colour), "width": 1.5, "points": {"show": False}})
    if with_a and a is not None and b is not None:
        for name, colour in names:
            if name in a.series:
                data.append(np.asarray(a.series[name], dtype=np.float64))
                series.append({"label": f"A: {name}", "stroke": _css(colour), "width": 1.0, "dash": [4, 3],
                               "points": {"show": False}})
    return tuple(data), tuple(series)


def _install_js(uuid: str) -> str:
    """JavaScript for one tab: every 0.4 s, each chart not seen yet (viser re-creates charts
    as their series change) gets a draw hook drawing the cursor line at
    `window.__picoCursorT`, and a click handler writing its time into the number box with id
    `uuid` (as if typed, so viser sends it to the server). Installed once per tab."""
    return (
        f"window.__picoGotoId={json.dumps(uuid)};"
        "if(!window.__picoPlots){var hook=function(){var w=window;var tp=(w.__viserTestpoints||{}).uplots||{};"
        "for(var k in tp){var u=tp[k].chart;if(!u||u.__pico)continue;u.__pico=1;"
        "(u.hooks.draw=u.hooks.draw||[]).push(function(u){var t=w.__picoCursorT;if(t==null)return;"
        "var x=u.valToPos(t,'x',true);if(!isFinite(x))return;var c=u.ctx;c.save();"
        "c.strokeStyle='rgba(213,94,0,0.9)';c.lineWidth=2;c.beginPath();c.moveTo(x,u.bbox.top);"
        "c.lineTo(x,u.bbox.top+u.bbox.height);c.stroke();c.restore();});"
        "(function(u){u.over.addEventListener('click',function(e){var t=u.posToVal(e.offsetX,'x');"
        "var el=document.getElementById(w.__picoGotoId);if(!el||!isFinite(t))return;"
        "var set=Object.getOwnPropertyDescriptor(HTMLInputElement.prototype,'value').set;"
        "set.call(el,t.toFixed(3));el.dispatchEvent(new Event('input',{bubbles:true}));});})(u);"
        "u.redraw(false);}};window.__picoPlots=setInterval(hook,400);hook();}"
    )


def _cursor_js(t: float | None) -> str:
    """Move the cursor line of every chart in the tab to `t` (None: none)."""
    return (f"window.__picoCursorT={json.dumps(t)};var tp=(window.__viserTestpoints||{{}}).uplots||{{}};"
            "for(var k in tp){var u=tp[k].chart;if(u&&u.__pico)u.redraw(false);}")


class PlotsPanel(Panel):
    name = "plots"

    def __init__(self, page: Page, gui: viser.GuiApi, whatif: WhatIf):
        super().__init__(page)
        self.gui = gui
        self.whatif = whatif
        self.status = gui.add_markdown("Change a parameter to re-judge the whole run.")
        self.bar = gui.add_progress_bar(0.0, animated=False)
        self.goto = gui.add_number("Go to t (s)", 0.0, step=0.001,
                                   hint="Jump the timeline to this time; a click on a plot writes its time here")
        on_user(self.goto, page.guard("go to time", lambda e: self.jump_to(float(e.target.value))))
        with gui.add_folder("Plots shown", expand_by_default=False):
            self.toggles = {g.key: gui.add_checkbox(g.title, g.key != "timing") for g in GROUPS}
        for key, box in self.toggles.items():
            on_user(box, page.guard("plots shown", lambda e, k=key: self._toggle(k)))
        self.plots: dict[str, Any] = {}
        self.folder = gui.add_folder("Over the run", expand_by_default=True)
        self._shape: dict[str, tuple[str, ...]] = {}  # series labels each chart was made with
        self._drawn: tuple[Any, ...] = ()  # what the charts show now (B's and A's generation)
        self._cursor_sent: dict[int, tuple[float | None, float]] = {}  # tab -> (t, wall time)
        self.t0 = 0.0
        page.hooks["jump_to_time"] = self.jump_to

    # ----- the charts -------------------------------------------------------------------------
    def _toggle(self, key: str) -> None:
        plot = self.plots.get(key)
        if plot is not None:
            plot.visible = bool(self.toggles[key].value)

    def _update_charts(self) -> None:
        w = self.whatif
        b = w.b.shown
        a = w.a.judged if w.a is not None and (w.comparable or (b is not None and not b.complete)) else None
        key = (id(b), id(a))
        if key == self._drawn:
            return
        self._drawn = key
        self.t0 = start_time(self.page.studio.source) if b is None or not len(b.times) else float(b.times[0])
        if is_replay(self.page.studio.source):
            self.t0 = start_time(self.page.studio.source)
        for order, group in enumerate(GROUPS):
            data, series = chart_data(group, b, a, self.t0)
            labels = tuple(s["label"] for s in series)
            plot = self.plots.get(group.key)
            if len(series) < 2:
                if plot is not None:
                    plot.visible = False
                continue
            if plot is None or self._shape.get(group.key) != labels:
                if plot is not None:
                    plot.remove()
                with self.folder:
                    scales: dict[str, Any] = {"x": {"time": False}}  # seconds, not a date
                    if group.scale is not None:
                        scales["y"] = {"range": list(group.scale)}
                    plot = self.gui.add_uplot(data, series, title=group.title, aspect=1.8, scales=scales,  # type: ignore[arg-type]
                                              order=order, visible=bool(self.toggles[group.key].value))
                self.plots[group.key] = plot
                self._shape[group.key] = labels
            else:
                plot.data = data
                plot.visible = bool(self.toggles[group.key].value)

    def _status_text(self) -> str:
        w = self.whatif
        b = w.b.judged
        done, total = w.progress
        parts = []
        if w.b.waiting and total:
            parts.append(f"re-judging the whole run… {done} / {total} frames")
        elif b is not None:
            parts.append(f"**{len(b.times)} frames** re-judged in {b.seconds:.2f} s")
        if w.error:
            parts.append(f"<span style='color:#c00'>{w.error}</span>")
        if b is not None and b.notes:
            parts.append("<small>" + "; ".join(b.notes) + "</small>")
        return "  \n".join(parts) or "Change a parameter to re-judge the whole run."

    # ----- the timeline -----------------------------------------------------------------------
    def jump_to(self, t_rel: float) -> None:
        """Show the frame at `t_rel` seconds on the plots' axis (paused there)."""
        if not math.isfinite(t_rel):
            return
        s = self.page.studio
        t = self.t0 + t_rel
        if is_replay(s.source):
            self.page.hooks["scrub"](recording_position(s.source, t))
            return
        with s.lock:
            times = np.array([f.time for f in s.timeline]) if len(s.timeline) else np.zeros(0)
        if not len(times):
            return
        self.page.hooks["scrub"](int(np.argmin(np.abs(times - t))))

    def _move_cursor(self, shown: Shown) -> None:
        t = None if shown.frame is None else float(shown.frame.time) - self.t0
        now = time.monotonic()
        for tab in list(self.page.tabs.values()):
            last = self._cursor_sent.get(tab.client_id)
            if last is not None and (last[0] == t or now - last[1] < 1.0 / CURSOR_HZ):
                continue
            first = last is None
            self._cursor_sent[tab.client_id] = (t, now)
            try:
                with warnings.catch_warnings():  # a tab closing meanwhile: its message is dropped
                    warnings.simplefilter("ignore")
                    run_js(tab.client, (_install_js(self.goto._impl.uuid) if first else "") + _cursor_js(t))
            except Exception:  # a tab that just went away
                self._cursor_sent.pop(tab.client_id, None)

    # ----- the panel --------------------------------------------------------------------------
    def connect(self, tab: TabState) -> None:
        self._cursor_sent.pop(tab.client_id, None)

    def refresh(self, shown: Shown) -> None:
        w = self.whatif
        self._update_charts()
        self.status.content = self._status_text()
        done, total = w.progress
        self.bar.value = 100.0 * done / total if w.b.waiting and total else (100.0 if w.b.judged is not None else 0.0)
        if shown is not None:
            self._move_cursor(shown)


def series_help() -> str:
    """Markdown: every series and what it means (for the help text)."""
    return "\n".join(f"- `{s.name}`: {s.help}" + (f" [{s.unit}]" if s.unit else "") for s in SERIES.values())
