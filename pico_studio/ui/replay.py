"""Playing a recording scan by scan, and jumping anywhere in it with the world model built
up to that frame. No viser here.

Playing: `ReplayDriver.play(wall_dt, speed)` delivers *every* scan in order (one `Studio.tick`
per scan, its dt the time to that scan), paced at `speed` x the recording's clock or as fast
as it computes (`speed = inf`, for at most `budget_s` of wall time per call).

Seeking: the perceptor's and localiser's state before every `every`-th frame is kept as it
goes by (a checkpoint, with the config it was computed with). `seek(k)` restores the nearest
checkpoint at or before k made with the current perception and localisation parameters (else
the nearest made with any, else the start), puts the file there and re-processes the scans
from it to k. Since playing also reads each scan with the newest odometry at its time, a
frame reached by seeking gets the world model it gets by playing from the checkpoint.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

from pico_studio.ui.clock import recording_position
from pico_studio.ui.runtime import Studio
from pico_studio.ui.timeline import FrameRecord

CHECKPOINT_EVERY = 10  # frames; a jump re-processes at most this many (~5 ms each)
BUDGET_S = 0.05  # wall time per `play` call at speed "max"


@dataclass
class Checkpoint:
    params: Any  # (perception, localisation) parameters the state was computed with
    state: Any  # Studio.state before the frame


class ReplayDriver:
    def __init__(self, studio: Studio, every: int = CHECKPOINT_EVERY):
        self.studio = studio
        self.every = max(1, int(every))
        self.checkpoints: dict[int, Checkpoint] = {}
        self.last_seek: dict[str, Any] = {}  # what the last seek re-processed (for the page and the bench)
        self._target: float | None = None  # the recording time playing should have reached
        self._source = studio.source

    def params(self) -> Any:
        cfg = self.studio.cfg
        return (cfg.perception, cfg.localisation)

    # ----- playing ----------------------------------------------------------------------
    def step(self) -> FrameRecord | None:
        """Read, perceive and show the next scan of the file (None at its end)."""
        s = self.studio
        with s.lock:
            source = s.source
            if not source.ok():
                s.playing = False
                return None
            nxt = source.frame_index + 1
            dt = max(float(source.frame_times[nxt]) - source.now(), 0.0) if nxt < source.frame_count else 0.0
            frame = s.tick(dt)
            if frame is not None:
                self.note(frame)
            return frame

    def play(self, wall_dt: float, speed: float, budget_s: float = BUDGET_S) -> int:
        """Deliver the scans due after `wall_dt` seconds at `speed`; returns how many."""
        s = self.studio
        source = s.source
        if not source.ok():  # the end of the file: paused there, and the page says so
            s.playing = False
            return 0
        end = time.monotonic() + budget_s
        n = 0
        if math.isinf(speed):
            while s.playing and source.ok() and time.monotonic() < end:
                n += self.step() is not None
            self._target = None
            return n
        if self._target is None or self._target < source.now():
            self._target = source.now()
        self._target += wall_dt * speed
        while s.playing and source.ok() and n < 200 and time.monotonic() < end + wall_dt:
            nxt = source.frame_index + 1
            if nxt >= source.frame_count or float(source.frame_times[nxt]) > self._target:
                break
            n += self.step() is not None
        return n

    def note(self, frame: FrameRecord) -> None:
        """Keep the state before this frame when it is a checkpoint frame."""
        self._check_source()
        k = recording_position(self.studio.source, frame.time)
        if k % self.every == 0 and frame.state_before is not None:
            self.checkpoints[k] = Checkpoint(self.params(), frame.state_before)

    # ----- seeking ----------------------------------------------------------------------
    def seek(self, k: int) -> FrameRecord | None:
        """Show frame k of the file with the world model built up to it (paused)."""
        s = self.studio
        t0 = time.perf_counter()
        with s.lock:
            source = s.source
            k = min(max(int(k), 0), source.frame_count - 1)
            start, state, exact = self._start_for(k)
            s.playing = False
            s.cursor = None
            s.timeline.clear()
            s.state = state
            source.seek(start)
            frame = None
            for _ in range(start, k + 1):
                frame = self.step()
                if frame is None:
                    break
            s.playing = False
            self._target = None
        self.last_seek = {"frame": k, "from": start, "frames": k - start + 1, "current_params": exact,
                          "ms": (time.perf_counter() - t0) * 1000.0}
        return frame

    def _start_for(self, k: int) -> tuple[int, Any, bool]:
        """(frame to start from, the state before it, whether made with the current params).
        Without a checkpoint made with the current params: from the start when that is near,
        else from the nearest older-params checkpoint (fast; `last_seek["current_params"]` is then False)."""
        self._check_source()
        params = self.params()
        same = [i for i, c in self.checkpoints.items() if i <= k and c.params == params]
        if same:
            i = max(same)
            return i, self.checkpoints[i].state, True
        older = [i for i in self.checkpoints if i <= k]
        if k > 4 * self.every and older:
            i = max(older)
            return i, self.checkpoints[i].state, False
        return 0, self.studio.initial_state(), True

    def _check_source(self) -> None:
        if self.studio.source is not self._source:
            self.forget()
            self._source = self.studio.source

    def forget(self) -> None:
        """The source was reopened (reset, map change): its checkpoints are gone too."""
        self.checkpoints.clear()
        self._target = None
