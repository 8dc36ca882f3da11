"""From clusters of points to walls: run the chosen segmenter, refit, merge neighbours, filter.

Segmenters are found by name in `SEGMENTERS` (`perception.scan.segmenter`); every one has the
shape `Segmenter`: the scan's resampled points (M, 2) in beam order, its clusters (C, 2) as
half-open point ranges [start, end), and the perception params (each reads its own section),
returning pieces (S, 2) as inclusive point-index ranges [first, last] in cluster order, never
crossing a cluster. `register_segmenter` adds one (a plugin's). Each piece is
then refitted by closed-form total least squares (orthogonal regression), for all pieces at
once from prefix sums of x, y, x^2, xy, y^2:

    centroid c = mean(p),  covariance S = [[sxx, sxy], [sxy, syy]]
    direction theta = atan2(2 sxy, sxx - syy) / 2     (the eigenvector of the largest eigenvalue)
    rms residual = sqrt(lambda_min),  lambda_min = (sxx + syy)/2 - sqrt(((sxx - syy)/2)^2 + sxy^2)

and its end points are its first and last point projected onto that line (floating end
points). Neighbouring pieces of one cluster whose refitted directions differ less than
`merge_angle` are merged and refitted (the *merge* of split-and-merge). Pieces with too few
points, too short, or too far from straight are dropped. The result is the current map.

End kinds (per segment end): 0 floating (occluded or at the edge of the view), 1 joint
(shared with the neighbouring wall of the same cluster: a corner seen in this scan), 2 seen
(a true free end: the laser looked past it).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from pico_studio.config.perception_params import SEGMENTER_NAMES, PerceptionParams
from pico_studio.core.geometry import segment_lengths
from pico_studio.core.perception import segment_angle, segment_ransac, segment_split_merge
from pico_studio.core.perception.scan import ScanPoints
from pico_studio.errors import ConfigError

END_FLOATING, END_JOINT, END_SEEN = 0, 1, 2


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
    """Refit, merge collinear neighbours, filter, and classify the ends of raw pieces."""
    p = params.scan
    pts = scan.points
    if len(pieces) == 0 or len(pts) == 0:
        return Segments.empty()
    pieces = pieces[(pieces[:, 1] - pieces[:, 0] + 1) >= 2]
    cid = np.searchsorted(scan.clusters[:, 0], pieces[:, 0], side="right") - 1
    pre = _prefix(pts)
    seg, theta, rms = refit(pts, pieces, pre)
    # merge: neighbours in one cluster, sharing (or nearly sharing) a vertex, almost parallel
    if len(pieces) > 1:
        adjacent = (cid[1:] == cid[:-1]) & (pieces[1:, 0] - pieces[:-1, 1] <= 1)
        dtheta = np.abs(_wrap_half(theta[1:] - theta[:-1]))
        join = adjacent & (dtheta < p.merge_angle)
        if join.any():
            group = np.concatenate([[0], np.cumsum(~join)])
            first = np.flatnonzero(np.concatenate([[True], ~join]))
            last = np.concatenate([first[1:], [len(pieces)]]) - 1
            pieces = np.column_stack([pieces[first, 0], pieces[last, 1]])
            cid = cid[first]
            del group
            seg, theta, rms = refit(pts, pieces, pre)
    n = pieces[:, 1] - pieces[:, 0] + 1
    length = segment_lengths(seg)
    keep = (n >= p.min_points) & (length >= p.min_length) & (rms <= p.max_rms)
    # end kinds, decided before filtering so a dropped neighbour leaves a floating end
    kind = np.zeros((len(pieces), 2), dtype=np.int64)
    if len(pieces) > 1:
        joint = (cid[1:] == cid[:-1]) & (pieces[1:, 0] - pieces[:-1, 1] <= 2) & keep[1:] & keep[:-1]
        kind[:-1, 1] = np.where(joint, END_JOINT, kind[:-1, 1])
        kind[1:, 0] = np.where(joint, END_JOINT, kind[1:, 0])
    c_first = scan.clusters[cid, 0]
    c_last = scan.clusters[cid, 1] - 1
    seen0 = (pieces[:, 0] == c_first) & scan.end_seen[cid, 0]
    seen1 = (pieces[:, 1] == c_last) & scan.end_seen[cid, 1]
    kind[:, 0] = np.where(seen0, END_SEEN, kind[:, 0])
    kind[:, 1] = np.where(seen1, END_SEEN, kind[:, 1])
    behind0, behind1 = _looked_past(pts, pieces, seg, scan.clusters[cid], p.seen_margin, p.seen_points)
    kind[:, 0] = np.where((kind[:, 0] != END_JOINT) & behind0, END_SEEN, kind[:, 0])
    kind[:, 1] = np.where((kind[:, 1] != END_JOINT) & behind1, END_SEEN, kind[:, 1])
    return Segments(seg[keep], pieces[keep], cid[keep], kind[keep], rms[keep])


def _looked_past(
    pts: np.ndarray, pieces: np.ndarray, seg: np.ndarray, clusters: np.ndarray, margin: float, k: int
) -> tuple[np.ndarray, np.ndarray]:
    """Per piece end: does one of the next `k` points of its cluster past that end lie more
    than `margin` behind the piece's line (on the side away from the robot)? Then the laser
    looked past the end — a convex end, e.g. a jamb whose end cap is seen at a grazing angle.
    A point in front of the line is a concave corner or an occluder: not seen."""
    d = seg[:, 2:4] - seg[:, 0:2]
    n = np.column_stack([-d[:, 1], d[:, 0]]) / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-12)[:, None]
    # robot (origin) side of each line: sign of n . (0 - a)
    robot_side = np.sign(-(n * seg[:, 0:2]).sum(axis=1))
    # both ends at once: idx[p, end, j] is the j-th point past that end of piece p
    off = np.arange(1, k + 1)
    idx = np.empty((len(pieces), 2, k), dtype=np.int64)
    idx[:, 0, :] = pieces[:, 0:1] - off
    idx[:, 1, :] = pieces[:, 1:2] + off
    inside = (idx >= clusters[:, 0, None, None]) & (idx < clusters[:, 1, None, None])
    q = pts[np.clip(idx, 0, len(pts) - 1)]
    depth = (q[..., 0] - seg[:, 0, None, None]) * n[:, 0, None, None]
    depth += (q[..., 1] - seg[:, 1, None, None]) * n[:, 1, None, None]
    depth *= -robot_side[:, None, None]
    hit = (inside & (depth > margin)).any(axis=2)
    return hit[:, 0], hit[:, 1]


def _wrap_half(a: np.ndarray) -> np.ndarray:
    """Wrap a difference of undirected line angles to (-pi/2, pi/2]."""
    return (a + np.pi / 2) % np.pi - np.pi / 2


def _prefix(pts: np.ndarray) -> np.ndarray:
    """(M + 1, 6) running sums of 1, x, y, x^2, xy, y^2 (row 0 all zero)."""
    x, y = pts[:, 0], pts[:, 1]
    mom = np.empty((len(pts) + 1, 6))
    mom[0] = 0.0
    mom[1:, 0] = 1.0
    mom[1:, 1] = x
    mom[1:, 2] = y
    np.multiply(x, x, out=mom[1:, 3])
    np.multiply(x, y, out=mom[1:, 4])
    np.multiply(y, y, out=mom[1:, 5])
    return np.cumsum(mom, axis=0, out=mom)


def refit(pts: np.ndarray, pieces: np.ndarray, pre: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Total-least-squares lines through each piece's points: (segments, direction, rms).

    A piece's end points shared with a neighbour (a corner of the scan) sit on the rounded
    tip of that corner, so pieces long enough leave one point out at each end of the fit; the
    end points are still the projections of the piece's first and last point."""
    if pre is None:
        pre = _prefix(pts)
    s, e = pieces[:, 0], pieces[:, 1]
    long = (e - s) >= 4
    fs = np.where(long, s + 1, s)
    fe = np.where(long, e - 1, e)
    m = pre[fe + 1] - pre[fs]
    n = m[:, 0]
    cx, cy = m[:, 1] / n, m[:, 2] / n
    sxx = m[:, 3] / n - cx * cx
    sxy = m[:, 4] / n - cx * cy
    syy = m[:, 5] / n - cy * cy
    theta = 0.5 * np.arctan2(2 * sxy, sxx - syy)
    half = np.sqrt(((sxx - syy) / 2) ** 2 + sxy**2)
    lam_min = np.maximum((sxx + syy) / 2 - half, 0.0)
    dx, dy = np.cos(theta), np.sin(theta)
    p0, p1 = pts[s], pts[e]
    t0 = (p0[:, 0] - cx) * dx + (p0[:, 1] - cy) * dy
    t1 = (p1[:, 0] - cx) * dx + (p1[:, 1] - cy) * dy
    seg = np.column_stack([cx + t0 * dx, cy + t0 * dy, cx + t1 * dx, cy + t1 * dy])
    return seg, theta, np.sqrt(lam_min)
