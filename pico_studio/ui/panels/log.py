"""The Log tab: every warning and error (time, frame, stage), newest first; a click on an
entry's button jumps to its frame."""

from __future__ import annotations

from typing import Any

import viser

from pico_studio.ui.logbook import LogEntry
from pico_studio.ui.page import Page, Panel, Shown

SHOWN = 12  # entries with a jump button; the rest as text


class LogPanel(Panel):
    name = "log"

    def __init__(self, page: Page, gui: viser.GuiApi):
        super().__init__(page)
        self.gui = gui
        self.summary = gui.add_markdown("No warnings or errors yet.")
        clear = gui.add_button("Clear the log", icon=viser.Icon.TRASH)
        clear.on_click(page.guard("clear log", lambda e: self.clear()))
        self.container = gui.add_folder("Entries", expand_by_default=True)
        self.rows: list[Any] = []
        self.more = None
        self._version = -1

    def clear(self) -> None:
        self.page.log.clear()
        self._version = -1
        self.page.redraw()  # the rows are rebuilt under the redraw's lock, not beside the loop's

    def refresh(self, shown: Shown | None) -> None:
        book = self.page.log
        if book.version == self._version:
            return
        self._version = book.version
        entries = book.newest(200)
        n, warnings = book.counts()
        self.summary.content = (f"**{n} entries**: {warnings} warning(s), {n - warnings} error(s)" if n
                                else "No warnings or errors yet.")
        for row in self.rows:
            row.remove()
        self.rows = []
        with self.container:
            for e in entries[:SHOWN]:
                self.rows.append(self._row(e))
            if len(entries) > SHOWN:
                rest = "\n".join(f"- {e.line()}" for e in entries[SHOWN:60])
                self.rows.append(self.gui.add_markdown(f"<small>{rest}</small>"))

    def _row(self, e: LogEntry) -> Any:
        label = e.line()
        label = label if len(label) <= 110 else label[:107] + "…"
        button = self.gui.add_button(label, color="yellow" if e.level == "warning" else "red", disabled=e.frame is None,
                                     hint="Jump to this frame" if e.frame is not None else None)
        if e.frame is not None:
            frame = e.frame
            button.on_click(self.page.guard("jump to frame", lambda _e: self.jump(frame)))
        return button

    def jump(self, frame: int) -> None:
        """Show the entry's frame: a replay seeks to it, the simulator scrubs the timeline."""
        self.page.hooks["jump_to_frame"](frame)
