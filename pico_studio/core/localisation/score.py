"""Localisation scored against a known true pose (the simulator's, or a corrected log's).

Pure bookkeeping, no simulator import: feed (estimate, truth, lost) per frame, read the
summary. Frames without an estimate count as lost and are left out of the error figures.

    score = PoseScore()
    score.add(wm.global_pose, sim.truth.pose, wm.lost)
    score.summary()   # {"pose_error_m": {"median", "max"}, "heading_error_rad": {...}, ...}
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pico_studio.core.geometry import wrap_angle

Pose = tuple[float, float, float]


@dataclass
class PoseScore:
    position: list[float] = field(default_factory=list)  # metres, frames with an estimate
    heading: list[float] = field(default_factory=list)  # radians, absolute
    lost: list[bool] = field(default_factory=list)  # every frame

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
