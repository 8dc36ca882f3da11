"""The web page: a viser server over a `Studio`, with a top-down view, layers and panels.

    app = StudioApp(studio, host="127.0.0.1", port=8080); app.start(); ...; app.stop()

This module only wires: it makes the server, the shared scene (`SceneLayers`), the log, and
the panels (`ui/panels/`, `ui/recording_panel.py`; each owns its widgets, see `ui.page`),
and runs the loop. Threads: viser calls the callbacks on its thread pool; `_loop` ticks the
studio at `ui.rate_hz` (or as fast as it computes at speed "max"); both redraw under
`studio.lock`, one redraw at a time. Every callback is wrapped by `Page.guard`: an error
becomes a red notification and a log entry, the server stays up.
"""

from __future__ import annotations

import json
import logging
import math
import threading
import time
from pathlib import Path
from typing import Any

import viser

from pico_studio.config import Config
from pico_studio.ui.ab_panel import ABPanel
from pico_studio.ui.client_input import guard_connection, guard_server
from pico_studio.ui.clock import frame_number, is_replay, recording_position, relative_time
from pico_studio.ui.layers import LayerToggles, SceneLayers
from pico_studio.ui.logbook import LogBook
from pico_studio.ui.page import Page, Panel, Shown, TabState
from pico_studio.ui.panels.behaviour import BehaviourPanel
from pico_studio.ui.panels.config_tab import ConfigTab
from pico_studio.ui.panels.help import HelpPanel
from pico_studio.ui.panels.layers import LayersPanel
from pico_studio.ui.panels.log import LogPanel
from pico_studio.ui.panels.map_choice import MapPanel
from pico_studio.ui.panels.plugins import PluginsPanel
from pico_studio.ui.panels.run import RunPanel
from pico_studio.ui.panels.tools import ToolsPanel
from pico_studio.ui.panels.tune import TunePanel
from pico_studio.ui.plots_panel import PlotsPanel
from pico_studio.ui.recording_panel import RecordingControls
from pico_studio.ui.replay import ReplayDriver
from pico_studio.ui.runtime import Studio
from pico_studio.ui.scene_data import Prim, frame_prims, map_prims
from pico_studio.ui.status import status_text
from pico_studio.ui.whatif import WhatIf

log = logging.getLogger(__name__)
SETTINGS_KEY = "pico_studio.tab_settings"  # one JSON object per browser (local storage)
MAX_BUSY_S = 0.05  # at speed "max": compute this long, then draw


class StudioApp:
    def __init__(
        self,
        studio: Studio,
        *,
        host: str = "127.0.0.1",
        port: int = 8080,
        export_dir: str | Path = "pico_studio_exports",
        verbose: bool = True,
        workers: int = 2,
    ):
        self.studio = studio
        self.export_dir = Path(export_dir)
        self.server = viser.ViserServer(host=host, port=port, label="pico_studio", verbose=verbose)
        guard_server(self.server, self._notify_tab)  # what a tab sends is checked first (client_input.py)
        self.server.scene.set_up_direction("+z")
        self.server.scene.world_axes.visible = False
        self.log = LogBook()
        self.page = Page(self.server, studio, self.log)
        self.layers = SceneLayers(self.server)
        self.map_prims = map_prims(studio.global_map)
        self.layers.update(self.map_prims)
        self.prims: dict[str, Prim] = {}
        self._stop = threading.Event()
        self._draw_lock = threading.RLock()
        self._thread: threading.Thread | None = None
        self.replay = ReplayDriver(studio) if is_replay(studio.source) else None
        self.whatif = WhatIf(studio, on_update=self.redraw, workers=workers)  # the whole run re-judged, A/B
        self.whatif.attach()
        self._build_panels()
        self.server.on_client_connect(self._on_connect)
        self.server.on_client_disconnect(self._on_disconnect)
        if self.replay is not None:  # a recording opens on its first frame, drawn
            playing = studio.playing
            self.replay.seek(0)
            studio.playing = playing
        self.redraw()

    def _build_panels(self) -> None:
        page, gui = self.page, self.server.gui
        gui.configure_theme(control_width="large", show_logo=False)
        page.redraw = self.redraw
        page.map_changed = self._map_changed
        page.save_settings = self._save_settings
        page.hooks.update(prims=lambda: self.prims | self.map_prims, frame_text=self._frame_text,
                          rescore=self._rescore, jump_to_frame=self.jump_to_frame,
                          pixel_size=self.layers.set_pixel_size, seek=self.seek,
                          replay_step=lambda: self.replay.step() if self.replay is not None else None)
        self.status_md = gui.add_markdown("")
        self.help = HelpPanel(page, gui)
        tabs = gui.add_tab_group()
        with tabs.add_tab("Run"):
            self.run = RunPanel(page, gui)
            self.behaviour = BehaviourPanel(page, gui)
            self.map = MapPanel(page, gui)
            self.recording = RecordingControls(page, gui, self.export_dir)
        with tabs.add_tab("Layers"):
            self.layers_panel = LayersPanel(page, gui)
        with tabs.add_tab("Config"):
            self.config = ConfigTab(page, gui, self.export_dir)
        with tabs.add_tab("What-if"):
            self.ab = ABPanel(page, gui, self.whatif, self.export_dir)
            self.plots = PlotsPanel(page, gui, self.whatif)
        with tabs.add_tab("Tools"):
            self.tools = ToolsPanel(page, gui, self.export_dir)
        with tabs.add_tab("Tune"):
            self.tune = TunePanel(page, gui, self.export_dir, apply=self.config.apply)
        with tabs.add_tab("Log"):
            self.log_panel = LogPanel(page, gui)
        with tabs.add_tab("Plugins"):
            self.plugins = PluginsPanel(page, gui)
        self.tab_group = tabs
        self.panels: list[Panel] = [self.run, self.behaviour, self.map, self.recording, self.layers_panel,
                                    self.config, self.ab, self.plots, self.tools, self.tune, self.log_panel,
                                    self.plugins, self.help]

    # ----- what tests and benchmarks read ---------------------------------------------------
    @property
    def url(self) -> str:
        return f"http://{self.server.get_host()}:{self.server.get_port()}"

    @property
    def tabs(self) -> dict[int, TabState]:
        return self.page.tabs

    @property
    def play(self) -> viser.GuiButtonHandle:
        return self.run.play

    @property
    def timeline(self) -> Any:
        return self.run.scrubber

    @property
    def config_panel(self) -> Any:
        return self.config.sliders

    @property
    def update_ms(self) -> list[float]:
        return self.config.update_ms

    @property
    def update_cpu_ms(self) -> list[float]:
        return self.config.update_cpu_ms

    @property
    def last_export(self) -> Path | None:
        return self.config.last_export

    def export_yaml(self) -> tuple[str, Path]:
        return self.config.export_yaml()

    def apply_config(self, cfg: Config) -> None:
        self.config.apply(cfg)

    def switch_map(self, path: Path, name: str, client: viser.ClientHandle | None) -> None:
        self.map.switch(path, name, client)

    def set_b(self, cfg: Config) -> None:
        """Make `cfg` the current config, B, against a pinned A (the Tune tab's "apply as
        B"): the sliders show it, the frame shown is re-processed, the whole run re-judged."""
        self.config.apply(cfg)

    # ----- lifecycle ------------------------------------------------------------------------
    def start(self) -> None:
        self._thread = threading.Thread(target=self._loop, name="pico-studio-loop", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=2.0)
        self.recording.recorder.stop()
        self.tune.close()
        self.whatif.close()
        self.server.stop()

    # ----- the loop and drawing --------------------------------------------------------------------
    def _loop(self) -> None:
        debt = 0.0
        next_t = time.monotonic()
        while not self._stop.is_set():
            period = 1.0 / self.studio.cfg.ui.rate_hz
            try:
                if self.studio.playing and self.replay is not None:
                    self.replay.play(period, self.studio.speed)
                    self.redraw()
                elif self.studio.playing:
                    if math.isinf(self.studio.speed):
                        self._tick_flat_out(period)
                    else:
                        debt += period * self.studio.speed
                        ticks = 0
                        while debt >= period - 1e-9 and ticks < 20:
                            self.studio.tick(period)
                            debt -= period
                            ticks += 1
                        debt = min(debt, period)
                    self.redraw()
            except Exception as e:  # a bug in a stage must not kill the page: pause and say so
                log.exception("the live loop stopped")
                self.studio.playing = False
                self.log.add("error", "loop", f"paused by an error: {type(e).__name__}: {e}", self.studio)
                self.page.notify(None, "paused by an error", f"{type(e).__name__}: {e}")
                self.redraw()
            next_t += period
            now = time.monotonic()
            if next_t < now - 1.0:
                next_t = now
            self._stop.wait(max(0.0, next_t - now))

    def _tick_flat_out(self, period: float) -> None:
        end = time.monotonic() + MAX_BUSY_S
        while self.studio.playing and time.monotonic() < end:
            self.studio.tick(period)

    def redraw(self) -> None:
        """Push the frame under the cursor to the scene and every panel. The loop and the
        callbacks both redraw; one at a time."""
        with self._draw_lock:
            shown = self._snapshot()
            self.prims = shown.prims
            self.layers.update(shown.prims)
            self.status_md.content = status_text(self.studio, shown.frame)
            for panel in self.panels:
                try:
                    panel.refresh(shown)
                except Exception as e:  # one panel's bug must not pause the run: that panel says so
                    log.exception("the %s panel failed to refresh", panel.name)
                    self.log.add("error", f"{panel.name} panel", f"refresh failed: {type(e).__name__}: {e}")

    def _snapshot(self) -> Shown:
        s = self.studio
        with s.lock:
            frame = s.shown()
            replay = is_replay(s.source)
            if replay:
                length = s.source.frame_count
                position = recording_position(s.source, frame.time) if frame is not None else 0
            else:
                length = len(s.timeline)
                position = (length - 1 if s.cursor is None else s.cursor) if length else 0
            if frame is not None:
                for w in list(frame.wm.warnings if frame.wm is not None else []) + list(frame.errors):
                    self.log.add("warning", "perception", w, frame=frame_number(s, frame),
                                 t=relative_time(s.source, frame.time))
            robot = s.robot_pose_in_map(frame) if frame is not None else None
            prims = frame_prims(s, frame) | self.ab.prims(frame.time if frame is not None else None, robot)
            return Shown(
                frame=frame, prims=prims, metrics=s.metrics(), length=length, position=position,
                robot=robot, playing=s.playing, replay=replay,
            )

    def _frame_text(self) -> str:
        s = self.studio
        frame = s.shown()
        if frame is None:
            return "no frame"
        text = f"frame {frame_number(s, frame)}, t = {relative_time(s.source, frame.time):.2f} s"
        if is_replay(s.source):
            text += f", stamp {frame.time:.3f}"  # absolute on inspect
        return text

    def _rescore(self) -> None:
        """After a change: the truth scores of the re-processed live frame (its layers went
        out first), then the whole run re-judged in the background."""
        self.studio.rescore()
        self.redraw()
        self.whatif.changed()

    def jump_to_frame(self, number: int) -> None:
        """Show frame `number` (as the log numbers frames): seek a replay, scrub the timeline."""
        s = self.studio
        if self.replay is not None:
            self.seek(number)
            return
        first = s.timeline[0].index if len(s.timeline) else 0
        self.page.hooks["scrub"](number - first)

    def seek(self, number: int) -> None:
        """Show frame `number` of the recording, its world model built up to it (paused)."""
        if self.replay is None:
            return
        self.replay.seek(number)
        self.redraw()

    def _map_changed(self) -> None:
        self.map_prims = map_prims(self.studio.global_map)
        self.layers.update(self.map_prims)
        for tab in list(self.page.tabs.values()):
            self.layers_panel.fit(tab.client)
        self.redraw()

    # ----- tabs ---------------------------------------------------------------------------------
    def _notify_tab(self, client_id: int, title: str, body: str) -> None:
        client = self.server.get_clients().get(client_id)
        if client is not None:
            self.page.notify(client, title, body)

    def _on_connect(self, client: viser.ClientHandle) -> None:
        guard_connection(client, self._notify_tab)
        tab = TabState(client, LayerToggles(client))
        for panel in self.panels:
            panel.connect(tab)
        self.page.tabs[client.client_id] = tab
        self.layers_panel.fit(client)
        threading.Thread(target=self._restore, args=(tab,), name="pico-studio-restore", daemon=True).start()
        if tab.settings.get("follow"):
            self.redraw()

    def _on_disconnect(self, client: viser.ClientHandle) -> None:
        self.page.tabs.pop(client.client_id, None)

    def _restore(self, tab: TabState) -> None:
        """Apply what this browser saved before a reload (local storage)."""
        try:
            text = tab.client.local_storage.get_item(SETTINGS_KEY, timeout=10.0)
        except (RuntimeError, TimeoutError) as e:
            log.debug("no saved settings: %s", e)
            return
        if not text:
            tab.settings["restored"] = True
            return
        try:
            saved = json.loads(text)
        except json.JSONDecodeError:
            log.warning("saved page settings unreadable; defaults kept")
            return
        if not isinstance(saved, dict):
            return
        for panel in self.panels:
            try:
                panel.restore(tab, saved)
            except Exception:  # a stale or hand-edited entry must not break the tab
                log.exception("restoring %s settings failed", panel.name)
        tab.settings["restored"] = True

    def _save_settings(self, tab: TabState) -> None:
        data = {k: v for k, v in tab.settings.items() if k != "restored"}
        try:
            tab.client.local_storage.set_item(SETTINGS_KEY, json.dumps(data))
        except Exception:  # a tab that just went away
            log.debug("settings of a closed tab not saved")
