"""Run a session over a whole replay, frame by frame, and report what was read and perceived.

`pico-studio run --source bag:FILE|carmen:FILE` uses this: every scan of the file goes
through the perceptor once (the loop steps from frame to frame instead of by a fixed dt,
so no scan is dropped), and the report gives frames read and the perceptor's figures per
frame (walls, corners, doors; stage timings), plus the truth where the file has it.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Iterator
from typing import Any

import numpy as np

from pico_studio.progress import Progress, ProgressObserver
from pico_studio.sources.replay import Replay


def frame_steps(replay: Replay) -> Iterator[float]:
    """The `dt` of each tick that meets every frame of `replay` once, from where it is."""
    while replay.ok():
        i = replay.frame_index
        yield 0.0 if i < 0 else max(float(replay.frame_times[i + 1]) - replay.now(), 0.0)


def run_replay(
    session: Any,
    replay: Replay,
    *,
    dt: float | None = None,
    seconds: float | None = None,
    progress: Progress | None = None,
) -> dict[str, Any]:
    """Tick `session` (whose source is `replay`) to the end of the file, or for `seconds`
    of recording time; the report.

    `dt=None` meets every frame; a number ticks at that period instead, dropping scans the
    way a loop of that rate would on the robot.
    """
    steps: Iterator[float] = frame_steps(replay) if dt is None else _fixed(replay, dt)
    until = None if seconds is None else replay.now() + seconds
    figures = ReplayFigures()
    watch = ProgressObserver(progress, replay.time_span[0]) if progress is not None else None
    ticks = 0
    for sf in session.frames(until=until, steps=steps):
        ticks += 1
        figures.on_frame(sf)
        if watch is not None:
            watch.on_frame(sf)
    report = replay.summary()
    report.update(
        ticks=ticks,
        frames_read=figures.frames,
        frames_dropped=replay.scans_dropped,
        perceptor=figures.summary() if figures.models else None,
    )
    return report


def _fixed(replay: Replay, dt: float) -> Iterator[float]:
    while replay.ok():
        yield dt


class ReplayFigures:
    """Per-frame counts from the world models, summarised as median / max (an observer of
    the frames with a new scan; no truth needed, the true path length when there is one)."""

    name = "perceptor"

    COUNTS = {
        "current_map_segments": lambda wm: len(wm.current_map),
        "local_map_walls": lambda wm: len(wm.local_map.walls),
        "corners": lambda wm: len(wm.corners),
        "convex_corners": lambda wm: int(np.sum(wm.corner_convex)),
        "doors": lambda wm: len(wm.doors),
        "possible_doors": lambda wm: len(wm.possible_doors),
        "valid_beams": lambda wm: int(np.sum(wm.beam_valid)),
        # how well the walls fit their points: the frame's median wall rms, in mm (none without walls)
        "current_map_rms_mm": lambda wm: 1000 * float(np.median(wm.current_map_rms)) if len(wm.current_map_rms) else None,
    }

    def __init__(self) -> None:
        self.frames = 0
        self.models = 0
        self.values: dict[str, list[float]] = {k: [] for k in self.COUNTS}
        self.step_ms: list[float] = []
        self.warnings = 0
        self.too_close = 0
        self.truth_path = 0.0
        self._last_truth: tuple[float, float, float] | None = None

    def on_frame(self, sf: Any) -> None:
        if sf.frame.laser is not None:
            self.add(sf.world_model, (sf.frame.truth or {}).get("pose"))

    def add(self, wm: Any, truth: tuple[float, float, float] | None) -> None:
        self.frames += 1
        if truth is not None:
            if self._last_truth is not None:
                self.truth_path += math.hypot(truth[0] - self._last_truth[0], truth[1] - self._last_truth[1])
            self._last_truth = truth
        if wm is None:
            return
        self.models += 1
        for name, count in self.COUNTS.items():
            try:
                value = count(wm)
            except AttributeError:
                continue
            if value is not None:
                self.values[name].append(float(value))
        timings = getattr(wm, "timings_ms", {}) or {}
        self.step_ms.append(float(sum(timings.values())))
        self.warnings += len(getattr(wm, "warnings", []) or [])
        self.too_close += bool(getattr(wm, "too_close", False))

    def summary(self) -> dict[str, Any]:
        out: dict[str, Any] = {"frames_perceived": self.models}
        for name, values in self.values.items():
            if values:
                out[name] = {"median": statistics.median(values), "max": max(values)}
        if self.step_ms:
            out["step_ms_median"] = round(statistics.median(self.step_ms), 3)
        out["frames_too_close"] = self.too_close
        out["world_model_warnings"] = self.warnings
        if self._last_truth is not None:
            out["truth_path_m"] = round(self.truth_path, 3)
        return out
