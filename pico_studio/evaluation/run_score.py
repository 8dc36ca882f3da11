"""A run's scores as running sums, and the session observers that keep them.

- `RunScore`: the perception figures of many frames (`FrameScore` sums added as they come;
  `summary()` is a ratio of sums, so every metre of wall and every door weighs the same).
- `PoseScore`: localisation against a known true pose (the simulator's, a corrected log's):
  feed (estimate, truth, lost) per frame; frames without an estimate count as lost and are
  left out of the error figures.
- `TruthScorer` / `PoseErrorScorer`: the two as observers of `Session.frames`.

    session = Session(sim, perceptor=p, observers=[TruthScorer(sim), PoseErrorScorer()])
    session.run(30.0)
    scorer.summary()   # {"wall_precision": ..., "door_recall": ..., "ms_per_scan": ...}
    pose.summary()     # {"pose_error_m": {"median", "max"}, "heading_error_rad": {...}, ...}
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import fields
from typing import Any

import numpy as np

from pico_studio.core.geometry import wrap_angle
from pico_studio.evaluation.frame_score import (
    FrameScore,
    Pose,
    Tolerances,
    as_pose,
    score_frame,
    static_vertices,
    true_zero_from,
    true_zero_pose,
)

_FIELDS = tuple(f.name for f in fields(FrameScore))


class RunScore:
    """The sum of every added `FrameScore`, the newest one, and the perceptor's times."""

    def __init__(self, frames: Iterable[FrameScore] = ()):
        self.total = FrameScore()
        self.count = 0
        self.last: FrameScore | None = None
        self.ms_per_scan: list[float] = []
        for f in frames:
            self.add(f)

    def add(self, frame: FrameScore) -> None:
        total, more = vars(self.total), vars(frame)  # field by field (its __dict__: no getattr/setattr per field)
        for name in _FIELDS:
            total[name] += more[name]
        self.count += 1
        self.last = frame

    def summary(self) -> dict[str, Any]:
        return summarise(self.total, self.count, self.ms_per_scan)


def summarise(t: FrameScore, n: int, ms_per_scan: list[float] | None = None) -> dict[str, Any]:
    """The figures of the sums `t` over `n` frames (the keys `eval --json` prints)."""
    k = max(n, 1)
    return {
        "frames": n,
        "wall_precision": _ratio(t.wall_len_ok, t.wall_len),
        "wall_recall": _ratio(t.truth_len_ok, t.truth_len),
        "endpoint_error_m": _ratio(t.endpoint_err_sum, t.endpoints, empty=0.0),
        "corner_precision": _ratio(t.corners_ok, t.corners),
        "corner_recall": _ratio(t.truth_corners_ok, t.truth_corners),
        "convexity_accuracy": _ratio(t.convexity_ok, t.corners_paired),
        "door_precision": _ratio(t.doors_ok, t.doors),
        "door_recall": _ratio(t.truth_doors_ok, t.truth_doors),
        "doors_detected": t.doors,
        "doors_visible": t.truth_doors,
        "pose_error_m": t.pose_err_m / k,
        "pose_error_rad": t.pose_err_rad / k,
        "ms_per_scan": float(np.median(ms_per_scan)) if ms_per_scan else 0.0,
        **({"map_door_precision": _ratio(t.map_doors_ok, t.map_doors),
            "map_door_recall": _ratio(t.map_truth_doors_ok, t.truth_doors),
            "map_doors_detected": t.map_doors} if t.map_frames else {}),
    }


def _ratio(num: float, den: float, empty: float = 1.0) -> float:
    """num / den; with nothing to count, `empty` (nothing claimed is nothing wrong)."""
    return float(num / den) if den > 0 else empty


class PoseScore:
    def __init__(self) -> None:
        self.position: list[float] = []  # metres, frames with an estimate
        self.heading: list[float] = []  # radians, absolute
        self.lost: list[bool] = []  # every frame

    def add(self, estimate: Pose | None, truth: Pose, lost: bool) -> None:
        self.lost.append(bool(lost) or estimate is None)
        if estimate is None:
            return
        self.position.append(math.hypot(estimate[0] - truth[0], estimate[1] - truth[1]))
        self.heading.append(abs(float(wrap_angle(estimate[2] - truth[2]))))

    def summary(self) -> dict[str, Any]:
        def stats(values: list[float]) -> dict[str, float | None]:
            if not values:
                return {"median": None, "max": None}
            return {"median": float(np.median(values)), "max": float(np.max(values))}

        return {
            "pose_error_m": stats(self.position),
            "heading_error_rad": stats(self.heading),
            "lost_fraction": float(np.mean(self.lost)) if self.lost else None,
            "frames": len(self.lost),
        }


def summary_line(s: dict[str, Any]) -> str:
    """One line of a `PoseScore.summary()` for the CLI."""
    p, h = s["pose_error_m"], s["heading_error_rad"]
    if p["median"] is None:
        return f"never found the robot ({s['frames']} frames, lost throughout)"
    return (f"error median {p['median']:.3f} m / {math.degrees(h['median']):.2f} deg, "
            f"max {p['max']:.3f} m / {math.degrees(h['max']):.2f} deg; "
            f"lost {100 * s['lost_fraction']:.0f} % of {s['frames']} frames")


class TruthScorer:
    """Scores every `every`-th new world model against the simulator's truth.

    `source`: the `Simulator` (its `truth`; the perceptor's zero frame is placed by the
    odometry, `true_zero_pose`), or a callable giving the truth object now: a kept one
    (`kept_truth.TruthSnapshot`, placed by the odometry likewise) or any other (the zero
    frame is then the true pose of the first scored frame). `vertices`: the static corners for the
    end-point error (default: the simulator's, or the corners in view). `run`: a `RunScore`
    to add to (several scorers may share one). `last_only`: score only the last world model,
    when `finish()` (or `summary()`) is called — the eval method's way."""

    name = "perceptor"

    def __init__(self, source: Any, *, tol: Tolerances | None = None, every: int = 1,
                 vertices: np.ndarray | None = None, run: RunScore | None = None, last_only: bool = False):
        self.sim = source if hasattr(source, "truth") else None
        self.truth: Callable[[], Any] = (lambda: source.truth) if self.sim is not None else source
        self.tol = tol or Tolerances()
        self.every = max(int(every), 1)
        self.vertices = vertices if vertices is not None or self.sim is None else static_vertices(self.sim)
        self.run = run if run is not None else RunScore()
        self.last_only = last_only
        self.scans = 0
        self.true_zero: Pose | None = None
        self._last_wm: Any = None

    def on_frame(self, sf: Any) -> None:
        wm = sf.world_model
        if wm is None or wm is self._last_wm:
            return
        self._last_wm = wm
        self.run.ms_per_scan.append(float(getattr(wm, "timings_ms", {}).get("total", 0.0)))
        if not self.last_only and self.scans % self.every == 0:
            self.run.add(self.score(wm))
        self.scans += 1

    def finish(self) -> None:
        """With `last_only`: score the last world model (once)."""
        if self.last_only and self._last_wm is not None:
            self.run.add(self.score(self._last_wm))
            self._last_wm = None

    def score(self, wm: Any) -> FrameScore:
        """Score `wm` against the truth now, without adding it to the run."""
        truth = self.truth()
        if self.sim is not None:
            zero = true_zero_pose(wm, self.sim)
        elif hasattr(truth, "odometry_form"):
            zero = true_zero_from(wm, truth, truth.odometry_form)
        else:
            if self.true_zero is None:
                self.true_zero = as_pose(truth.pose)
            zero = self.true_zero
        return score_frame(wm, truth, self.tol, true_zero=zero, true_vertices=self.vertices)

    def summary(self) -> dict[str, Any]:
        self.finish()
        return self.run.summary()


class PoseErrorScorer:
    """The localised pose (`wm.global_pose`, `wm.lost`) of every frame with a new scan against
    the true pose: `truth()` when given, else the frame's recorded truth {"pose": ...}."""

    name = "localisation"

    def __init__(self, truth: Callable[[], Pose | None] | None = None, *, score: PoseScore | None = None):
        self.truth = truth
        self.score = score if score is not None else PoseScore()

    def on_frame(self, sf: Any) -> None:
        wm = sf.world_model
        if sf.frame.laser is None or wm is None or not hasattr(wm, "global_pose"):
            return
        true = self.truth() if self.truth is not None else (sf.frame.truth or {}).get("pose")
        if true is None:
            return
        self.score.add(wm.global_pose, as_pose(true), wm.lost)

    def summary(self) -> dict[str, Any]:
        return self.score.summary()
