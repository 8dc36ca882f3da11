"""The page's recording controls, beside the Run tab's play/step/timeline:

* **Record** / **Stop recording**: the running session is written as a ROS 1 bag (laser,
  odometry, base references, open-door requests, and the true pose when simulated) into
  the export folder; a reset or map switch ends the recording (the session it recorded
  is gone). The file plays back with `--source bag:FILE` and in ROS tools.
* A replay's position in its file is the Run tab's one scrubber (`seek`); what the replay
  skipped while reading its file goes to the log.
"""

from __future__ import annotations

from datetime import datetime
from pathlib import Path
from typing import Any

import viser

from pico_studio.sources.recorder import BagRecorder
from pico_studio.ui.clock import is_replay
from pico_studio.ui.page import Page, Panel, Shown
from pico_studio.ui.runtime import Studio


class RunRecorder:
    """Records the studio's session to a bag until stopped, or until the studio resets."""

    def __init__(self, studio: Studio, folder: Path):
        self.studio = studio
        self.folder = folder
        self.recorder: BagRecorder | None = None
        self._session: Any = None
        self.last: dict[str, Any] | None = None  # the file and counts of the last recording

    @property
    def active(self) -> bool:
        return self.recorder is not None

    def start(self) -> Path:
        cfg = self.studio.cfg.sources
        stamp = datetime.now().strftime("%Y%m%d-%H%M%S")
        self.folder.mkdir(parents=True, exist_ok=True)
        path = (self.folder / f"pico_studio_run_{stamp}.bag").resolve()
        n = 1
        while path.exists():
            path = path.with_name(f"pico_studio_run_{stamp}_{n}.bag")
            n += 1
        recorder = BagRecorder(path, cfg.topics, compression=cfg.recorder.compression)
        with self.studio.lock:
            self.stop()
            self.studio.session.recorder = recorder
            self.recorder, self._session = recorder, self.studio.session
        return path

    def stop(self) -> dict[str, Any] | None:
        with self.studio.lock:
            recorder, self.recorder = self.recorder, None
            if recorder is None:
                return None
            if self._session is not None and self._session.recorder is recorder:
                self._session.recorder = None
            self._session = None
            recorder.close()
            self.last = {"file": str(recorder.path), "messages": dict(sorted(recorder.counts.items()))}
            return self.last

    def check(self) -> None:
        """End the recording if the studio started a new session (reset, map switch)."""
        if self.recorder is not None and self.studio.session is not self._session:
            self.stop()

    def describe(self) -> str:
        if self.recorder is not None:
            scans = self.recorder.counts.get(self.recorder.topics.laser, 0)
            return f"**Recording** to `{self.recorder.path.name}`: {scans} scans so far"
        if self.last is not None:
            return f"Recorded `{self.last['file']}`: " + ", ".join(f"{k} {v}" for k, v in self.last["messages"].items())
        return "Record the run as a ROS 1 bag (plays back with `--source bag:FILE` and in ROS)."


class RecordingControls(Panel):
    """The record toggle, and a replay's seek."""

    name = "recording"

    def __init__(self, page: Page, gui: viser.GuiApi, folder: Path):
        super().__init__(page)
        self.studio = page.studio
        self.recorder = RunRecorder(page.studio, folder)
        with gui.add_folder("Recording", expand_by_default=False):
            self.button = gui.add_button("Record", icon=viser.Icon.PLAYER_RECORD,
                                         hint="Write the run as a ROS 1 bag into the export folder")
            self.button.on_click(page.guard("record", lambda e: self.toggle()))
            self.text = gui.add_markdown(self.recorder.describe())
        self._logged_warnings = 0

    def toggle(self) -> None:
        if self.recorder.active:
            self.recorder.stop()
        else:
            self.recorder.start()
        self.page.redraw()  # under the redraw's lock, like every panel's refresh

    def seek(self, index: int) -> None:
        """Show frame `index` of the recording (paused, the world model built up to it)."""
        self.page.hooks["seek"](index)

    def refresh(self, shown: Shown | None) -> None:
        """Follow the studio: end a recording whose session is gone; log what a replay skipped."""
        self.recorder.check()
        recording = self.recorder.active
        self.button.label = "Stop recording" if recording else "Record"
        self.button.icon = viser.Icon.PLAYER_STOP if recording else viser.Icon.PLAYER_RECORD
        self.text.content = self.recorder.describe() + _replay_warnings(self.studio.source)
        warnings = getattr(self.studio.source, "warnings", None) if is_replay(self.studio.source) else None
        for w in (warnings or [])[self._logged_warnings:]:
            self.page.log.add("warning", "source", str(w), frame=None)
        self._logged_warnings = len(warnings or [])


def _replay_warnings(source: Any) -> str:
    """What a replay skipped while reading its file (corrupt messages, bad lines)."""
    warnings = getattr(source, "warnings", None) if is_replay(source) else None
    if not warnings:
        return ""
    shown = "\n".join(f"- {w}" for w in warnings[:3])
    more = f"\n- … and {len(warnings) - 3} more" if len(warnings) > 3 else ""
    return f"\n\n**The recording had {len(warnings)} problem(s)**, skipped:\n{shown}{more}"
