"""The Tune tab: search perception parameters on the current map in background processes,
watch the trials and the best so far plotted live, see the top trials, apply one or export it.

The study is the CLI's (`pico_studio.tuning`): a journal file in the export folder, the
scenario the current map at K random free poses, the start config the page's config now.
One study for the page at a time, shared by every browser tab; it runs in worker processes
so the page stays responsive, and a poll thread draws what the storage holds once a second.
"""

from __future__ import annotations

import json
import threading
from collections.abc import Callable
from datetime import datetime
from pathlib import Path
from typing import Any

import numpy as np
import viser

from pico_studio.config import Config
from pico_studio.errors import ConfigError
from pico_studio.json_map.json_io import map_to_dict
from pico_studio.tuning.backend import METRICS, Scenario, ScenarioSet
from pico_studio.tuning.live import LiveStudy, TrialRow, best_so_far, top
from pico_studio.tuning.objective import DEFAULT_OBJECTIVE, parse_objective
from pico_studio.tuning.report import partial_yaml
from pico_studio.tuning.space import search_space
from pico_studio.tuning.study import StudySpec, storage_url
from pico_studio.ui.page import Page, Panel

DEFAULT_GLOBS = "perception.merge.*,perception.identify.*"
POLL_S = 1.0
TOP = 5
PERCEPTION_METRICS = [m for m in METRICS if not m.startswith(("localisation.", "behaviour."))]


class TunePanel(Panel):
    name = "tune"

    def __init__(self, page: Page, gui: viser.GuiApi, export_dir: Path, apply: Callable[[Config], None]):
        super().__init__(page)
        self.export_dir = export_dir
        self.apply_config = apply
        self.live: LiveStudy | None = None
        self.folder: Path | None = None
        self._poll: threading.Thread | None = None
        self._stop = threading.Event()
        gui.add_markdown("Search parameters that score best against the simulator's truth on the "
                         "current map (Optuna, in background processes).")
        self.globs = gui.add_text("Parameters", DEFAULT_GLOBS, hint="globs, comma separated (see the Config tab)")
        self.objective = gui.add_dropdown("Objective", PERCEPTION_METRICS, initial_value=DEFAULT_OBJECTIVE,
                                          hint="perception_score: mean of wall, corner, door F1 and convexity")
        self.poses = gui.add_number("Poses", 5, min=1, max=200, step=1, hint="random free poses on the map per trial")
        self.trials = gui.add_number("Trials", 30, min=2, max=10000, step=1)
        self.workers = gui.add_number("Workers", 1, min=1, max=16, step=1, hint="background processes")
        self.start_button = gui.add_button("Start study", icon=viser.Icon.PLAYER_PLAY)
        self.stop_button = gui.add_button("Stop", icon=viser.Icon.PLAYER_STOP, disabled=True)
        self.status = gui.add_markdown("No study yet.")
        self.plot = gui.add_uplot(
            (np.zeros(1), np.zeros(1), np.zeros(1)),
            ({"label": "trial #"},
             {"label": "trial", "stroke": "#56B4E9", "width": 0, "points": {"show": True, "size": 6}},
             {"label": "best so far", "stroke": "#E69F00", "width": 2}),
            scales={"x": {"time": False}}, title="value by trial (higher is better)", aspect=1.6)
        self.top_md = gui.add_markdown("")
        self.choice = gui.add_dropdown("Trial", ["-"], initial_value="-")
        self.apply_button = gui.add_button("Apply to the config", icon=viser.Icon.CHECK, disabled=True)
        self.export_button = gui.add_button("Export as YAML", icon=viser.Icon.DOWNLOAD, disabled=True)
        self.export_md = gui.add_markdown("")
        self.start_button.on_click(page.guard("start study", lambda e: self.start()))
        self.stop_button.on_click(page.guard("stop study", lambda e: self.stop()))
        self.apply_button.on_click(page.guard("apply trial", self._on_apply))
        self.export_button.on_click(page.guard("export trial", self._on_export))

    # ----- a study ----------------------------------------------------------------------------
    def start(self) -> None:
        """Start a study on the current map with the page's config as the start trial."""
        if self.live is not None and self.live.running:
            raise ConfigError("a study is running; stop it first", field="Tune")
        s = self.page.studio
        if s.global_map is None:
            raise ConfigError("tuning needs a map to simulate on; choose one in the Run tab", field="Tune")
        cfg = s.cfg
        space = search_space(cfg, str(self.globs.value))
        objective = parse_objective(str(self.objective.value))
        stamp = datetime.now().strftime("%Y%m%d-%H%M%S")
        folder = (self.export_dir / f"tune-{s.map_name or 'map'}-{stamp}").resolve()
        folder.mkdir(parents=True, exist_ok=True)
        map_path = folder / "map.json"  # the map as the page has it (also one drawn or edited)
        map_path.write_text(json.dumps(map_to_dict(s.global_map)), encoding="utf-8")
        name = str(s.map_name or "map")
        scenarios = ScenarioSet(name, None, [Scenario(name, map=str(map_path), poses=int(self.poses.value), frames=20)])
        spec = StudySpec(storage_url(None, folder), name, space, objective, scenarios, cfg,
                         trials=int(self.trials.value))
        self.live = LiveStudy.start(spec, workers=int(self.workers.value))
        self.folder = folder
        self.start_button.disabled, self.stop_button.disabled = True, False
        self.status.content = f"Started: {len(space.dimensions)} parameters, journal `{folder / 'journal.log'}`"
        self._stop.clear()
        self._poll = threading.Thread(target=self._poll_loop, name="pico-studio-tune", daemon=True)
        self._poll.start()

    def stop(self) -> None:
        self._stop.set()
        if self.live is not None:
            self.live.stop()
        self.update()

    def close(self) -> None:
        """End the workers when the page stops."""
        self._stop.set()
        if self.live is not None and self.live.running:
            self.live.stop()

    def _poll_loop(self) -> None:
        while not self._stop.wait(POLL_S):
            try:
                self.update()
            except Exception as e:  # a hiccup reading the journal: say so, keep watching
                self.status.content = f"cannot read the study: {type(e).__name__}: {e}"
            if self.live is None or not self.live.running:
                self.update()
                return

    # ----- what the tab shows -------------------------------------------------------------------
    def update(self) -> None:
        """Redraw status, plot, top trials from the study's storage."""
        live = self.live
        if live is None:
            return
        rows = live.rows()
        done = [r for r in rows if r.value is not None]
        failed = sum(r.state == "FAIL" for r in rows)
        curve = best_so_far(rows)
        best_at = {r.number: b for r, b in zip(sorted(rows, key=lambda r: r.number), curve, strict=True)}
        if done:
            self.plot.data = (np.array([r.number for r in done], float), np.array([r.value for r in done], float),
                              np.array([best_at[r.number] for r in done], float))
        state = "running" if live.running else "stopped" if len(rows) < live.spec.trials else "done"
        start = next((r for r in rows if r.number == 0 and r.value is not None), None)
        best = top(rows, TOP)
        gain = f"; start {start.value:.4f} → best {best[0].value:.4f}" if start and best else ""
        why = f"; a worker ended: {live.error}" if live.error else ""
        self.status.content = (f"**{state}**: {len(rows)}/{live.spec.trials} trials, {len(done)} complete, "
                               f"{failed} failed{gain}{why}")
        self.top_md.content = _top_table(best)
        options = [f"#{r.number}" for r in best] or ["-"]
        if list(self.choice.options) != options:
            self.choice.options = options
            self.choice.value = options[0]
        self.apply_button.disabled = self.export_button.disabled = not best
        if not live.running:
            self.start_button.disabled, self.stop_button.disabled = False, True

    def _chosen(self) -> int:
        text = str(self.choice.value)
        if not text.startswith("#"):
            raise ConfigError("no complete trial to choose yet", field="Trial")
        return int(text[1:])

    def apply_trial(self, number: int) -> Config:
        """Put trial `number`'s config on the page (the sliders follow)."""
        assert self.live is not None
        cfg = self.live.config_of(number)
        self.apply_config(cfg)
        return cfg

    def _on_apply(self, event: viser.GuiEvent) -> None:
        self.apply_trial(self._chosen())

    def export_trial(self, number: int) -> tuple[str, Path]:
        assert self.live is not None and self.folder is not None
        cfg = self.live.config_of(number)
        text = partial_yaml(cfg, header=f"pico-studio tune (page): study '{self.live.spec.study_name}', trial {number}")
        path = self.folder / f"trial-{number}.yaml"
        path.write_text(text, encoding="utf-8")
        return text, path

    def _on_export(self, event: viser.GuiEvent) -> None:
        text, path = self.export_trial(self._chosen())
        self.export_md.content = f"Saved to `{path}`"
        if event.client is not None:
            event.client.send_file_download(path.name, text.encode("utf-8"), save_immediately=True)


def _top_table(rows: list[TrialRow]) -> str:
    if not rows:
        return ""
    lines = ["| trial | value | values |", "|---:|---:|---|"]
    for r in rows:
        lines.append(f"| {r.number} | {r.value:.4f} | {_params_text(r.params)} |")
    return "\n".join(lines)


def _params_text(params: dict[str, Any], limit: int = 3) -> str:
    items = [f"{k.rsplit('.', 1)[-1]}={v:.3g}" if isinstance(v, float) else f"{k.rsplit('.', 1)[-1]}={v}"
             for k, v in params.items()]
    return ", ".join(items[:limit]) + (" …" if len(items) > limit else "")
