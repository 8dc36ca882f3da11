"""A gap (a candidate door, P to Q) tested against the local map's walls: is it blocked? A
Python wrapper over identify_kernels' compiled loop (the kernels call that loop directly)."""

from __future__ import annotations

import numpy as np

from pico_studio.core.perception.identify_kernels import blocked_many


def gaps_blocked(segs: np.ndarray, walls: np.ndarray, own_a: np.ndarray, own_b: np.ndarray) -> np.ndarray:
    """(G,) bool: does a wall other than the gap's own two cross the middle 80% of the gap?
    (The loop and its maths: identify_kernels.blocked_many.)"""
    if len(segs) == 0:
        return np.zeros(0, dtype=bool)
    return blocked_many(np.ascontiguousarray(segs, dtype=float), np.ascontiguousarray(walls, dtype=float),
                        np.ascontiguousarray(own_a, dtype=np.int64), np.ascontiguousarray(own_b, dtype=np.int64))
