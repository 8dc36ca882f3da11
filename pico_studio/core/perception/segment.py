"""From clusters of points to walls: run the chosen segmenter, refit, merge neighbours, filter.

Segmenters are found by name in `SEGMENTERS` (`perception.scan.segmenter`); every one has the
shape `Segmenter`: the scan's resampled points (M, 2) in beam order, its clusters (C, 2) as
half-open point ranges [start, end), and the perception params (each reads its own section),
returning pieces (S, 2) as inclusive point-index ranges [first, last] in cluster order, never
crossing a cluster. `register_segmenter` adds one (a plugin's). Each piece is then refitted
by closed-form total least squares, neighbouring pieces of one cluster that turn out almost
parallel are merged (the *merge* of split-and-merge), pieces with too few points, too short,
or too far from straight are dropped, and each end gets its kind: 0 floating (occluded or at
the edge of the view), 1 joint (shared with the neighbouring wall of the same cluster: a
corner seen in this scan), 2 seen (a true free end: the laser looked past it). The maths and
the compiled loop are in segment_refit.py. The result is the current map.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from pico_studio.config.perception_params import SEGMENTER_NAMES, PerceptionParams
from pico_studio.core.perception import (
    segment_angle,
    segment_ransac,
    segment_refit,
    segment_split_merge,
)
from pico_studio.core.perception.scan import ScanPoints
from pico_studio.core.perception.segment_refit import END_FLOATING, END_JOINT, END_SEEN, refit  # noqa: F401
from pico_studio.errors import ConfigError


@dataclass(frozen=True)
class Segments:
    segments: np.ndarray  # (S, 4) robot frame
    index: np.ndarray  # (S, 2) inclusive point range
    cluster: np.ndarray  # (S,) cluster id
    end_kind: np.ndarray  # (S, 2) int, END_*
    rms: np.ndarray  # (S,)
    covariance: np.ndarray  # (S, 3) of the line's (alpha, rho): var(alpha), var(rho), cov(alpha, rho)

    @staticmethod
    def empty() -> Segments:
        return Segments(np.zeros((0, 4)), np.zeros((0, 2), dtype=np.int64), np.zeros(0, dtype=np.int64),
                        np.zeros((0, 2), dtype=np.int64), np.zeros(0), np.zeros((0, 3)))


Segmenter = Callable[[np.ndarray, np.ndarray, PerceptionParams], np.ndarray]
"""(points (M, 2), clusters (C, 2) [start, end), params) -> pieces (S, 2) [first, last]."""

SEGMENTERS: dict[str, Segmenter] = {}


def register_segmenter(name: str, fn: Segmenter, *, replace: bool = False) -> None:
    """Make `fn` selectable as `perception.scan.segmenter: <name>`."""
    if name in SEGMENTERS and not replace:
        raise ValueError(f"a segmenter named {name!r} is already registered")
    SEGMENTERS[name] = fn
    SEGMENTER_NAMES.add(name)  # the config's choice list: YAML and sliders accept it now


def unregister_segmenter(name: str) -> None:
    """Forget a registered segmenter (a plugin unloaded); the built-ins stay."""
    if name not in SEGMENTER_NAMES.builtin:
        SEGMENTERS.pop(name, None)
        SEGMENTER_NAMES.remove(name)


# the built-in three, each handed its own params section
register_segmenter("split_merge", lambda pts, cl, p: segment_split_merge.split(pts, cl, p.split_merge))
register_segmenter("angle", lambda pts, cl, p: segment_angle.cluster(pts, cl, p.angle))
register_segmenter("ransac", lambda pts, cl, p: segment_ransac.extract(pts, cl, p.ransac))


def run_segmenter(scan: ScanPoints, params: PerceptionParams) -> np.ndarray:
    """Raw pieces (S, 2) from the configured segmenter."""
    name = params.scan.segmenter
    fn = SEGMENTERS.get(name)
    if fn is None:
        raise ConfigError(f"unknown segmenter {name!r}; one of: {', '.join(SEGMENTERS)}",
                          field="perception.scan.segmenter")
    return np.asarray(fn(scan.points, scan.clusters, params), dtype=np.int64).reshape(-1, 2)


def segment_scan(scan: ScanPoints, params: PerceptionParams) -> Segments:
    pieces = run_segmenter(scan, params)
    return finish_pieces(scan, pieces, params)


def finish_pieces(scan: ScanPoints, pieces: np.ndarray, params: PerceptionParams) -> Segments:
    """Refit, merge collinear neighbours, filter, and classify the ends of raw pieces
    (one compiled loop: segment_refit.finish_kernel)."""
    p = params.scan
    if len(pieces) == 0 or len(scan.points) == 0:
        return Segments.empty()
    out = segment_refit.finish_kernel(
        np.ascontiguousarray(scan.points, dtype=np.float64), np.ascontiguousarray(pieces, dtype=np.int64),
        np.ascontiguousarray(scan.clusters, dtype=np.int64), np.ascontiguousarray(scan.end_seen, dtype=np.bool_),
        float(p.merge_angle), int(p.min_points), float(p.min_length), float(p.max_rms),
        float(p.seen_margin), int(p.seen_points), float(p.range_sigma0), float(p.range_sigma_per_m),
        bool(p.weighted_fit), float(p.min_points_per_m))
    return Segments(*out)
