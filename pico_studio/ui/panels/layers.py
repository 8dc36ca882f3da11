"""The Layers tab: each tab's own layer toggles (a colour swatch beside each), Follow robot,
the on-canvas legend and the dark theme; Fit map. All per tab and remembered by the
browser across reloads."""

from __future__ import annotations

from typing import Any

import viser

from pico_studio.ui import camera, style
from pico_studio.ui.browser_js import show_legend
from pico_studio.ui.gui_values import on_user
from pico_studio.ui.page import Page, Panel, Shown, TabState
from pico_studio.ui.scene_data import LAYERS


class LayersPanel(Panel):
    name = "layers"

    def __init__(self, page: Page, gui: viser.GuiApi):
        super().__init__(page)
        self.folder = gui.add_folder("Shown in this tab")
        fit = gui.add_button("Fit map", icon=viser.Icon.ZOOM_RESET)
        fit.on_click(lambda e: self.fit(e.client) if e.client is not None else None)
        # a recording without a map: keep the robot in view
        self.follow_default = page.studio.global_map is None

    def connect(self, tab: TabState) -> None:
        gui = tab.client.gui
        h: dict[str, Any] = {}
        with self.folder:
            for layer in LAYERS:
                gui.add_html(style.swatch_row(layer.key))
                cb = gui.add_checkbox(layer.label, layer.default_on)
                on_user(cb, lambda e, key=layer.key: self.set_layer(tab, key, bool(e.target.value)))
                h[layer.key] = cb
            h["follow"] = gui.add_checkbox("Follow robot", self.follow_default, hint="Keep the robot in the middle of this tab's view")
            h["legend"] = gui.add_checkbox("Legend on the view", True, hint="The short colour key, bottom left")
            h["dark"] = gui.add_checkbox("Dark theme", False)
        on_user(h["follow"], self.page.guard("follow", lambda e: self.set_follow(tab, bool(e.target.value))))
        on_user(h["legend"], lambda e: self.set_legend(tab, bool(e.target.value)))
        on_user(h["dark"], lambda e: self.set_dark(tab, bool(e.target.value)))
        tab.handles[self.name] = h
        tab.client.camera.on_update(lambda cam: self.page.hooks["pixel_size"](camera.metres_per_pixel(tab.client)))
        tab.settings.update({"follow": self.follow_default, "legend": True, "dark": False})
        tab.settings["layers"] = {layer.key: layer.default_on for layer in LAYERS}
        self.set_legend(tab, True, save=False)

    # ----- the settings (a user's click, or restored after a reload) ----------------------
    def set_layer(self, tab: TabState, key: str, on: bool, save: bool = True) -> None:
        tab.toggles.set(key, on)
        tab.handles[self.name][key].value = on
        tab.settings["layers"][key] = on
        if save:
            self.page.save_settings(tab)

    def set_follow(self, tab: TabState, on: bool, save: bool = True) -> None:
        tab.handles[self.name]["follow"].value = on
        tab.settings["follow"] = on
        tab.last_follow = None
        if on:
            self.page.redraw()
        else:
            self.fit(tab.client)
        if save:
            self.page.save_settings(tab)

    def set_legend(self, tab: TabState, on: bool, save: bool = True) -> None:
        tab.handles[self.name]["legend"].value = on
        tab.settings["legend"] = on
        show_legend(tab.client, style.short_legend_html(tab.settings.get("dark", False)), on, tab.settings.get("dark", False))
        if save:
            self.page.save_settings(tab)

    def set_dark(self, tab: TabState, on: bool, save: bool = True) -> None:
        tab.handles[self.name]["dark"].value = on
        tab.settings["dark"] = on
        tab.client.gui.configure_theme(control_width="large", show_logo=False, dark_mode=on)
        self.set_legend(tab, tab.settings["legend"], save=False)
        if save:
            self.page.save_settings(tab)

    def restore(self, tab: TabState, settings: dict[str, Any]) -> None:
        for key, on in (settings.get("layers") or {}).items():
            if key in tab.settings["layers"]:
                self.set_layer(tab, key, bool(on), save=False)
        if "dark" in settings:
            self.set_dark(tab, bool(settings["dark"]), save=False)
        if "legend" in settings:
            self.set_legend(tab, bool(settings["legend"]), save=False)
        if "follow" in settings:
            self.set_follow(tab, bool(settings["follow"]), save=False)

    # ----- the camera ----------------------------------------------------------------------------
    def fit(self, client: viser.ClientHandle) -> None:
        m = self.page.studio.global_map
        camera.fit(client, self.page.studio.cfg.ui.camera_fov, m.bounds if m is not None else None)

    def refresh(self, shown: Shown) -> None:
        """Centre the view of every tab with Follow on."""
        if shown.robot is None:
            return
        xy = (shown.robot[0], shown.robot[1])
        span = self.page.studio.cfg.ui.follow_span
        fov = self.page.studio.cfg.ui.camera_fov
        for tab in list(self.page.tabs.values()):
            if not tab.settings.get("follow"):
                continue
            if tab.last_follow is not None and abs(tab.last_follow[0] - xy[0]) + abs(tab.last_follow[1] - xy[1]) < 0.01:
                continue
            tab.last_follow = xy
            try:
                camera.look_at(tab.client, fov, xy[0], xy[1], span, span)
            except Exception:  # a tab closing right now must not stop the loop
                pass
