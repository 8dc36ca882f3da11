"""An installed pico_studio plugin: a segmenter that keeps every cluster whole as one piece."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pico_studio.plugins import param, segmenter


@dataclass(frozen=True)
class WholeParams:
    min_points: int = param(3, lo=2, hi=50, step=1, help="Clusters with fewer points give no piece")


@segmenter("whole_cluster", WholeParams, help="Installed example: one piece per cluster")
def whole_cluster(points: np.ndarray, params: WholeParams) -> list[tuple[int, int]]:
    return [(0, len(points) - 1)] if len(points) >= params.min_points else []
