"""Split-and-merge / iterative end-point fit (seed 003): Douglas-Peucker per cluster, compiled.

Seed 003's recursion: draw a chord from a cluster's first to its last point; split at the
point farthest from the chord when that distance exceeds `split_distance`; repeat on both
halves until every piece is within the threshold:

    piece [s, e], chord a = p[s], b = p[e], L^2 = |b - a|^2
    d_i^2 L^2 = ((b - a) x (p_i - a))^2          (the point's foot falls on the chord)
              = |p_i - a|^2 L^2 or |p_i - b|^2 L^2  (it falls before a / past b)
    split at the first i with the largest d_i^2 L^2  when  max > split_distance^2 L^2

That recursion is Douglas-Peucker polyline simplification. `split` runs it as one compiled
loop over all clusters (`_douglas_peucker`, an explicit stack, left half first, so vertices
come out in scan order) with the arithmetic of OpenCV's `cv2.approxPolyDP` (float32 points,
float64 products, the same tie rule and its final pass that drops a vertex lying within
split_distance / sqrt(2) of the chord of its neighbours when that chord is not axis-aligned),
so it returns the very vertices the earlier production path (`split_opencv`) found, without
matching coordinates back to indices. `split_numpy` is the same recursion vectorised over
all pieces at once (float64, no final pass), kept as the readable cross-check. The *merge*
half (joining neighbours that turn out collinear after the least-squares refit) is shared
by every segmenter, in segment.py.
"""

from __future__ import annotations

import cv2
import numpy as np

from pico_studio.config.perception_params import SplitMergeParams
from pico_studio.jit import kernel

MAX_LEVELS = 64  # a safety bound: each level at least halves... or splits off one point


def _example() -> tuple:
    pts = np.array([[1.0, 0.0], [1.0, 0.5], [1.0, 1.0], [0.5, 1.0], [0.0, 1.0]], dtype=np.float32)
    return pts, np.array([[0, 5]], dtype=np.int64), 0.02


@kernel(_example)
def _douglas_peucker(pts: np.ndarray, clusters: np.ndarray, eps: float) -> np.ndarray:
    """(S, 2) int64 pieces [first, last] of every cluster [start, end) of float32 `pts`."""
    m = pts.shape[0]
    eps2 = eps * eps
    out = np.empty((max(m, 1), 2), dtype=np.int64)
    n_out = 0
    verts = np.empty(m + 1, dtype=np.int64)  # one cluster's vertices, in scan order
    stack = np.empty((m + 1, 2), dtype=np.int64)
    for k in range(clusters.shape[0]):
        c0, c1 = clusters[k, 0], clusters[k, 1]
        if c1 - c0 < 2:
            continue
        # 1. the recursion, as a stack of pieces; the left half is popped first
        nv = 0
        stack[0, 0], stack[0, 1] = c0, c1 - 1
        top = 1
        while top > 0:
            top -= 1
            s, e = stack[top, 0], stack[top, 1]
            if e - s < 2:
                verts[nv] = s
                nv += 1
                continue
            ax, ay = pts[s, 0], pts[s, 1]
            bx, by = pts[e, 0], pts[e, 1]
            dx = np.float64(bx - ax)
            dy = np.float64(by - ay)
            len2 = dx * dx + dy * dy
            scale = len2 if len2 > 0.0 else 1.0  # a zero chord (a = b): plain distance to a
            best = 0.0
            at = s
            for i in range(s + 1, e):
                px, py = pts[i, 0] - ax, pts[i, 1] - ay  # float32, as OpenCV
                proj = px * dx + py * dy
                if len2 == 0.0 or proj < 0.0:  # before a (or a zero chord): distance to a
                    d2 = np.float64(px * px + py * py) * scale
                elif proj > len2:  # past b: distance to b
                    qx, qy = pts[i, 0] - bx, pts[i, 1] - by
                    d2 = np.float64(qx * qx + qy * qy) * len2
                else:
                    cross = py * dx - px * dy
                    d2 = cross * cross
                if d2 > best:
                    best = d2
                    at = i
            if best <= eps2 * scale:
                verts[nv] = s
                nv += 1
            else:
                stack[top, 0], stack[top, 1] = at, e  # right half, popped second
                stack[top + 1, 0], stack[top + 1, 1] = s, at
                top += 2
        verts[nv] = c1 - 1
        nv += 1
        # 2. OpenCV's final pass: drop a vertex within eps / sqrt(2) of its neighbours' chord
        # (not axis-aligned, the vertex between them along it); the next one is then skipped
        count = nv
        kept = nv
        start = verts[0]
        mid = verts[1]
        w = 1
        r = 2
        i = 1
        while i < count - 1 and kept > 2:
            end = verts[r] if r < count else verts[0]
            r += 1
            dx = np.float64(pts[end, 0] - pts[start, 0])
            dy = np.float64(pts[end, 1] - pts[start, 1])
            ux, uy = pts[mid, 0] - pts[start, 0], pts[mid, 1] - pts[start, 1]
            dist = abs(ux * dy - uy * dx)
            inner = np.float64(ux * (pts[end, 0] - pts[mid, 0]) + uy * (pts[end, 1] - pts[mid, 1]))
            if dist * dist <= 0.5 * eps2 * (dx * dx + dy * dy) and dx != 0.0 and dy != 0.0 and inner >= 0.0:
                kept -= 1
                verts[w] = end
                start = end
                w += 1
                mid = verts[r] if r < count else verts[0]
                r += 1
                i += 2
                continue
            verts[w] = mid
            start = mid
            w += 1
            mid = end
            i += 1
        verts[w] = mid  # w <= i < count: the last vertex
        # 3. consecutive vertices are the cluster's pieces
        for j in range(kept - 1):
            out[n_out, 0] = verts[j]
            out[n_out, 1] = verts[j + 1]
            n_out += 1
    return out[:n_out].copy()


def split(points: np.ndarray, clusters: np.ndarray, params: SplitMergeParams) -> np.ndarray:
    """(S, 2) int: inclusive [first, last] point index of every piece, in scan order."""
    pts32 = np.ascontiguousarray(points, dtype=np.float32)
    return _douglas_peucker(pts32, np.ascontiguousarray(clusters, dtype=np.int64), float(params.split_distance))


def split_opencv(points: np.ndarray, clusters: np.ndarray, params: SplitMergeParams) -> np.ndarray:
    """The same split by `cv2.approxPolyDP` per cluster, vertices found back by their exact
    float32 coordinates (the production path before the compiled loop; the peer in tests and
    benchmarks)."""
    pts32 = np.ascontiguousarray(points, dtype=np.float32)
    keys = pts32.view(np.complex64).ravel()  # one exact key per point: its float32 (x, y)
    chains: list[np.ndarray] = []  # per cluster, its vertices' point indices in order
    for a, b in clusters.tolist():
        if b - a < 2:
            continue
        v = cv2.approxPolyDP(pts32[a:b].reshape(-1, 1, 2), params.split_distance, False)
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
