"""The Tools tab: what a click in the view does in this tab (inspect every feature under it,
or measure between two clicks), and exporting the view (PNG as drawn, standalone HTML)."""

from __future__ import annotations

from datetime import datetime
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import viser

from pico_studio.ui import style
from pico_studio.ui.camera import view_size
from pico_studio.ui.colour import line_uniform
from pico_studio.ui.gui_values import on_user
from pico_studio.ui.inspect import Feature, features_near, measure_text, ray_to_ground
from pico_studio.ui.layers import LAYER_OF
from pico_studio.ui.page import Page, Panel, TabState

MODES = ["inspect", "measure"]
MAX_LISTED = 8


class ToolsPanel(Panel):
    name = "tools"

    def __init__(self, page: Page, gui: viser.GuiApi, export_dir: Path):
        super().__init__(page)
        self.export_dir = export_dir
        self.folder = gui.add_folder("In this tab")
        with gui.add_folder("Export the view"):
            png = gui.add_button("Download PNG of the view", icon=viser.Icon.PHOTO)
            html = gui.add_button("Download standalone HTML", icon=viser.Icon.FILE_CODE)
            self.export_md = gui.add_markdown("")
        png.on_click(page.guard("export PNG", self.export_png))
        html.on_click(page.guard("export HTML", self.export_html))
        page.server.scene.on_click()(page.guard("click", self.on_click))

    def connect(self, tab: TabState) -> None:
        gui, scene = tab.client.gui, tab.client.scene
        h: dict[str, Any] = {}
        with self.folder:
            h["mode"] = gui.add_dropdown(
                "Click does", MODES, initial_value="inspect",
                hint="inspect: every wall, corner or door under the click with its numbers; measure: two clicks, distance and angle",
            )
            h["text"] = gui.add_markdown("Click in the view.")
        on_user(h["mode"], lambda e: self.set_mode(tab, str(e.target.value)))
        h["measure"] = scene.add_line_segments("/tools/measure", np.zeros((1, 2, 3), np.float32), line_uniform(style.MEASURE),
                                               thickness=3.0, thickness_units="screen", visible=False)
        h["inspect"] = scene.add_line_segments("/tools/inspect", np.zeros((1, 2, 3), np.float32), line_uniform(style.INSPECT),
                                               thickness=7.0, thickness_units="screen", visible=False)
        h["inspect_point"] = scene.add_point_cloud("/tools/inspect_point", np.zeros((1, 3), np.float32),
                                                   np.array(style.INSPECT, np.uint8), point_size=0.2, point_shape="circle",
                                                   precision="float32", visible=False)
        h["measure_from"] = None
        tab.handles[self.name] = h
        tab.settings["click_mode"] = "inspect"

    def set_mode(self, tab: TabState, mode: str, save: bool = True) -> None:
        """Switch the tool: the other tool's marks and text are cleared."""
        h = tab.handles[self.name]
        h["mode"].value = mode
        h["measure_from"] = None
        for mark in ("measure", "inspect", "inspect_point"):
            h[mark].visible = False
        h["text"].content = "Click in the view." if mode == "inspect" else "Click the first point."
        tab.settings["click_mode"] = mode
        if save:
            self.page.save_settings(tab)

    def restore(self, tab: TabState, settings: dict[str, Any]) -> None:
        if settings.get("click_mode") in MODES:
            self.set_mode(tab, settings["click_mode"], save=False)

    def mode(self, tab: TabState) -> str:
        return str(tab.handles[self.name]["mode"].value)

    # ----- clicks --------------------------------------------------------------------------------
    def on_click(self, event: viser.SceneClickEvent) -> None:
        xy = ray_to_ground(event.ray_origin, event.ray_direction)
        tab = self.page.tabs.get(event.client_id)
        if xy is None or tab is None or self.name not in tab.handles:
            return
        if self.mode(tab) == "measure":
            self._measure(tab, xy)
        else:
            self._inspect(tab, xy)

    def _measure(self, tab: TabState, xy: tuple[float, float]) -> None:
        h = tab.handles[self.name]
        if h["measure_from"] is None:
            h["measure_from"] = xy
            h["text"].content = f"measure: first point ({xy[0]:.3f}, {xy[1]:.3f}); click the second"
            h["measure"].visible = False
            return
        a, h["measure_from"] = h["measure_from"], None
        h["measure"].points = np.array([[[a[0], a[1], 0.05], [xy[0], xy[1], 0.05]]], np.float32)
        h["measure"].visible = True
        h["text"].content = measure_text(a, xy)

    def _inspect(self, tab: TabState, xy: tuple[float, float]) -> None:
        h = tab.handles[self.name]
        prims = self.page.hooks["prims"]()
        shown = {k: v for k, v in prims.items() if tab.toggles.visible[LAYER_OF[k]]}  # what this tab shows
        found = features_near(xy, shown)
        h["inspect"].visible = False
        h["inspect_point"].visible = False
        if not found:
            h["text"].content = f"nothing within 1 m of ({xy[0]:.3f}, {xy[1]:.3f})"
            return
        h["text"].content = inspect_text(found, self.page.hooks["frame_text"]())
        self._highlight(tab, found[0])

    def _highlight(self, tab: TabState, feature: Feature) -> None:
        h = tab.handles[self.name]
        if feature.segment is not None:
            s = feature.segment
            h["inspect"].points = np.array([[[s[0], s[1], 0.06], [s[2], s[3], 0.06]]], np.float32)
            h["inspect"].visible = True
        elif feature.point is not None:
            h["inspect_point"].points = np.array([[feature.point[0], feature.point[1], 0.06]], np.float32)
            h["inspect_point"].visible = True

    # ----- export --------------------------------------------------------------------------------
    def _save(self, name: str, data: bytes) -> Path:
        self.export_dir.mkdir(parents=True, exist_ok=True)
        path = (self.export_dir / name).resolve()
        path.write_bytes(data)
        self.export_md.content = f"Saved to `{path}`"
        return path

    def export_png(self, event: viser.GuiEvent) -> None:
        client = event.client
        if client is None:
            return
        w, h = view_size(client)  # a size the tab sent, checked
        rgba = client.get_render(height=h, width=w, transport_format="png", timeout=20.0)
        rgb = rgba[:, :, :3].astype(np.float32)
        alpha = rgba[:, :, 3:4].astype(np.float32) / 255.0 if rgba.shape[2] == 4 else 1.0
        img = (rgb * alpha + 255.0 * (1.0 - alpha)).astype(np.uint8)  # on the page's white
        ok, png = cv2.imencode(".png", img[:, :, ::-1])
        name = f"pico_studio_view_{datetime.now():%Y%m%d-%H%M%S}.png"
        path = self._save(name, png.tobytes())
        client.send_file_download(path.name, path.read_bytes(), save_immediately=True)

    def export_html(self, event: viser.GuiEvent) -> None:
        html = self.page.server.scene.as_html()
        path = self._save(f"pico_studio_scene_{datetime.now():%Y%m%d-%H%M%S}.html", html.encode("utf-8"))
        if event.client is not None:
            event.client.send_file_download(path.name, path.read_bytes(), save_immediately=True)


def inspect_text(found: list[Feature], when: str) -> str:
    lines = [f"**{len(found)} feature(s) under the click**, nearest first ({when}):"]
    lines += [f"{i + 1}. {f.describe()}" for i, f in enumerate(found[:MAX_LISTED])]
    if len(found) > MAX_LISTED:
        lines.append(f"… and {len(found) - MAX_LISTED} more")
    return "\n".join(lines)
