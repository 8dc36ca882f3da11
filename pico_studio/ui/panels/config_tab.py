"""The Config tab: reset to defaults, export / import YAML, and a slider per parameter
(`ui.config_panel.ConfigPanel`)."""

from __future__ import annotations

import time
from datetime import datetime
from pathlib import Path
from typing import Any

import viser

from pico_studio.config import Config, dump_yaml, loads_config
from pico_studio.errors import ConfigError, UserError
from pico_studio.ui.config_panel import ConfigPanel
from pico_studio.ui.page import Page, Panel
from pico_studio.user_files import check_upload


class ConfigTab(Panel):
    name = "config"

    def __init__(self, page: Page, gui: viser.GuiApi, export_dir: Path):
        super().__init__(page)
        self.export_dir = export_dir
        self.last_export: Path | None = None
        self.update_ms: list[float] = []  # slider change -> layers sent, server side (wall)
        self.update_cpu_ms: list[float] = []  # the same, CPU time of the callback's thread
        reset = gui.add_button("Reset to defaults", icon=viser.Icon.RESTORE)
        export = gui.add_button("Export config (YAML)", icon=viser.Icon.DOWNLOAD)
        upload = gui.add_upload_button("Import config (YAML)", icon=viser.Icon.UPLOAD, mime_type=".yaml,.yml")
        self.export_md = gui.add_markdown("")
        reset.on_click(page.guard("reset to defaults", lambda e: self.apply(Config())))
        export.on_click(page.guard("export", self._on_export))
        upload.on_upload(page.guard("config import", self._on_upload))
        self.sliders = ConfigPanel(gui, page.studio.cfg, page.guard("parameter", lambda e, path: self.edit(path, e.target.value)))

    def edit(self, path: str, value: Any) -> None:
        """What a user's edit of one parameter does: validate, re-process the frame shown,
        redraw; an invalid value is put back on the page and reported."""
        t0, c0 = time.perf_counter(), time.thread_time()
        try:
            self.page.studio.set_param(path, value)
        except UserError:
            self.sliders.show(self.page.studio.cfg)
            raise
        self.page.redraw()
        self.page.server.flush()
        self.update_ms.append((time.perf_counter() - t0) * 1000.0)
        self.update_cpu_ms.append((time.thread_time() - c0) * 1000.0)
        self.page.hooks["rescore"]()

    def apply(self, cfg: Config) -> None:
        self.page.studio.set_config(cfg)
        self.sliders.show(cfg)
        self.page.redraw()
        self.page.hooks["rescore"]()

    def export_yaml(self) -> tuple[str, Path]:
        text = dump_yaml(self.page.studio.cfg)
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

    def _on_upload(self, event: viser.GuiEvent) -> None:
        f = event.target.value
        check_upload(f.name, f.content, ConfigError, (".yaml", ".yml"))  # capped before parsing
        try:
            text = f.content.decode("utf-8")
        except UnicodeDecodeError:
            raise UserError("not a text file", file=f.name) from None
        self.apply(loads_config(text, file=f.name))
        self.page.notify(event.client, "config imported", f.name, color="green")
