"""The Run tab's Map section: pick an example map or upload one (JSON, PNG/PGM heightmap).
A new map starts playing at once, with the robot drawn."""

from __future__ import annotations

import tempfile
from pathlib import Path

import viser

from pico_studio.errors import MapError
from pico_studio.json_map import load_map
from pico_studio.ui.gui_values import on_user
from pico_studio.ui.page import Page, Panel
from pico_studio.ui.sources import example_maps
from pico_studio.user_files import check_upload

KEEP = "(keep)"


class MapPanel(Panel):
    name = "map"

    def __init__(self, page: Page, gui: viser.GuiApi):
        super().__init__(page)
        s = page.studio
        self.maps = example_maps()
        with gui.add_folder("Map", expand_by_default=False):
            current = s.map_name if s.map_name in self.maps else KEEP
            self.choice = gui.add_dropdown("Example", [KEEP, *self.maps], initial_value=current)
            self.upload = gui.add_upload_button("Upload map (JSON / PNG)", icon=viser.Icon.UPLOAD, mime_type=".json,.png,.pgm")
        on_user(self.choice, page.guard("map", self._pick))
        self.upload.on_upload(page.guard("map upload", self._on_upload))

    def _pick(self, event: viser.GuiEvent) -> None:
        name = event.target.value
        s = self.page.studio
        if name == KEEP or name == s.map_name:
            return
        try:
            self.switch(self.maps[name], name, event.client)
        finally:  # show the map that is really loaded
            self.choice.value = s.map_name if s.map_name in self.maps else KEEP

    def _on_upload(self, event: viser.GuiEvent) -> None:
        f = event.target.value
        name = check_upload(f.name, f.content, MapError, (".json", ".png", ".pgm"))  # capped, a safe name
        folder = Path(tempfile.mkdtemp(prefix="pico_studio_map_"))
        path = folder / name
        path.write_bytes(f.content)
        self.switch(path, name, event.client)

    def switch(self, path: Path, name: str, client: viser.ClientHandle | None) -> None:
        """Load the map, restart the world in it and play from its first frame."""
        s = self.page.studio
        global_map = load_map(path, s.cfg.map)
        with s.lock:
            s.set_map(global_map, name)
            s.playing = True
            s.tick(1.0 / s.cfg.ui.rate_hz)  # the robot is drawn at once, not after the next tick
        self.page.map_changed()
        for w in global_map.warnings:
            self.page.log.add("warning", "map", f"{name}: {w}", s)
        for w in global_map.warnings[:5]:
            self.page.notify(client, "map warning", w, color="yellow")
