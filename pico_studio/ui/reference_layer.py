"""The reference map of a replay with true poses, and the local map's agreement with it.

For a recording whose true poses are known (a CARMEN corrected log) the page draws the
building as the laser saw it from where the robot really was (`evaluation.ReferenceMap`: every
scan of the file cast from its true pose), in the truth frame the page already shows such a
replay in, and tells per frame how much of the local map lies on it: `local_map.agreement`
as `pico-studio run --json` reports it (`evaluation.AgreementObserver`), here for the frame
shown and for the frames perceived since the recording opened.

Building the reference takes a few seconds on the Intel log, so it runs once per recording
in a background thread; until it is done the layer is empty and the figures are absent.
No viser here.
"""

from __future__ import annotations

import logging
import math
import threading
from typing import Any

import numpy as np

from pico_studio.core.geometry import compose, invert, transform_segments
from pico_studio.evaluation.agreement import AgreementObserver, sample_segments
from pico_studio.evaluation.reference_map import ReferenceMap
from pico_studio.ui.clock import is_replay

log = logging.getLogger(__name__)


def build_reference(recording: Any) -> ReferenceMap:
    """Every scan of the recording cast from the newest true pose at its time."""
    ref = ReferenceMap()
    truth_t = np.array([p.time for p in recording.truth], dtype=float)
    for scan in recording.scans:
        j = int(np.searchsorted(truth_t, float(scan.timestamp) + 1e-9, side="right")) - 1
        if j < 0:
            continue
        pose = tuple(float(v) for v in recording.truth[j].pose)
        if all(math.isfinite(v) for v in pose):
            ref.add_scan(scan.points, pose)  # type: ignore[arg-type]
    ref.wall_points()  # builds the grid and its distance field here, off the page's thread
    return ref


class _Build:
    """One recording's reference map, built in a thread."""

    def __init__(self, recording: Any):
        self.recording = recording
        self.ref: ReferenceMap | None = None
        self.points = np.zeros((0, 2))
        self.done = threading.Event()
        threading.Thread(target=self._run, name="reference-map", daemon=True).start()

    def _run(self) -> None:
        try:
            ref = build_reference(self.recording)
            self.points, self.ref = ref.wall_points(), ref
        except Exception as e:  # a bad file must not take the page down: no layer, no figure
            log.warning("reference map failed: %s", e)
        finally:
            self.done.set()


_builds: dict[int, _Build] = {}  # id(recording) -> its build, kept while the recording lives


def _build_for(recording: Any) -> _Build:
    b = _builds.get(id(recording))
    if b is None or b.recording is not recording:
        _builds.clear()  # one recording open at a time
        b = _builds[id(recording)] = _Build(recording)
    return b


class ReferenceAgreement:
    """A replay's reference map (drawn) and the local map's agreement with it, per frame and
    over the frames judged since it was made (the studio makes one per reset)."""

    def __init__(self, source: Any):
        self._build = _build_for(source.recording)
        self.judge = AgreementObserver()  # its distance and sample step, as the CLI judges
        self._frames: dict[float, tuple[int, int]] = {}  # frame time -> (samples agreeing, samples)

    @staticmethod
    def applies(source: Any) -> bool:
        return is_replay(source) and bool(getattr(source, "has_truth", False))

    def ready(self, timeout: float | None = None) -> bool:
        return self._build.done.wait(timeout) and self._build.ref is not None

    def points(self) -> np.ndarray:
        """(K, 2) the occupied cells' centres, truth frame; empty until built."""
        return self._build.points

    def frame_agreement(self, frame: Any) -> float | None:
        """The share of the frame's local-map wall samples (placed with its true pose) within
        the judge's distance of the reference; remembered for the run figure."""
        ref, wm, truth = self._build.ref, frame.wm, frame.truth_pose
        if ref is None or wm is None or truth is None:
            return None
        map_t_zero = compose(tuple(map(float, truth)), invert(tuple(map(float, wm.pose))))
        walls = np.asarray(wm.local_map.walls, dtype=float).reshape(-1, 4)
        pts = sample_segments(transform_segments(walls, map_t_zero), self.judge.sample_step)
        if not len(pts):
            return None
        ok = int((ref.distance(pts) <= self.judge.distance).sum())
        self._frames[float(frame.time)] = (ok, len(pts))
        return ok / len(pts)

    def figures(self, frame: Any) -> dict[str, float]:
        """{"frame": the shown frame's agreement, "run": over every frame judged, "frames"}."""
        out: dict[str, float] = {}
        if frame is not None:
            a = self.frame_agreement(frame)
            if a is not None:
                out["frame"] = a
        if self._frames:
            ok, n = (sum(v) for v in zip(*self._frames.values(), strict=True))
            out["run"] = ok / n
            out["frames"] = len(self._frames)
        return out


def agreement_text(figures: dict[str, float]) -> str:
    """The Run tab's line: `local_map.agreement` for the frame shown and the run so far."""
    if not figures:
        return ""
    parts = []
    if "frame" in figures:
        parts.append(f"this frame {figures['frame']:.2f}")
    if "run" in figures:
        parts.append(f"run so far {figures['run']:.2f} ({int(figures['frames'])} frames)")
    return "**Reference map agreement** (local_map.agreement): " + " · ".join(parts)
