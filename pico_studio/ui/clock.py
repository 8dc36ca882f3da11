"""Times and frame numbers as the page shows them: relative to the start of the run or of
the recording (a bag's clock is epoch seconds), and a replay's frames numbered by their
place in the whole file. No viser here."""

from __future__ import annotations

from typing import Any

import numpy as np


def is_replay(source: Any) -> bool:
    """A recording played back (it has a fixed number of frames and can seek)."""
    return bool(getattr(source, "frame_count", 0)) and callable(getattr(source, "seek", None))


def start_time(source: Any) -> float:
    """Where the page's clock starts: the recording's first stamp, else 0 (the simulator's
    and the live robot's clocks are shown as they are)."""
    if is_replay(source):
        return float(source.time_span[0])
    return 0.0


def relative_time(source: Any, t: float) -> float:
    return float(t) - start_time(source)


def recording_position(source: Any, t: float) -> int:
    """The frame of the recording whose stamp `t` is (the last one at or before it)."""
    times = np.asarray(source.frame_times, dtype=float)
    i = int(np.searchsorted(times, t + 1e-9, side="right")) - 1
    return min(max(i, 0), len(times) - 1)


def frame_number(studio: Any, frame: Any) -> int:
    """A frame's number on the page: its place in the recording for a replay, else its
    running index since the last reset."""
    if is_replay(studio.source):
        return recording_position(studio.source, frame.time)
    return int(frame.index)
