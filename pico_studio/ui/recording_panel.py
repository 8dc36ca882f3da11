"""The page's recording controls, beside the Run tab's play/step/timeline:

* **Record** / **Stop recording**: the running session is written as a ROS 1 bag (laser,
  odometry, base references, open-door requests, and the true pose when simulated) into
  the export folder; a reset or map switch ends the recording (the session it recorded
  is gone). The file plays back with `--source bag:FILE` and in ROS tools.
* **Recording position** (replays only): a slider over the whole file. Moving it restarts
  the perceptor at that scan (the recording's own timeline; the Timeline slider above
  scrubs the frames played since, re-processing each with the current config).
* The status line gets the source's own state: the live robot's (stale data, no master)
  or the replay's position in its file.
"""

from __future__ import annotations

from datetime import datetime
from pathlib import Path
from typing import Any

import viser

from pico_studio.sources.recorder import BagRecorder
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


def source_status(studio: Studio) -> str:
    """The source's own state for the status line: live robot or replay position; '' for the sim."""
    source = studio.source
    status = getattr(source, "status", None)
    if callable(status):
        s = status()
        text = s.message
        return f"**{text}**" if (s.stale or not s.master_up) else text
    count = getattr(source, "frame_count", None)
    if count:
        t0, t1 = source.time_span
        return (f"recording frame {max(source.frame_index, 0) + 1} / {count} · "
                f"{source.now() - t0:.2f} / {t1 - t0:.2f} s")
    return ""


class RecordingControls:
    """The widgets: the record toggle and, for a replay, the position slider."""

    def __init__(self, studio: Studio, gui: viser.GuiApi, folder: Path, changed: Any, guard: Any):
        self.studio = studio
        self.recorder = RunRecorder(studio, folder)
        self.changed = changed  # the page re-syncs its play button and redraws
        self._quiet = False
        with gui.add_folder("Recording"):
            self.button = gui.add_button("Record", icon=viser.Icon.PLAYER_RECORD,
                                         hint="Write the run as a ROS 1 bag into the export folder")
            self.button.on_click(guard("record", lambda e: self.toggle()))
            self.position: Any = None
            count = getattr(studio.source, "frame_count", None)
            if count:
                self.position = gui.add_slider(
                    "Recording position", 0, max(count - 1, 1), 1, 0,
                    hint="Jump within the whole recording: the perceptor starts afresh at that scan",
                )
                self.position.on_update(guard("recording position", self._on_position))
            self.text = gui.add_markdown(self.recorder.describe())

    def toggle(self) -> None:
        if self.recorder.active:
            self.recorder.stop()
        else:
            self.recorder.start()
        self.refresh()

    def seek(self, index: int) -> None:
        """Restart at scan `index` of the recording (paused, that frame perceived and shown)."""
        s = self.studio
        with s.lock:
            s.reset()
            s.source.seek(min(max(int(index), 0), s.source.frame_count - 1))
            s.playing = False
            s.tick(1.0 / s.cfg.ui.rate_hz)
        self.changed()

    def _on_position(self, event: viser.GuiEvent) -> None:
        if not self._quiet:
            self.seek(int(event.target.value))

    def refresh(self) -> None:
        """Follow the studio: end a recording whose session is gone, move the position slider."""
        self.recorder.check()
        recording = self.recorder.active
        self.button.label = "Stop recording" if recording else "Record"
        self.button.icon = viser.Icon.PLAYER_STOP if recording else viser.Icon.PLAYER_RECORD
        self.text.content = self.recorder.describe() + _replay_warnings(self.studio.source)
        if self.position is not None and getattr(self.studio.source, "frame_index", -1) >= 0:
            self._quiet = True
            try:
                self.position.value = int(self.studio.source.frame_index)
            finally:
                self._quiet = False


def _replay_warnings(source: Any) -> str:
    """What a replay skipped while reading its file (corrupt messages, bad lines)."""
    warnings = getattr(source, "warnings", None) if hasattr(source, "frame_count") else None
    if not warnings:
        return ""
    shown = "\n".join(f"- {w}" for w in warnings[:3])
    more = f"\n- … and {len(warnings) - 3} more" if len(warnings) > 3 else ""
    return f"\n\n**The recording had {len(warnings)} problem(s)**, skipped:\n{shown}{more}"
