"""The Run tab's Behaviour section (what drives the robot, its state, target, plan and
progress) and Teleop (buttons and W A S D Q E X keys). Hidden for a replay, which drives
nothing."""

from __future__ import annotations

from typing import Any

import viser

from pico_studio.ui.behaviour_text import behaviour_lines
from pico_studio.ui.clock import is_replay
from pico_studio.ui.gui_values import on_user
from pico_studio.ui.page import Page, Panel, Shown
from pico_studio.ui.runtime import behaviour_names

TELEOP: list[tuple[str, str, tuple[float, float, float]]] = [
    ("Forward", "W", (1, 0, 0)), ("Back", "S", (-1, 0, 0)),
    ("Left", "A", (0, 1, 0)), ("Right", "D", (0, -1, 0)),
    ("Turn left", "Q", (0, 0, 1)), ("Turn right", "E", (0, 0, -1)),
    ("Stop", "X", (0, 0, 0)),
]


class BehaviourPanel(Panel):
    name = "behaviour"

    def __init__(self, page: Page, gui: viser.GuiApi):
        super().__init__(page)
        s = page.studio
        self.drives = not is_replay(s.source)
        self.folder = gui.add_folder("Behaviour", visible=self.drives)
        with self.folder:
            self.dropdown = gui.add_dropdown("Behaviour", list(behaviour_names()), initial_value=s.behaviour_name)
            self.info = gui.add_markdown("")
            self.door = gui.add_button("Open door", icon=viser.Icon.DOOR, hint="Ask the door in front of the robot to open")
        on_user(self.dropdown, page.guard("behaviour", lambda e: s.set_behaviour(e.target.value)))
        self.door.on_click(page.guard("open door", lambda e: s.open_door()))
        self.teleop_folder = gui.add_folder("Teleop (keys W A S D Q E, X stops)", expand_by_default=False, visible=self.drives)
        self.commands: list[Any] = []
        with self.teleop_folder:
            for label, key, move in TELEOP:
                drive = page.guard("teleop", lambda e, move=move: self.drive(*move))
                gui.add_button(f"{label} ({key})").on_click(drive)
                if self.drives:
                    cmd = gui.add_command(f"Teleop: {label}", hotkey=key)  # type: ignore[arg-type]
                    cmd.on_trigger(drive)
                    self.commands.append(cmd)

    def drive(self, fx: float, fy: float, fa: float) -> None:
        s = self.page.studio
        ui = s.cfg.ui
        s.teleop(fx * ui.teleop_speed, fy * ui.teleop_speed, fa * ui.teleop_turn_rate)
        self.dropdown.value = "teleop"  # quiet: shows what drives now

    def refresh(self, shown: Shown) -> None:
        if not self.drives:
            return
        s = self.page.studio
        self.dropdown.value = s.behaviour_name
        self.info.content = "\n\n".join(behaviour_lines(s.behaviour_name, s.behaviour, shown.frame))
