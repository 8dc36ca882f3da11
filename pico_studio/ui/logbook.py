"""Every warning and error the page saw, with when, at which frame and in which stage.

Fed by the redraw (the shown frame's world-model warnings and re-processing errors, stage
"perception"), by the source (a replay's skipped messages, stage "source"), by map loading
(stage "map") and by every guarded callback (stage = the action). The log panel lists the
newest first; a click on one jumps to its frame. No viser here.
"""

from __future__ import annotations

import threading
import time
from collections import deque
from dataclasses import dataclass
from typing import Any

from pico_studio.ui.clock import frame_number, relative_time

MAX_ENTRIES = 500


@dataclass(frozen=True)
class LogEntry:
    level: str  # "warning" | "error"
    stage: str
    message: str
    frame: int | None  # the frame's index (recording position for a replay), when there is one
    time: float | None  # the source's time, relative to the start of the run or recording
    wall: float  # time.time() when logged

    def line(self) -> str:
        at = f"frame {self.frame}" if self.frame is not None else "no frame"
        t = f"t = {self.time:.2f} s" if self.time is not None else "t = –"
        return f"{self.level} · {t} · {at} · {self.stage}: {self.message}"


class LogBook:
    def __init__(self, max_entries: int = MAX_ENTRIES):
        # read only through the methods below: a callback thread adds while the loop's redraw
        # reads, and iterating a deque another thread appends to raises
        self._entries: deque[LogEntry] = deque(maxlen=max_entries)
        self._seen: set[tuple[str, str, int | None]] = set()  # one entry per message and frame
        self._lock = threading.Lock()
        self.version = 0  # bumped on every new entry (the panel redraws only then)

    def add(self, level: str, stage: str, message: str, studio: Any = None, *,
            frame: int | None = None, t: float | None = None) -> LogEntry | None:
        if studio is not None and frame is None:
            frame, t = where(studio)
        key = (stage, message, frame)
        with self._lock:
            if key in self._seen:
                return None
            self._seen.add(key)
            if len(self._seen) > 4 * MAX_ENTRIES:
                self._seen = {(e.stage, e.message, e.frame) for e in self._entries}
            entry = LogEntry(level, stage, message, frame, t, time.time())
            self._entries.append(entry)
            self.version += 1
            return entry

    def newest(self, n: int = 50) -> list[LogEntry]:
        with self._lock:
            return list(self._entries)[::-1][:n]

    def all(self) -> list[LogEntry]:
        """Every entry kept, oldest first (a copy)."""
        with self._lock:
            return list(self._entries)

    def counts(self) -> tuple[int, int]:
        """(entries kept, warnings among them)."""
        with self._lock:
            return len(self._entries), sum(e.level == "warning" for e in self._entries)

    def clear(self) -> None:
        with self._lock:
            self._entries.clear()
            self._seen.clear()
            self.version += 1


def where(studio: Any) -> tuple[int | None, float | None]:
    """The frame shown now and its relative time (a studio's `shown()` and clock)."""
    frame = studio.shown()
    if frame is None:
        return None, None
    return frame_number(studio, frame), relative_time(studio.source, frame.time)
