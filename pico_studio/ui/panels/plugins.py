"""The Plugins tab: the loaded plugins and their stages, reloading a changed plugin file
without restarting the server, and what the plugins handed the page on the frame shown.

A reload runs the changed files again (`pico_studio.plugins.reload`) under the studio's
lock, carries the config over to the new declarations (`plugins.rebase`) and re-processes
the frame shown, so the edit is on screen at once. A file that no longer imports is a red
notification; its previous version keeps running.
"""

from __future__ import annotations

import viser

from pico_studio import plugins
from pico_studio.ui.page import Page, Panel, Shown


def plugin_lines() -> list[str]:
    """One markdown line per loaded plugin: where from, its stages, changed / last error."""
    lines = []
    for p in plugins.loaded():
        stages = ", ".join(f"{s.kind.replace('_', ' ')} `{s.name}`" for s in p.stages) or "no stages"
        note = " — **changed on disk**" if p.changed() else ""
        if p.error:
            note += f" — last reload failed: {p.error}"
        lines.append(f"- `{p.key}` ({p.origin}): {stages}{note}")
    return lines


def extras_lines(extras: dict) -> list[str]:  # type: ignore[type-arg]
    out = []
    for name, a in extras.items():
        kind = "segments" if a.ndim == 2 and a.shape[1] == 4 else "points"
        out.append(f"- `{name}`: {len(a)} {kind}")
    return out


class PluginsPanel(Panel):
    name = "plugins"

    def __init__(self, page: Page, gui: viser.GuiApi):
        super().__init__(page)
        self.list_md = gui.add_markdown("")
        reload = gui.add_button("Reload changed plugins", icon=viser.Icon.REFRESH,
                                hint="Run the plugin files saved since they were loaded again (all when none changed)")
        reload.on_click(page.guard("plugin reload", self._on_reload))
        self.extras_md = gui.add_markdown("")
        self._shown = ("", "")
        self._update_list()

    def reload(self) -> list[str]:
        """Reload the changed plugins (every one when none changed); the keys reloaded."""
        studio = self.page.studio
        with studio.lock:
            todo = plugins.changed() or plugins.loaded()
            done: list[str] = []
            try:
                for p in todo:
                    plugins.reload(p.key)
                    done.append(p.key)
            finally:
                studio.set_config(plugins.rebase(studio.cfg))  # new declarations; re-processes the frame
        return done

    def _on_reload(self, event: viser.GuiEvent) -> None:
        try:
            done = self.reload()
        finally:
            self._update_list()
            self.page.redraw()
        names = ", ".join(k.rsplit("/", 1)[-1] for k in done) or "no plugins loaded"
        self.page.notify(event.client, "plugins reloaded", names, color="green")

    def _update_list(self) -> None:
        lines = plugin_lines()
        text = "**Loaded plugins**\n\n" + ("\n".join(lines) if lines else "none (start with `--plugin FILE.py`)")
        if text != self._shown[0]:
            self.list_md.content = text
            self._shown = (text, self._shown[1])

    def refresh(self, shown: Shown) -> None:
        self._update_list()
        wm = shown.frame.wm if shown.frame is not None else None
        lines = extras_lines(getattr(wm, "extras", {}) or {})
        text = "**Plugin outputs on this frame**\n\n" + ("\n".join(lines) if lines else "none")
        if text != self._shown[1]:
            self.extras_md.content = text
            self._shown = (self._shown[0], text)



