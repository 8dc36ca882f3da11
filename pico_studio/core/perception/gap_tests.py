"""Tests of a gap (a candidate door, P to Q) against the local map's walls: is it blocked, and
where do rays first meet a wall. Python wrappers over identify_kernels' compiled loops, shared by
identify and the map-proven candidates (map_proven)."""

from __future__ import annotations

import numpy as np

from pico_studio.core.perception.identify_kernels import blocked_many, ray_hits


def gaps_blocked(segs: np.ndarray, walls: np.ndarray, own_a: np.ndarray, own_b: np.ndarray) -> np.ndarray:
    """(G,) bool: does a wall other than the gap's own two cross the middle 80% of the gap?
    (The loop and its maths: identify_kernels.blocked_many.)"""
    if len(segs) == 0:
        return np.zeros(0, dtype=bool)
    return blocked_many(np.ascontiguousarray(segs, dtype=float), np.ascontiguousarray(walls, dtype=float),
                        np.ascontiguousarray(own_a, dtype=np.int64), np.ascontiguousarray(own_b, dtype=np.int64))


def nearest_hits(origin: np.ndarray, direction: np.ndarray, walls: np.ndarray,
                 exclude: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Nearest wall hit (distance, index; inf/-1 for none) of rays (R, 2) + t (R, 2); `exclude`:
    per ray two wall indices not to hit. (The loop and its maths: identify_kernels.ray_hits.)"""
    r = len(origin)
    ex_a, ex_b = exclude if exclude is not None else (np.full(r, -1), np.full(r, -1))
    return ray_hits(np.ascontiguousarray(origin, dtype=float), np.ascontiguousarray(direction, dtype=float),
                    np.ascontiguousarray(walls, dtype=float), np.ascontiguousarray(ex_a, dtype=np.int64),
                    np.ascontiguousarray(ex_b, dtype=np.int64))
