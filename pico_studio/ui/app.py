"""The web page: a viser server over a `Studio`, with a top-down view, layers and panels.

    app = StudioApp(studio, host="127.0.0.1", port=8080); app.start(); ...; app.stop()

Threads: viser calls the callbacks on its thread pool; `_loop` ticks the studio at
`ui.rate_hz`; both redraw under `studio.lock`. Every callback is wrapped by `_guard`: a user
error (bad upload, invalid value) becomes a red notification in the page and a log line,
anything else is logged with its traceback and reported too — the server stays up, and the
tuned config is never replaced by a half-applied one.
"""

from __future__ import annotations

import contextlib
import functools
import logging
import math
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from datetime import datetime
from pathlib import Path
from typing import Any

import numpy as np
import viser

from pico_studio.config import Config, dump_yaml, loads_config
from pico_studio.errors import MapError, UserError
from pico_studio.ui import style
from pico_studio.ui.colour import line_uniform
from pico_studio.ui.config_panel import ConfigPanel
from pico_studio.ui.inspect import measure_text, nearest_feature, ray_to_ground
from pico_studio.ui.layers import LAYER_OF, LayerToggles, SceneLayers
from pico_studio.ui.recording_panel import RecordingControls, source_status
from pico_studio.ui.runtime import BEHAVIOURS, Studio
from pico_studio.ui.scene_data import LAYERS, frame_prims, map_prims, room_text
from pico_studio.ui.sources import example_maps, load_any_map

log = logging.getLogger(__name__)
CAMERA_MARGIN = 1.15  # the map fills ~85% of the view
PANEL_PX = 420  # the control panel (control_width="large") covers this much of the view's right side


@dataclass
class TabState:
    """What belongs to one browser tab; rebuilt from scratch on every (re)connect: its layer
    toggles and Follow (client-scoped GUI and scene), its click mode, measuring and inspect
    marks and their text."""

    client: viser.ClientHandle
    toggles: LayerToggles
    follow: Any = None  # the tab's "Follow robot" checkbox
    last_follow: tuple[float, float] | None = None  # where its camera was last centred
    measure_from: tuple[float, float] | None = None
    tools: dict[str, Any] = field(default_factory=dict)  # per-tab scene nodes
    checkboxes: dict[str, Any] = field(default_factory=dict)  # layer key -> its checkbox
    click_mode: Any = None  # the tab's "Click does" dropdown
    tool_md: Any = None  # what its last click found


class StudioApp:
    def __init__(
        self,
        studio: Studio,
        *,
        host: str = "127.0.0.1",
        port: int = 8080,
        export_dir: str | Path = "pico_studio_exports",
        verbose: bool = True,
    ):
        self.studio = studio
        self.export_dir = Path(export_dir)
        self.server = viser.ViserServer(host=host, port=port, label="pico_studio", verbose=verbose)
        self.server.scene.set_up_direction("+z")
        self.server.scene.world_axes.visible = False
        self.tabs: dict[int, TabState] = {}
        self.layers = SceneLayers(self.server)
        self.map_prims = map_prims(studio.global_map)
        self.layers.update(self.map_prims)
        self.update_ms: list[float] = []  # slider change -> layers sent, server side (wall)
        self.update_cpu_ms: list[float] = []  # the same, CPU time of the callback's thread
        self.last_export: Path | None = None
        self._stop = threading.Event()
        self._draw_lock = threading.RLock()
        self._thread: threading.Thread | None = None
        # a recording without a map: keep the robot in view
        self.follow_default = studio.global_map is None
        self._build_gui()
        self.server.on_client_connect(self._on_connect)
        self.server.on_client_disconnect(lambda c: self.tabs.pop(c.client_id, None))
        self.server.scene.on_click()(self._guard("click", self._on_click))
        self.redraw()

    # ----- lifecycle ------------------------------------------------------------------------
    @property
    def url(self) -> str:
        return f"http://{self.server.get_host()}:{self.server.get_port()}"

    def start(self) -> None:
        self._thread = threading.Thread(target=self._loop, name="pico-studio-loop", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=2.0)
        self.recording.recorder.stop()
        self.server.stop()

    # ----- errors -------------------------------------------------------------------------------
    def notify(self, client: viser.ClientHandle | None, title: str, body: str, color: str = "red") -> None:
        targets = [client] if client is not None else list(self.server.get_clients().values())
        for c in targets:
            try:
                c.add_notification(title, body, color=color, auto_close_seconds=10.0)  # type: ignore[arg-type]
            except Exception:  # a tab that just went away
                log.debug("notification to a closed tab dropped")

    def _guard(self, what: str, fn: Callable[..., None]) -> Callable[..., None]:
        @functools.wraps(fn)
        def wrapper(event: Any = None, *args: Any) -> None:
            client = getattr(event, "client", None)
            try:
                fn(event, *args)
            except UserError as e:
                log.warning("%s: %s", what, e)
                self.notify(client, f"{what}: error", str(e))
            except Exception as e:
                log.exception("%s failed", what)
                self.notify(client, f"{what}: internal error", f"{type(e).__name__}: {e}")

        return wrapper

    # ----- the loop and drawing --------------------------------------------------------------------
    def _loop(self) -> None:
        debt = 0.0
        next_t = time.monotonic()
        while not self._stop.is_set():
            period = 1.0 / self.studio.cfg.ui.rate_hz
            try:
                if self.studio.playing:
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
                self._sync_play_button()
                self.notify(None, "paused by an error", f"{type(e).__name__}: {e}")
            next_t += period
            now = time.monotonic()
            if next_t < now - 1.0:
                next_t = now
            self._stop.wait(max(0.0, next_t - now))

    def redraw(self) -> None:
        """Push the frame under the cursor: layers, metrics, timeline, follow camera. The loop
        and the callbacks both redraw; one at a time."""
        with self._draw_lock:
            self._redraw()

    def _redraw(self) -> None:
        with self.studio.lock:
            frame = self.studio.shown()
            prims = frame_prims(self.studio, frame)
            metrics = self.studio.metrics()
            n = len(self.studio.timeline)
            pos = (n - 1 if self.studio.cursor is None else self.studio.cursor) if n else 0
            robot = self.studio.robot_pose_in_map(frame) if frame is not None else None
            status = self._status_text(frame)
        self.prims = prims
        self.layers.update(prims)
        with self._quiet_timeline():
            self.timeline.max = max(1, n - 1)
            self.timeline.value = min(pos, max(1, n - 1))
        self.metrics_md.content = self._metrics_text(metrics)
        self.status_md.content = status
        self.recording.refresh()
        if robot is not None:
            self._follow(robot[:2])

    def _status_text(self, frame: Any) -> str:
        s = self.studio
        state = "playing" if s.playing else "paused"
        if frame is None:
            return f"**{s.map_name}** · {state} · no frame yet"
        live = "live" if s.cursor is None else f"timeline frame {frame.index}"
        if getattr(frame.wm, "too_close", False):
            live += " · **too close!**"
        source = source_status(s)
        return f"**{s.map_name}** · {state} · {live} · t = {frame.time:.2f} s · behaviour: {frame.behaviour_state or s.behaviour_name}" + (f" · {source}" if source else "")

    def _metrics_text(self, m: dict[str, Any]) -> str:
        lines = []
        ms = "–" if math.isnan(m["ms"]) else f"{m['ms']:.1f} ms"
        lines.append(f"**Perception** {m['hz']:.1f} Hz · last frame {ms}")
        if m["stages"]:
            lines.append("Stages: " + " · ".join(f"{k} {v:.2f} ms" for k, v in m["stages"].items()))
        if m["counts"]:
            lines.append("Counts: " + " · ".join(f"{k.replace('_', ' ')} {v}" for k, v in m["counts"].items()))
        percept = []
        lm = m.get("laser_motion")
        if lm is not None:
            percept.append(f"laser motion ({lm[0]:+.3f} m, {lm[1]:+.3f} m, {lm[2]:+.3f} rad), {m['laser_motion_matches']} matches")
        if m.get("entrance") is not None:
            a, d = m["entrance"]
            percept.append(f"{'hallway' if m.get('hallway') else 'entrance'} at {d:.2f} m, {a:+.2f} rad")
        if m.get("room"):
            percept.append("side room: " + room_text(m["room"]))
        if percept:
            lines.append(" · ".join(percept))
        loc = m.get("localisation") or {}
        if loc:
            text = f"**Localisation** quality {loc['quality']:.2f}" + (" · LOST" if loc["lost"] else "")
            if "error_m" in loc:
                text += f" · error vs truth {loc['error_m']:.3f} m, {loc['error_rad']:.3f} rad"
            lines.append(text)
        for which, title in (("frame", "this frame"), ("run", "since reset")):
            figures = m["scores"].get(which)
            if figures:
                lines.append(f"**Truth, {title}**: " + " · ".join(f"{k} {v:.2f}" for k, v in figures.items()))
        if m["warnings"]:
            lines.append("Warnings: " + "; ".join(m["warnings"][:5]))
        return "\n\n".join(lines)

    # ----- camera -------------------------------------------------------------------------------
    def _view(self, client: viser.ClientHandle, cx: float, cy: float, span_x: float, span_y: float) -> None:
        """Look straight down at (cx, cy) so that span_x x span_y fits beside the panel."""
        fov = self.studio.cfg.ui.camera_fov
        w = client.camera.image_width or 1200
        h = client.camera.image_height or 800
        panel = PANEL_PX if w > 2 * PANEL_PX else 0
        view_h = max(span_y, span_x * h / (w - panel)) * CAMERA_MARGIN  # world metres, vertically
        cx += 0.5 * panel * view_h / h  # centre the map in the part the panel leaves free
        height = view_h / (2.0 * math.tan(fov / 2.0))
        with client.atomic():
            client.camera.fov = fov
            client.camera.up_direction = (0.0, 1.0, 0.0)
            client.camera.position = (cx, cy, height)
            client.camera.look_at = (cx, cy, 0.0)
            client.camera.far = height * 4.0

    def fit_map(self, client: viser.ClientHandle) -> None:
        m = self.studio.global_map
        x0, y0, x1, y1 = m.bounds if m is not None else (-5.0, -5.0, 5.0, 5.0)
        self._view(client, (x0 + x1) / 2, (y0 + y1) / 2, max(x1 - x0, 1.0), max(y1 - y0, 1.0))

    def _follow(self, xy: tuple[float, float]) -> None:
        """Centre the view of every tab with Follow on."""
        span = self.studio.cfg.ui.follow_span
        for tab in list(self.tabs.values()):
            if tab.follow is None or not tab.follow.value:
                continue
            if tab.last_follow is not None and math.dist(tab.last_follow, xy) < 0.01:
                continue
            tab.last_follow = xy
            try:
                self._view(tab.client, xy[0], xy[1], span, span)
            except Exception:  # a tab closing right now must not stop the loop
                log.debug("camera of a closed tab not moved")

    # ----- tabs ---------------------------------------------------------------------------------
    def _on_connect(self, client: viser.ClientHandle) -> None:
        tab = TabState(client, LayerToggles(client))
        self._build_tab_layers(tab)
        self._build_tab_tools(tab)
        tab.tools["measure"] = client.scene.add_line_segments(
            "/tools/measure", np.zeros((1, 2, 3), np.float32), line_uniform(style.MEASURE), thickness=0.04, visible=False
        )
        tab.tools["inspect"] = client.scene.add_line_segments(
            "/tools/inspect", np.zeros((1, 2, 3), np.float32), line_uniform(style.INSPECT), thickness=0.12, visible=False
        )
        tab.tools["inspect_point"] = client.scene.add_point_cloud(
            "/tools/inspect_point", np.zeros((1, 3), np.float32), np.array(style.INSPECT, np.uint8),
            point_size=0.3, point_shape="circle", precision="float32", visible=False,
        )
        self.tabs[client.client_id] = tab
        self.fit_map(client)
        if tab.follow.value and getattr(self, "prims", None) is not None:
            self.redraw()

    def _on_click(self, event: viser.SceneClickEvent) -> None:
        xy = ray_to_ground(event.ray_origin, event.ray_direction)
        tab = self.tabs.get(event.client_id)
        if xy is None or tab is None:
            return
        if tab.click_mode.value == "measure":
            if tab.measure_from is None:
                tab.measure_from = xy
                tab.tool_md.content = f"measure: first point ({xy[0]:.3f}, {xy[1]:.3f}); click the second"
                tab.tools["measure"].visible = False
            else:
                a, tab.measure_from = tab.measure_from, None
                tab.tools["measure"].points = np.array([[[a[0], a[1], 0.05], [xy[0], xy[1], 0.05]]], np.float32)
                tab.tools["measure"].visible = True
                tab.tool_md.content = measure_text(a, xy)
            return
        shown = {k: v for k, v in (self.prims | self.map_prims).items() if tab.toggles.visible[LAYER_OF[k]]}
        feature = nearest_feature(xy, shown)  # what this tab shows
        tab.tools["inspect"].visible = False
        tab.tools["inspect_point"].visible = False
        if feature is None:
            tab.tool_md.content = f"nothing within 1 m of ({xy[0]:.3f}, {xy[1]:.3f})"
            return
        tab.tool_md.content = feature.describe()
        if feature.segment is not None:
            s = feature.segment
            tab.tools["inspect"].points = np.array([[[s[0], s[1], 0.04], [s[2], s[3], 0.04]]], np.float32)
            tab.tools["inspect"].visible = True
        elif feature.point is not None:
            tab.tools["inspect_point"].points = np.array([[feature.point[0], feature.point[1], 0.04]], np.float32)
            tab.tools["inspect_point"].visible = True

    # ----- panels -------------------------------------------------------------------------------
    def _build_gui(self) -> None:
        gui = self.server.gui
        gui.configure_theme(control_width="large", show_logo=False)
        self.status_md = gui.add_markdown("")
        tabs = gui.add_tab_group()
        with tabs.add_tab("Run"):
            self._build_run(gui)
        with tabs.add_tab("Layers"):
            self._build_layers(gui)
        with tabs.add_tab("Config"):
            self._build_config(gui)
        with tabs.add_tab("Tools"):
            self._build_tools(gui)

    def _build_run(self, gui: viser.GuiApi) -> None:
        s = self.studio
        self.play = gui.add_button("Pause" if s.playing else "Play", icon=viser.Icon.PLAYER_PAUSE if s.playing else viser.Icon.PLAYER_PLAY)
        step = gui.add_button("Step one frame", icon=viser.Icon.PLAYER_TRACK_NEXT)
        reset = gui.add_button("Reset", icon=viser.Icon.REFRESH, hint="Restart the source, the perceptor and the timeline")
        speed = gui.add_slider("Speed", 0.25, 4.0, 0.25, s.speed, hint="Simulated seconds per wall-clock second")
        self.timeline = gui.add_slider("Timeline", 0, 1, 1, 0, hint="Scrub the recorded frames (pauses); each is re-processed with the current config")
        live = gui.add_button("Back to live", icon=viser.Icon.PLAYER_SKIP_FORWARD)
        self.metrics_md = gui.add_markdown("")
        self.recording = RecordingControls(s, gui, self.export_dir, lambda: (self._sync_play_button(), self.redraw()), self._guard)

        self.play.on_click(self._guard("play/pause", self._on_play))
        step.on_click(self._guard("step", self._on_step))
        reset.on_click(self._guard("reset", self._on_reset))
        speed.on_update(self._guard("speed", lambda e: setattr(s, "speed", float(e.target.value))))
        live.on_click(self._guard("back to live", self._on_live))
        self.timeline.on_update(self._guard("timeline", self._on_scrub))

        with gui.add_folder("Behaviour"):
            behaviour = gui.add_dropdown("Behaviour", list(BEHAVIOURS), initial_value=s.behaviour_name)
            behaviour.on_update(self._guard("behaviour", lambda e: s.set_behaviour(e.target.value)))
            self.behaviour_dropdown = behaviour
            door = gui.add_button("Open door", icon=viser.Icon.DOOR, hint="Ask the door in front of the robot to open")
            door.on_click(self._guard("open door", lambda e: s.open_door()))
        with gui.add_folder("Teleop (keys W A S D Q E, X stops)"):
            self._build_teleop(gui)
        with gui.add_folder("Map"):
            maps = example_maps()
            current = s.map_name if s.map_name in maps else None
            choice = gui.add_dropdown("Example", ["(keep)"] + list(maps), initial_value=current or "(keep)")
            upload = gui.add_upload_button("Upload map (JSON / PNG)", icon=viser.Icon.UPLOAD, mime_type=".json,.png,.pgm")

            def pick(event: viser.GuiEvent) -> None:
                name = event.target.value
                if name == "(keep)" or name == s.map_name:
                    return
                try:
                    self.switch_map(maps[name], name, event.client)
                except Exception:
                    with _NoCallbacks(choice):  # show the map that is really loaded
                        choice.value = s.map_name if s.map_name in maps else "(keep)"
                    raise

            choice.on_update(self._guard("map", pick))
            upload.on_upload(self._guard("map upload", self._on_map_upload))
            self.map_choice = choice

    # ----- run control -------------------------------------------------------------------------
    def _on_play(self, _event: Any = None) -> None:
        s = self.studio
        s.playing = not s.playing
        if s.playing:
            s.scrub(None)
        self._sync_play_button()
        self.redraw()

    def _on_step(self, _event: Any = None) -> None:
        """Pause and advance exactly one control period."""
        s = self.studio
        s.playing = False
        s.scrub(None)
        s.tick(1.0 / s.cfg.ui.rate_hz)
        self._sync_play_button()
        self.redraw()

    def _on_reset(self, _event: Any = None) -> None:
        self.studio.reset()
        self.redraw()

    def _on_live(self, _event: Any = None) -> None:
        self.studio.scrub(None)
        self.studio.playing = True
        self._sync_play_button()
        self.redraw()

    def _on_scrub(self, event: viser.GuiEvent) -> None:
        """The timeline slider moved (by the user): pause on that frame, re-processed."""
        if self._timeline_quiet:
            return
        self.studio.playing = False
        self.studio.scrub(int(event.target.value))
        self._sync_play_button()
        self.redraw()

    _timeline_quiet = False

    @contextlib.contextmanager
    def _quiet_timeline(self) -> Iterator[None]:
        self._timeline_quiet = True
        try:
            yield
        finally:
            self._timeline_quiet = False

    def _sync_play_button(self) -> None:
        playing = self.studio.playing
        self.play.label = "Pause" if playing else "Play"
        self.play.icon = viser.Icon.PLAYER_PAUSE if playing else viser.Icon.PLAYER_PLAY

    def _build_teleop(self, gui: viser.GuiApi) -> None:
        s = self.studio
        moves: list[tuple[str, str, tuple[float, float, float]]] = [
            ("Forward", "W", (1, 0, 0)), ("Back", "S", (-1, 0, 0)),
            ("Left", "A", (0, 1, 0)), ("Right", "D", (0, -1, 0)),
            ("Turn left", "Q", (0, 0, 1)), ("Turn right", "E", (0, 0, -1)),
            ("Stop", "X", (0, 0, 0)),
        ]
        for label, key, (fx, fy, fa) in moves:
            def drive(_: Any = None, fx: float = fx, fy: float = fy, fa: float = fa) -> None:
                ui = s.cfg.ui
                s.teleop(fx * ui.teleop_speed, fy * ui.teleop_speed, fa * ui.teleop_turn_rate)
                with self.behaviour_quiet():
                    self.behaviour_dropdown.value = "teleop"

            button = gui.add_button(f"{label} ({key})")
            button.on_click(self._guard("teleop", drive))
            cmd = gui.add_command(f"Teleop: {label}", hotkey=key)  # type: ignore[arg-type]
            cmd.on_trigger(self._guard("teleop", drive))

    def behaviour_quiet(self) -> Any:
        return _NoCallbacks(self.behaviour_dropdown)

    def _build_layers(self, gui: viser.GuiApi) -> None:
        # the toggles and Follow are each tab's own: filled in per tab on connect
        self.layer_folder = gui.add_folder("Shown in this tab")
        fit = gui.add_button("Fit map", icon=viser.Icon.ZOOM_RESET)
        fit.on_click(lambda e: self.fit_map(e.client) if e.client is not None else None)
        gui.add_html(style.legend_html())

    def _build_tab_layers(self, tab: TabState) -> None:
        """The layer toggles and Follow of one tab (client-scoped, in the shared Layers tab)."""
        gui = tab.client.gui
        with self.layer_folder:
            for layer in LAYERS:
                cb = gui.add_checkbox(layer.label, layer.default_on)
                cb.on_update(functools.partial(self._toggle_layer, tab, layer.key))
                tab.checkboxes[layer.key] = cb
            tab.follow = gui.add_checkbox("Follow robot", self.follow_default, hint="Keep the robot in the middle of this tab's view")
        tab.follow.on_update(self._guard("follow", functools.partial(self._on_follow, tab)))

    def _toggle_layer(self, tab: TabState, key: str, event: viser.GuiEvent) -> None:
        tab.toggles.set(key, bool(event.target.value))

    def _on_follow(self, tab: TabState, event: viser.GuiEvent) -> None:
        tab.last_follow = None
        if event.target.value:
            self.redraw()
        else:
            self.fit_map(tab.client)

    def _build_config(self, gui: viser.GuiApi) -> None:
        reset = gui.add_button("Reset to defaults", icon=viser.Icon.RESTORE)
        export = gui.add_button("Export config (YAML)", icon=viser.Icon.DOWNLOAD)
        upload = gui.add_upload_button("Import config (YAML)", icon=viser.Icon.UPLOAD, mime_type=".yaml,.yml")
        self.export_md = gui.add_markdown("")
        reset.on_click(self._guard("reset to defaults", lambda e: self.apply_config(Config())))
        export.on_click(self._guard("export", self._on_export))
        upload.on_upload(self._guard("config import", self._on_config_upload))
        self.config_panel = ConfigPanel(gui, self.studio.cfg, self._guard("parameter", self._on_param))

    def _build_tools(self, gui: viser.GuiApi) -> None:
        # the click mode and its result are each tab's own: filled in per tab on connect
        self.tools_folder = gui.add_folder("In this tab")

    def _build_tab_tools(self, tab: TabState) -> None:
        gui = tab.client.gui
        with self.tools_folder:
            tab.click_mode = gui.add_dropdown(
                "Click does", ["inspect", "measure"], initial_value="inspect",
                hint="inspect: the nearest wall, corner or door with its numbers; measure: two clicks, distance and angle",
            )
            tab.tool_md = gui.add_markdown("Click in the view.")
        tab.click_mode.on_update(lambda e: setattr(tab, "measure_from", None))

    # ----- actions ----------------------------------------------------------------------------
    def _on_param(self, event: viser.GuiEvent, path: str) -> None:
        t0, c0 = time.perf_counter(), time.thread_time()
        try:
            self.studio.set_param(path, event.target.value)
        except UserError:
            self.config_panel.show(self.studio.cfg)  # put the slider back to the valid value
            raise
        self.redraw()
        self.server.flush()
        self.update_ms.append((time.perf_counter() - t0) * 1000.0)
        self.update_cpu_ms.append((time.thread_time() - c0) * 1000.0)
        self._rescore()

    def _rescore(self) -> None:
        """The truth scores of a re-processed live frame, after its layers went out."""
        self.studio.rescore()
        self.metrics_md.content = self._metrics_text(self.studio.metrics())

    def apply_config(self, cfg: Config) -> None:
        self.studio.set_config(cfg)
        self.config_panel.show(cfg)
        self.redraw()
        self._rescore()

    def export_yaml(self) -> tuple[str, Path]:
        text = dump_yaml(self.studio.cfg)
        stamp = datetime.now().strftime("%Y%m%d-%H%M%S")
        path = (self.export_dir / f"pico_studio_config_{stamp}.yaml").resolve()
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        self.last_export = path
        return text, path

    def _on_export(self, event: viser.GuiEvent) -> None:
        text, path = self.export_yaml()
        self.export_md.content = f"Saved to `{path}`"
        if event.client is not None:
            event.client.send_file_download(path.name, text.encode("utf-8"), save_immediately=True)

    def _on_config_upload(self, event: viser.GuiEvent) -> None:
        f = event.target.value
        try:
            text = f.content.decode("utf-8")
        except UnicodeDecodeError:
            raise UserError("not a text file", file=f.name) from None
        self.apply_config(loads_config(text, file=f.name))
        self.notify(event.client, "config imported", f.name, color="green")

    def _on_map_upload(self, event: viser.GuiEvent) -> None:
        f = event.target.value
        suffix = Path(f.name).suffix.lower()
        if suffix not in (".json", ".png", ".pgm"):
            raise MapError("upload a JSON map or a PNG/PGM heightmap", file=f.name)
        folder = Path(tempfile.mkdtemp(prefix="pico_studio_map_"))
        path = folder / Path(f.name).name
        path.write_bytes(f.content)
        self.switch_map(path, f.name, event.client)

    def switch_map(self, path: Path, name: str, client: viser.ClientHandle | None) -> None:
        global_map = load_any_map(path, self.studio.cfg)
        self.studio.set_map(global_map, name)
        self.map_prims = map_prims(global_map)
        self.layers.update(self.map_prims)
        for tab in list(self.tabs.values()):
            self.fit_map(tab.client)
        self.redraw()
        for w in global_map.warnings[:5]:
            self.notify(client, "map warning", w, color="yellow")


class _NoCallbacks:
    """Write a GUI value from the server without its update callbacks firing."""

    def __init__(self, handle: Any):
        self.handle = handle

    def __enter__(self) -> None:
        self.saved = list(self.handle._impl.update_cb)
        self.handle._impl.update_cb.clear()

    def __exit__(self, *exc: object) -> None:
        self.handle._impl.update_cb.extend(self.saved)
