"""Help: a modal with the layers and what their colours mean, the tools and the keys; and the
keyboard shortcuts themselves (space play/pause, ← → step, H help; B is kept for an A/B swap,
`Page.hooks["ab_swap"]`, which the what-if panel registers)."""

from __future__ import annotations

import viser

from pico_studio.ui import style
from pico_studio.ui.page import Page, Panel

KEYS: list[tuple[str, str]] = [
    ("space", "play / pause"),
    ("← / →", "step one frame back / on"),
    ("W A S D Q E", "drive by hand (teleop; X stops); not for replays"),
    ("B", "swap A / B (when a comparison is open)"),
    ("H", "this help"),
]

TOOLS = [
    ("Inspect", "click in the view: every wall, corner or door under the click, nearest first, with its numbers"),
    ("Measure", "two clicks: distance, dx, dy and direction"),
    ("Timeline", "scrub to any frame; it is re-processed with the current config"),
    ("Log", "every warning and error with its time, frame and stage; click one to jump to its frame"),
    ("Export", "Config: the tuned parameters as YAML; Tools: the view as PNG or a standalone HTML"),
]


def help_markdown() -> str:
    keys = "\n".join(f"- **{k}**: {v}" for k, v in KEYS)
    tools = "\n".join(f"- **{k}**: {v}" for k, v in TOOLS)
    return f"### Keys\n{keys}\n\n### Tools\n{tools}\n\n### Layers and their colours"


class HelpPanel(Panel):
    name = "help"

    def __init__(self, page: Page, gui: viser.GuiApi):
        super().__init__(page)
        self.gui = gui
        button = gui.add_button("Help (H)", icon=viser.Icon.HELP)
        button.on_click(lambda e: self.open(e.client))
        hooks = page.hooks
        shortcuts = [
            ("Play / pause", "space", lambda: hooks["play_pause"]()),
            ("Step back", "arrowleft", lambda: hooks["step_back"]()),
            ("Step one frame", "arrowright", lambda: hooks["step_forward"]()),
            ("A/B swap", "B", lambda: hooks["ab_swap"]() if "ab_swap" in hooks else None),
        ]
        for label, key, action in shortcuts:
            cmd = gui.add_command(label, hotkey=key)  # type: ignore[arg-type]
            cmd.on_trigger(page.guard(label.lower(), lambda e, action=action: action()))
        help_cmd = gui.add_command("Help", hotkey="H")
        help_cmd.on_trigger(lambda e: self.open(getattr(e, "client", None)))

    def open(self, client: viser.ClientHandle | None) -> None:
        if client is None:
            return
        with client.gui.add_modal("pico_studio: help") as modal:
            client.gui.add_markdown(help_markdown())
            client.gui.add_html(style.legend_html())
            client.gui.add_button("Close").on_click(lambda _: modal.close())
