"""The Run tab's transport: play/pause, step back/forward, reset, speed, the one scrubber,
back to live, and the metrics text.

The scrubber covers the timeline kept in memory for the simulator and the live robot, and
the whole file for a replay (its frames numbered from the start of the recording).
"""

from __future__ import annotations

import math

import viser

from pico_studio.ui.clock import is_replay, recording_position
from pico_studio.ui.gui_values import on_user
from pico_studio.ui.page import Page, Panel, Shown
from pico_studio.ui.reference_layer import agreement_text
from pico_studio.ui.status import metrics_text

# Simulated seconds per wall-clock second; "max" ticks as fast as the perceptor computes.
SPEEDS = {"0.25×": 0.25, "0.5×": 0.5, "1×": 1.0, "2×": 2.0, "4×": 4.0, "8×": 8.0, "max": math.inf}


def speed_label(speed: float) -> str:
    for label, v in SPEEDS.items():
        if v == speed:
            return label
    return "1×"


class RunPanel(Panel):
    name = "run"

    def __init__(self, page: Page, gui: viser.GuiApi):
        super().__init__(page)
        s = page.studio
        self.replay = is_replay(s.source)
        self.play = gui.add_button("Play", icon=viser.Icon.PLAYER_PLAY, hint="Play / pause (space)")
        with gui.add_folder("Step", expand_by_default=True):
            self.back = gui.add_button("Step back", icon=viser.Icon.PLAYER_TRACK_PREV, hint="One frame back (←)")
            self.step = gui.add_button("Step one frame", icon=viser.Icon.PLAYER_TRACK_NEXT, hint="One frame on (→)")
        self.reset = gui.add_button("Reset", icon=viser.Icon.REFRESH, hint="Restart the source, the perceptor and the timeline")
        self.speed = gui.add_dropdown("Speed", list(SPEEDS), initial_value=speed_label(s.speed),
                                      hint="Source seconds per wall-clock second; max: as fast as it computes")
        hint = ("Any frame of the recording, re-processed with the current config" if self.replay
                else "Scrub the recorded frames (pauses); each is re-processed with the current config")
        self.scrubber = gui.add_slider("Timeline", 0, 1, 1, 0, hint=hint)
        self.live = gui.add_button("Back to live", icon=viser.Icon.PLAYER_SKIP_FORWARD, visible=not self.replay)
        self.metrics_md = gui.add_markdown("")

        guard = page.guard
        self.play.on_click(guard("play/pause", lambda e: self.toggle_play()))
        self.step.on_click(guard("step", lambda e: self.step_forward()))
        self.back.on_click(guard("step back", lambda e: self.step_back()))
        self.reset.on_click(guard("reset", lambda e: self.do_reset()))
        self.live.on_click(guard("back to live", lambda e: self.back_to_live()))
        on_user(self.speed, guard("speed", lambda e: setattr(s, "speed", SPEEDS[e.target.value])))
        on_user(self.scrubber, guard("timeline", lambda e: self.scrub(int(e.target.value))))
        page.hooks["play_pause"] = self.toggle_play
        page.hooks["step_forward"] = self.step_forward
        page.hooks["step_back"] = self.step_back
        page.hooks["scrub"] = self.scrub

    # ----- actions (the buttons, the keys and the log's jumps) -------------------------------
    def toggle_play(self) -> None:
        s = self.page.studio
        if self.replay and not s.playing and not s.source.ok():  # at the end: play it again
            self.page.hooks["seek"](0)
        with s.lock:
            s.playing = not s.playing
            if s.playing and not self.replay:
                s.scrub(None)
        self.page.redraw()

    def step_forward(self) -> None:
        """Pause and advance exactly one control period (a replay: one frame)."""
        s = self.page.studio
        with s.lock:
            s.playing = False
            if self.replay:
                s.cursor = None
                self.page.hooks["replay_step"]()
            else:
                s.scrub(None)
                s.tick(1.0 / s.cfg.ui.rate_hz)
        self.page.redraw()

    def step_back(self) -> None:
        s = self.page.studio
        with s.lock:
            s.playing = False
            if self.replay:
                shown = s.shown()
                k = recording_position(s.source, shown.time) if shown is not None else 0
                self.page.hooks["seek"](max(k - 1, 0))
                return
            n = len(s.timeline)
            pos = (n - 1 if s.cursor is None else s.cursor) - 1
            s.scrub(max(pos, 0))
        self.page.redraw()

    def do_reset(self) -> None:
        self.page.studio.reset()
        self.page.redraw()

    def back_to_live(self) -> None:
        s = self.page.studio
        with s.lock:
            s.scrub(None)
            s.playing = True
        self.page.redraw()

    def scrub(self, position: int) -> None:
        """Pause on that frame (a replay: that frame of the file), re-processed."""
        s = self.page.studio
        if self.replay:
            s.playing = False
            self.page.hooks["seek"](position)
            return
        with s.lock:
            s.playing = False
            s.scrub(position)
        self.page.redraw()

    # ----- following the studio ------------------------------------------------------------------
    def refresh(self, shown: Shown) -> None:
        playing = shown.playing
        self.play.label = "Pause" if playing else "Play"
        self.play.icon = viser.Icon.PLAYER_PAUSE if playing else viser.Icon.PLAYER_PLAY
        top = max(1, shown.length - 1)
        if self.scrubber.max != top:
            self.scrubber.max = top
        self.scrubber.value = min(shown.position, top)  # quiet: only users' edits call back
        agreement = agreement_text(shown.metrics.get("agreement") or {})
        self.metrics_md.content = metrics_text(shown.metrics) + (f"\n\n{agreement}" if agreement else "")
