"""Vectorised 2D raycasting of a laser fan against line segments.

The maths, for a beam from the origin with direction (c, s) = (cos b, sin b) and a segment
P1 -> P2 with d = P2 - P1 (all in the sensor frame): the beam point t (c, s) lies on the
segment's line when cross(t (c, s) - P1, d) = 0, so

    t = cross(P1, d) / cross((c, s), d) = (x1 y2 - y1 x2) / (c dy - s dx).

Only beams whose angle lies inside the angular span the segment subtends from the origin can
hit it, and for those the hit is on the segment itself. So instead of testing every beam
against every segment (N x n), each segment contributes only the index range of beams inside
its span; all (segment, beam) pairs are built at once with `repeat`/`arange` and the nearest
hit per beam is a `minimum.at`. A room seen from inside gives roughly 2-4 pairs per beam.
"""

from __future__ import annotations

import math

import numpy as np


class Fan:
    """A fixed laser fan: beam i at `angle_min + i * increment` radians (sensor frame)."""

    def __init__(self, angle_min: float, increment: float, n: int):
        self.angle_min = float(angle_min)
        self.increment = float(increment)
        self.n = int(n)
        angles = self.angle_min + np.arange(self.n) * self.increment
        self.cos = np.cos(angles)
        self.sin = np.sin(angles)

    def _index_ranges(self, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """First and one-past-last beam index with angle in [lo, hi], clipped to the fan."""
        eps = 1e-9  # a beam exactly through an end point still hits
        i0 = np.ceil((lo - self.angle_min) / self.increment - eps).astype(np.int64)
        i1 = np.floor((hi - self.angle_min) / self.increment + eps).astype(np.int64) + 1
        return np.clip(i0, 0, self.n), np.clip(i1, 0, self.n)

    def pairs(self, segments: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(segment index, beam index) of every beam inside some segment's angular span."""
        a1 = np.arctan2(segments[:, 1], segments[:, 0])
        a2 = np.arctan2(segments[:, 3], segments[:, 2])
        lo = np.minimum(a1, a2)
        hi = np.maximum(a1, a2)
        # A segment behind the sensor spans the +-pi cut: its span is [hi, pi] + [-pi, lo].
        wrap = hi - lo > math.pi
        start = np.where(wrap, hi, lo)
        stop = np.where(wrap, math.pi, hi)
        seg_ids = np.arange(len(segments))
        if wrap.any():
            start = np.concatenate([start, np.full(int(wrap.sum()), -math.pi)])
            stop = np.concatenate([stop, lo[wrap]])
            seg_ids = np.concatenate([seg_ids, seg_ids[wrap]])
        i0, i1 = self._index_ranges(start, stop)
        counts = np.maximum(i1 - i0, 0)
        total = int(counts.sum())
        seg = np.repeat(seg_ids, counts)
        first = np.cumsum(counts) - counts  # where each piece starts in the flat pair list
        beam = np.arange(total) - np.repeat(first - i0, counts)
        return seg, beam

    def cast(self, segments: np.ndarray, *, with_hits: bool = False) -> tuple[np.ndarray, np.ndarray | None]:
        """Distance along every beam to the nearest segment (inf where none), and optionally
        the index of the segment hit (-1 where none). `segments` (N, 4) in the sensor frame."""
        ranges = np.full(self.n, np.inf)
        if len(segments) == 0:
            return ranges, (np.full(self.n, -1) if with_hits else None)
        seg, beam = self.pairs(segments)
        x1, y1, x2, y2 = segments.T
        num = x1 * y2 - y1 * x2
        dx = x2 - x1
        dy = y2 - y1
        with np.errstate(divide="ignore", invalid="ignore"):
            t = num[seg] / (self.cos[beam] * dy[seg] - self.sin[beam] * dx[seg])
        t[~(t >= 0.0)] = np.inf  # parallel (nan/inf) or behind
        np.minimum.at(ranges, beam, t)
        hits = None
        if with_hits:
            hits = np.full(self.n, -1)
            nearest = (t == ranges[beam]) & np.isfinite(t)
            hits[beam[nearest]] = seg[nearest]
        return ranges, hits


def cast_rays(origin: tuple[float, float], angles: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """Distance along rays from `origin` at arbitrary map-frame `angles` to the nearest of
    `segments` (map frame), inf where none: the plain (K x N) test, for a few rays."""
    angles = np.asarray(angles, dtype=float)
    if len(segments) == 0:
        return np.full(angles.shape, np.inf)
    c = np.cos(angles)[:, None]
    s = np.sin(angles)[:, None]
    p1 = segments[None, :, 0:2] - np.asarray(origin)
    d = segments[None, :, 2:4] - segments[None, :, 0:2]
    with np.errstate(divide="ignore", invalid="ignore"):
        den = c * d[..., 1] - s * d[..., 0]
        t = (p1[..., 0] * d[..., 1] - p1[..., 1] * d[..., 0]) / den
        # where along the segment the ray crosses: cross(p1, (c, s)) / den
        u = (p1[..., 0] * s - p1[..., 1] * c) / den
    ok = (t >= 0.0) & (u >= 0.0) & (u <= 1.0)
    return np.where(ok, t, np.inf).min(axis=1)
