"""From clusters of points to walls: run the chosen segmenter, then refit, merge, filter.

Every segmenter returns pieces as inclusive point-index ranges [first, last]. Each piece is
then refitted by closed-form total least squares, neighbouring pieces of one cluster that
turn out almost parallel are merged (the *merge* of split-and-merge), pieces with too few
points, too short, or too far from straight are dropped, and each end gets its kind:
0 floating (occluded or at the edge of the view), 1 joint (shared with the neighbouring wall
of the same cluster: a corner seen in this scan), 2 seen (a true free end: the laser looked
past it). The maths and the compiled loop are in segment_refit.py. The result is the
current map.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pico_studio.config.perception_params import PerceptionParams
from pico_studio.core.perception import (
    segment_angle,
    segment_ransac,
    segment_refit,
    segment_split_merge,
)
from pico_studio.core.perception.scan import ScanPoints
from pico_studio.core.perception.segment_refit import END_FLOATING, END_JOINT, END_SEEN, refit  # noqa: F401


@dataclass(frozen=True)
class Segments:
    segments: np.ndarray  # (S, 4) robot frame
    index: np.ndarray  # (S, 2) inclusive point range
    cluster: np.ndarray  # (S,) cluster id
    end_kind: np.ndarray  # (S, 2) int, END_*
    rms: np.ndarray  # (S,)

    @staticmethod
    def empty() -> Segments:
        return Segments(np.zeros((0, 4)), np.zeros((0, 2), dtype=np.int64), np.zeros(0, dtype=np.int64),
                        np.zeros((0, 2), dtype=np.int64), np.zeros(0))


def run_segmenter(scan: ScanPoints, params: PerceptionParams) -> np.ndarray:
    """Raw pieces (S, 2) from the configured segmenter."""
    name = params.scan.segmenter
    if name == "angle":
        return segment_angle.cluster(scan.points, scan.clusters, params.angle)
    if name == "ransac":
        return segment_ransac.extract(scan.points, scan.clusters, params.ransac)
    return segment_split_merge.split(scan.points, scan.clusters, params.split_merge)


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
        float(p.seen_margin), int(p.seen_points))
    return Segments(*out)
