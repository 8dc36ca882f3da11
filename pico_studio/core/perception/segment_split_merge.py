"""Split-and-merge / iterative end-point fit (seed 003), vectorised over the whole scan.

Seed 003's recursion: draw a chord from a cluster's first to its last point; split at the
point farthest from the chord when that distance exceeds `split_distance`; repeat on both
halves until every piece is within the threshold. Here every level of that recursion runs for
all pieces of all clusters at once:

    piece k spans points [s_k, e_k];  d_i = |(b - a) x (p_i - a)| / |b - a|  with a = p[s_k], b = p[e_k]
    split piece k at argmax_i d_i  when  max_i d_i > split_distance

so the cost is a few numpy passes per level (about log2 of the points per wall), not a
Python call per piece (`split_numpy`). That recursion is Douglas-Peucker polyline
simplification, which OpenCV runs in C++ (`cv2.approxPolyDP`, open curves): `split` uses it
per cluster, three times faster, and recovers the vertices' indices by matching their exact
float32 coordinates; the two agree (tests/test_perception_scan.py). The *merge* half
(joining neighbours that turn out collinear after the least-squares refit) is shared by
every segmenter, in segment.py.
"""

from __future__ import annotations

import cv2
import numpy as np

from pico_studio.config.perception_params import SplitMergeParams

MAX_LEVELS = 64  # a safety bound: each level at least halves... or splits off one point


def split(points: np.ndarray, clusters: np.ndarray, params: SplitMergeParams) -> np.ndarray:
    """(S, 2) int: inclusive [first, last] point index of every piece, in scan order."""
    pts32 = np.ascontiguousarray(points, dtype=np.float32)
    keys = pts32.view(np.complex64).ravel()  # one exact key per point: its float32 (x, y)
    chains: list[np.ndarray] = []  # per cluster, its vertices' point indices in order
    for a, b in clusters.tolist():
        if b - a < 2:
            continue
        v = cv2.approxPolyDP(pts32[a:b].reshape(-1, 1, 2), params.split_distance, False)
        # the vertices are copies of input points: find them by their exact coordinates (a
        # broadcast compare: a handful of vertices against a cluster's points)
        vk = v.reshape(-1, 2).view(np.complex64).ravel()
        idx = np.flatnonzero((keys[a:b, None] == vk[None, :]).any(axis=1))
        if len(idx) != len(vk):  # duplicate points: do this cluster the numpy way
            pieces = split_numpy(points, np.array([[a, b]]), params)
            idx = np.append(pieces[:, 0], pieces[-1, 1]) - a
        chains.append(idx + a)
    if not chains:
        return np.zeros((0, 2), dtype=np.int64)
    # consecutive vertices of one chain are a piece; a chain's last vertex starts none
    verts = np.concatenate(chains).astype(np.int64)
    starts_piece = np.ones(len(verts), dtype=bool)
    starts_piece[np.cumsum([len(c) for c in chains]) - 1] = False
    return np.column_stack([verts[:-1], verts[1:]])[starts_piece[:-1]]


def split_numpy(points: np.ndarray, clusters: np.ndarray, params: SplitMergeParams) -> np.ndarray:
    """The same split, every level of the recursion vectorised over all pieces."""
    if len(clusters) == 0:
        return np.zeros((0, 2), dtype=np.int64)
    m = len(points)
    # vertices: sorted point indices where pieces start/end; `is_end[k]` marks a cluster's last
    # point, after which no piece continues
    starts = clusters[:, 0].astype(np.int64)
    lasts = clusters[:, 1].astype(np.int64) - 1
    ok = lasts > starts
    pieces = np.column_stack([starts[ok], lasts[ok]])
    if len(pieces) == 0:
        return np.zeros((0, 2), dtype=np.int64)
    idx = np.arange(m)
    for _ in range(MAX_LEVELS):
        s, e = pieces[:, 0], pieces[:, 1]
        # every point's piece: the last piece starting at or before it (points between
        # clusters' pieces belong to none: filtered by `inside`)
        k = np.searchsorted(s, idx, side="right") - 1
        inside = (k >= 0) & (idx <= e[np.maximum(k, 0)])
        k = np.maximum(k, 0)
        a = points[s[k]]
        b = points[e[k]]
        ab = b - a
        norm = np.hypot(ab[:, 0], ab[:, 1])
        cross = np.abs(ab[:, 0] * (points[:, 1] - a[:, 1]) - ab[:, 1] * (points[:, 0] - a[:, 0]))
        d = np.where(norm > 1e-12, cross / np.maximum(norm, 1e-12), np.hypot(*(points - a).T))
        d = np.where(inside, d, -1.0)
        dmax = np.full(len(pieces), -1.0)
        np.maximum.at(dmax, k[inside], d[inside])
        splitting = dmax > params.split_distance
        if not splitting.any():
            break
        # the first point reaching its piece's maximum is where that piece splits
        hit = inside & (d == dmax[k]) & splitting[k]
        hk, first = np.unique(k[hit], return_index=True)
        at = idx[hit][first]
        new_left = np.column_stack([s[hk], at])
        new_right = np.column_stack([at, e[hk]])
        keep = pieces[~splitting]
        pieces = np.vstack([keep, new_left, new_right])
        pieces = pieces[np.lexsort((pieces[:, 1], pieces[:, 0]))]
    return pieces
