"""A one-line progress report on stderr for long headless work (eval, run, replays).

Drawn only on a terminal (so JSON on stdout and CI logs stay clean), at most a few times a
second, and cleared at the end:

    with Progress(total=60.0, label="simulating", unit="s") as progress:
        while ...:
            progress.set(sim.now() - start)
"""

from __future__ import annotations

import sys
import time
from typing import Any, TextIO


class Progress:
    def __init__(
        self,
        total: float,
        label: str,
        unit: str = "",
        *,
        stream: TextIO | None = None,
        min_interval: float = 0.2,
    ):
        self.total = max(float(total), 0.0)
        self.label = label
        self.unit = unit
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = bool(getattr(self.stream, "isatty", lambda: False)())
        self.min_interval = min_interval
        self.t0 = time.monotonic()
        self._last_draw = -float("inf")
        self.done = 0.0

    def set(self, done: float) -> None:
        self.done = min(max(float(done), 0.0), self.total) if self.total else float(done)
        now = time.monotonic()
        if self.enabled and now - self._last_draw >= self.min_interval:
            self._last_draw = now
            self.stream.write("\r" + self.line(now) + "\x1b[K")
            self.stream.flush()

    def line(self, now: float | None = None) -> str:
        elapsed = (time.monotonic() if now is None else now) - self.t0
        unit = f" {self.unit}" if self.unit else ""
        if not self.total:
            return f"{self.label}: {self.done:g}{unit} ({elapsed:.1f} s)"
        frac = self.done / self.total
        width = 24
        bar = "#" * int(round(frac * width)) + "-" * (width - int(round(frac * width)))
        eta = f", {elapsed / frac - elapsed:.0f} s left" if 0 < frac < 1 else ""
        return f"{self.label} [{bar}] {self.done:g}/{self.total:g}{unit} {frac:4.0%} ({elapsed:.1f} s{eta})"

    def close(self) -> None:
        if self.enabled and self._last_draw > -float("inf"):
            self.stream.write("\r\x1b[K")
            self.stream.flush()

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class ProgressObserver:
    """A session observer that shows the source time since `start` on a `Progress` bar (or,
    with `count=True`, the frames seen: for loops whose total is a number of frames)."""

    name = "progress"

    def __init__(self, progress: Progress, start: float = 0.0, *, count: bool = False):
        self.progress = progress
        self.start = start
        self.count = count
        self.frames = 0

    def on_frame(self, sf: Any) -> None:
        self.frames += 1
        self.progress.set(self.frames if self.count else sf.frame.time - self.start)

    def summary(self) -> dict[str, Any]:
        return {"done": self.progress.done, "total": self.progress.total, "frames": self.frames}
