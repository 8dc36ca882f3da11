"""`local_map.agreement`: how much of the local map lies where the building really is.

For a replay whose true poses are known (a CARMEN corrected log, a recorded simulation):

    agreement = (local-map wall length within `distance` of the reference map)
                / (local-map wall length)

The local map is sampled every `sample_step` along its walls and placed in the truth frame
with the frame's true pose (map_T_zero = truth_pose (x) wm.pose^-1, as the scoring does), so
it measures the map the perceptor built, drift included: a local map that drifted from
where the robot is draws ghost walls off the reference. The reference map
(`reference_map.ReferenceMap`) is built from *every* scan of the run cast from its true
pose, so it is complete only at the end: the samples are kept (every `every`-th scan) and
judged in `summary()`.

The observer plugs into a session: `on_frame(session_frame)` after every tick, `summary()`
at the end.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pico_studio.core.geometry import compose, invert, transform_segments
from pico_studio.evaluation.reference_map import ReferenceMap


def sample_segments(segments: np.ndarray, step: float) -> np.ndarray:
    """(N, 2) points every `step` along each segment (its middle for a short one)."""
    if len(segments) == 0:
        return np.zeros((0, 2))
    a, b = segments[:, 0:2], segments[:, 2:4]
    length = np.hypot(*(b - a).T)
    n = np.maximum(np.round(length / step).astype(np.int64), 1)
    seg_of = np.repeat(np.arange(len(segments)), n)
    k = np.arange(len(seg_of)) - np.repeat(np.cumsum(n) - n, n)
    t = (k + 0.5) / n[seg_of]
    return a[seg_of] + t[:, None] * (b - a)[seg_of]


@dataclass
class AgreementObserver:
    """Session observer: collects scans and local maps, scores them once the run is over."""

    distance: float = 0.1  # m: a local-map sample this close to a reference wall agrees
    sample_step: float = 0.05  # m between samples along the local map's walls
    every: int = 5  # judge the local map of every this many scans (every scan feeds the reference)
    reference: ReferenceMap = field(default_factory=ReferenceMap)
    name: str = "local_map"  # the key of its summary in Session.summaries()

    def __post_init__(self) -> None:
        self._samples: list[np.ndarray] = []
        self._per_frame: list[tuple[int, int]] = []  # (first sample, count) per judged frame
        self._scans = 0
        self._count = 0

    def on_frame(self, sf: Any) -> None:
        frame, wm = sf.frame, sf.world_model
        truth = (frame.truth or {}).get("pose") if isinstance(frame.truth, dict) else None
        if frame.laser is None or truth is None or wm is None:
            return
        truth = tuple(float(v) for v in truth)
        if not all(math.isfinite(v) for v in truth):
            return
        self.reference.add_scan(np.asarray(wm.points), truth)
        self._scans += 1
        if (self._scans - 1) % self.every:
            return
        map_t_zero = compose(truth, invert(tuple(wm.pose)))
        pts = sample_segments(transform_segments(np.asarray(wm.local_map.walls).reshape(-1, 4), map_t_zero),
                              self.sample_step)
        self._per_frame.append((self._count, len(pts)))
        self._samples.append(pts.astype(np.float32))
        self._count += len(pts)

    def summary(self) -> dict[str, Any]:
        """{"agreement": share of sampled wall length near the reference, "scans", "frames_judged",
        "wall_m": local-map wall length judged (summed over frames), "worst_frame": lowest
        per-frame agreement}. Agreement is 1.0 (nothing to disagree with) without samples."""
        pts = np.vstack(self._samples) if self._samples else np.zeros((0, 2))
        ok = self.reference.distance(pts) <= self.distance if len(pts) else np.zeros(0, bool)
        per = [float(ok[s : s + n].mean()) for s, n in self._per_frame if n]
        return {
            "agreement": float(ok.mean()) if len(ok) else 1.0,
            "scans": self._scans,
            "frames_judged": len(self._per_frame),
            "wall_m": float(len(pts) * self.sample_step),
            "worst_frame": min(per) if per else 1.0,
        }
