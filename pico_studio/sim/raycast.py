"""2D raycasting of a laser fan against line segments, one compiled loop.

The maths, in complex numbers (a point x + iy): seen from the sensor, a segment runs from z1
to z2 (sensor frame), d = z2 - z1. A beam at angle b has direction e^{ib}; its point t e^{ib}
is on the segment's line when Im(conj(t e^{ib} - z1) d) = 0, so

    t = Im(conj(z1) z2) / Im(e^{-ib} d)  = 1 / Im(e^{-ib} q),   q = d / Im(conj(z1) z2)

(cross(z1, z2) / cross(e^{ib}, d) in vector terms).

Only beams whose angle lies inside the angular span the segment subtends from the sensor can
hit it, and for those the hit is on the segment itself. So instead of testing every beam
against every segment (N x n), each segment visits only the beams inside its span (a segment
behind the sensor that crosses the +-pi cut: the two pieces either side of the cut), and
per (segment, beam) pair the work is one complex multiply and one reciprocal (no
trigonometry: e^{-ib} is precomputed per beam). The nearest hit per beam wins (NaN, a beam
along a segment's own line, never does; a tie goes to the later piece), a negative nearest
distance means no hit. `_cast` is that loop; the arithmetic is numpy's complex arithmetic
written out, so the ranges are the ones the vectorised version (repeat/arange/fmin.at)
gave.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel

Pose = tuple[float, float, float]
_EPS = 1e-9  # a beam exactly through an end point still hits


class Fan:
    """A fixed laser fan: beam i at `angle_min + i * increment` radians (sensor frame)."""

    def __init__(self, angle_min: float, increment: float, n: int):
        self.angle_min = float(angle_min)
        self.increment = float(increment)
        self.n = int(n)
        self.turn = np.exp(-1j * (self.angle_min + np.arange(self.n) * self.increment))  # e^{-ib}
        # +-pi and half a turn in beam-index units
        self._top = (math.pi - self.angle_min) / self.increment
        self._bottom = (-math.pi - self.angle_min) / self.increment
        self._half_turn = math.pi / self.increment
        self._hits: np.ndarray | None = None  # the segment each beam of the last cast hit

    def cast(self, segments: np.ndarray, pose: Pose = (0.0, 0.0, 0.0)) -> np.ndarray:
        """Distance along every beam of a sensor at `pose` to the nearest of `segments`
        (N, 4, same frame as the pose); inf where a beam hits nothing."""
        if len(segments) == 0:
            self._hits = np.full(self.n, -1)
            return np.full(self.n, np.inf)
        if segments.dtype != np.float64 or not segments.flags.c_contiguous:
            segments = np.ascontiguousarray(segments, dtype=np.float64)
        x, y, th = pose
        ranges, self._hits = _cast(segments, float(x), float(y), math.cos(th), math.sin(th), self.turn,
                                   self.angle_min, self.increment, self._top, self._bottom, self._half_turn)
        return ranges

    def last_hits(self, ranges: np.ndarray) -> np.ndarray:
        """For the latest `cast` (whose result was `ranges`): the index of the segment each
        beam hit, -1 where none (or where `ranges` is no longer finite)."""
        hits = np.full(self.n, -1) if self._hits is None else self._hits.copy()
        hits[~np.isfinite(ranges)] = -1
        return hits


def _cast_example() -> tuple:
    fan = Fan(-2.0, 4.0 / 9, 10)
    segs = np.array([[1.0, -1.0, 1.0, 1.0], [-1.0, 1.0, -1.0, -1.0]])
    return segs, 0.0, 0.0, 1.0, 0.0, fan.turn, fan.angle_min, fan.increment, fan._top, fan._bottom, fan._half_turn


@kernel(_cast_example)
def _cast(segments: np.ndarray, x: float, y: float, cos_th: float, sin_th: float, turn: np.ndarray,
          angle_min: float, increment: float, top: float, bottom: float, half_turn: float,
          ) -> tuple[np.ndarray, np.ndarray]:
    """(ranges (n,), hit segment (n,) or -1) of the fan `turn` (e^{-ib} per beam) from (x, y)."""
    n = turn.shape[0]
    ns = segments.shape[0]
    best = np.full(n, np.inf)
    hit = np.full(n, -1, dtype=np.int64)
    # 1. end points in the sensor frame, (z - position) e^{-i heading}, and q per segment
    zr = np.empty((ns, 2))
    zi = np.empty((ns, 2))
    qr = np.empty(ns)
    qi = np.empty(ns)
    for k in range(ns):
        for e in range(2):
            ar, ai = segments[k, 2 * e] - x, segments[k, 2 * e + 1] - y
            zr[k, e] = ar * cos_th - ai * -sin_th
            zi[k, e] = ar * -sin_th + ai * cos_th
        # q = (z2 - z1) / Im(conj(z1) z2); a zero cross divides as numpy's complex division
        # does (by +0)
        cross = zr[k, 0] * zi[k, 1] + -zi[k, 0] * zr[k, 1]
        den = cross if cross != 0.0 else 0.0
        qr[k] = (zr[k, 1] - zr[k, 0]) / den
        qi[k] = (zi[k, 1] - zi[k, 0]) / den
    # 2.-3. every piece's beams: first pieces, then second pieces (the order ties go by)
    for piece in range(2 * ns):
        k = piece % ns
        s0 = (math.atan2(zi[k, 0], zr[k, 0]) - angle_min) * (1.0 / increment)
        s1 = (math.atan2(zi[k, 1], zr[k, 1]) - angle_min) * (1.0 / increment)
        lo, hi = min(s0, s1), max(s0, s1)
        wrap = (hi - lo) > half_turn
        if piece < ns:
            start, stop = (hi, top) if wrap else (lo, hi)
        else:
            start, stop = (bottom, lo) if wrap else (top, bottom)
        i0 = max(math.ceil(start - _EPS), 0.0)
        count = int(max(min(math.floor(stop + _EPS) + 1.0, n) - i0, 0.0))
        # 4. the distance along each beam to the segment's line: 1 / Im(e^{-ib} q); 5. the
        # nearest per beam (NaN, a beam along the segment's own line, never wins; a tie: the
        # later piece)
        for b in range(int(i0), int(i0) + count):
            t = 1.0 / (turn[b].real * qi[k] + turn[b].imag * qr[k])
            if t <= best[b]:
                best[b] = t
                hit[b] = k
    for b in range(n):
        if best[b] < 0.0:
            best[b] = np.inf
        if not best[b] < np.inf:
            hit[b] = -1
    return best, hit
