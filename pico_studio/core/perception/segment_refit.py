"""From a segmenter's raw pieces to walls: refit, merge neighbours, filter, classify the ends.

One compiled loop (`finish_kernel`) over the pieces of a scan, shared by every segmenter.

Refit: closed-form (weighted) total least squares (orthogonal regression) per piece, from
prefix sums of w, wx, wy, wx^2, wxy, wy^2 over the points (so a piece costs O(1), whatever
its length):

    W = sum w,  centroid c = sum(w p) / W,  covariance S = [[sxx, sxy], [sxy, syy]] (weighted)
    direction theta = atan2(2 sxy, sxx - syy) / 2     (the eigenvector of the largest eigenvalue)
    rms residual = sqrt(lambda_min),  lambda_min = (sxx + syy)/2 - sqrt(((sxx - syy)/2)^2 + sxy^2)

Range weighting (Pfister et al. 2003, "Weighted line fitting algorithms for mobile robot map
building"; laser_line_extraction's LineFitter): a point at range r has noise sigma = sigma0 +
k r, so it weighs w = (sigma0 / sigma)^2 (normalised to at most 1, which keeps the prefix sums
well scaled); `weighted=False` gives every point w = 1, the plain fit. The line's covariance
comes from the same sums (Fisher information of the fit, points of known noise sigma_i):
with the normal angle alpha and distance rho of the line (Hessian form, rho >= 0) and t_c
the centroid's coordinate along the line,

    var(alpha) = sigma0^2 / (W lambda_max)      (W lambda_max = sum w t_i^2, spread along the line)
    var(rho)   = sigma0^2 / W + t_c^2 var(alpha),   cov(alpha, rho) = t_c var(alpha)

so a far, sparse, short wall gets a wide covariance. (With `weighted=False` it assumes
sigma0 for every point.)

A piece's end points shared with a neighbour (a corner of the scan) sit on the rounded tip
of that corner, so pieces of 5 points or more leave one point out at each end of the fit;
its end points are its first and last point projected onto the line (floating end points).

Merge (the *merge* of split-and-merge): neighbouring pieces of one cluster (sharing, or
nearly sharing, a vertex) whose refitted directions differ less than `merge_angle` (as
undirected lines, the difference wrapped to (-pi/2, pi/2]) become one piece, refitted.

Filter: fewer than `min_points + min_points_per_m * range` points (range: the distance of
the piece's midpoint from the robot), shorter than `min_length` or an rms above `max_rms`: dropped.

End kinds, decided before filtering so a dropped neighbour leaves a floating end:
0 floating; 1 joint (the next piece of the same cluster starts within 2 points: a corner
seen in this scan); 2 seen (a true free end: the cluster's end with the laser looking past
it, or one of the next `seen_points` points of the cluster past the end lies more than
`seen_margin` behind the piece's line, on the side away from the robot — a convex end such
as a door jamb seen at a grazing angle).
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel

END_FLOATING, END_JOINT, END_SEEN = 0, 1, 2


def _example() -> tuple:
    pts = np.array([[1.0, -0.2 + 0.05 * i] for i in range(9)] + [[1.0 - 0.05 * i, 0.25] for i in range(1, 9)])
    pieces = np.array([[0, 8], [8, 16]], dtype=np.int64)
    clusters = np.array([[0, 17]], dtype=np.int64)
    seen = np.zeros((1, 2), dtype=np.bool_)
    return pts, pieces, clusters, seen, 0.1, 4, 0.1, 0.03, 0.05, 3, 0.01, 0.005, True, 0.0


@kernel(_example)
def finish_kernel(
    pts: np.ndarray, pieces_in: np.ndarray, clusters: np.ndarray, end_seen: np.ndarray,
    merge_angle: float, min_points: int, min_length: float, max_rms: float,
    seen_margin: float, seen_points: int,
    sigma0: float = 0.01, sigma_per_m: float = 0.0, weighted: bool = False, min_points_per_m: float = 0.0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(segments (S, 4), pieces (S, 2), cluster (S,), end_kind (S, 2), rms (S,), covariance
    (S, 3): var(alpha), var(rho), cov(alpha, rho)) of the kept walls."""
    m = pts.shape[0]
    # pieces of at least two points, each with its cluster (the last cluster starting at or
    # before the piece's first point)
    pieces = np.empty((pieces_in.shape[0], 2), dtype=np.int64)
    cid = np.empty(pieces_in.shape[0], dtype=np.int64)
    s_n = 0
    k = 0
    for j in range(pieces_in.shape[0]):
        a, b = pieces_in[j, 0], pieces_in[j, 1]
        if b - a + 1 < 2:
            continue
        while k + 1 < clusters.shape[0] and clusters[k + 1, 0] <= a:
            k += 1
        while k > 0 and clusters[k, 0] > a:  # pieces come in scan order; guard anyway
            k -= 1
        pieces[s_n, 0], pieces[s_n, 1] = a, b
        cid[s_n] = k
        s_n += 1
    pieces = pieces[:s_n]
    cid = cid[:s_n]
    # running sums of w, wx, wy, wx^2, wxy, wy^2 (row 0 all zero); w = 1 unweighted
    pre = np.zeros((m + 1, 6))
    for i in range(m):
        x, y = pts[i, 0], pts[i, 1]
        w = 1.0
        if weighted:
            q = sigma0 / (sigma0 + sigma_per_m * math.hypot(x, y))
            w = q * q
        pre[i + 1, 0] = pre[i, 0] + w
        pre[i + 1, 1] = pre[i, 1] + w * x
        pre[i + 1, 2] = pre[i, 2] + w * y
        pre[i + 1, 3] = pre[i, 3] + w * x * x
        pre[i + 1, 4] = pre[i, 4] + w * x * y
        pre[i + 1, 5] = pre[i, 5] + w * y * y
    seg, theta, rms, cov = _refit(pts, pieces, pre, sigma0)
    # merge almost parallel neighbours of one cluster
    n_p = pieces.shape[0]
    if n_p > 1:
        first = np.empty(n_p, dtype=np.int64)  # the first piece of every merged group
        n_g = 1
        first[0] = 0
        for i in range(1, n_p):
            d = theta[i] - theta[i - 1]
            d = (d + math.pi / 2) % math.pi - math.pi / 2
            join = cid[i] == cid[i - 1] and pieces[i, 0] - pieces[i - 1, 1] <= 1 and abs(d) < merge_angle
            if not join:
                first[n_g] = i
                n_g += 1
        if n_g < n_p:
            merged = np.empty((n_g, 2), dtype=np.int64)
            mcid = np.empty(n_g, dtype=np.int64)
            for g in range(n_g):
                last = first[g + 1] - 1 if g + 1 < n_g else n_p - 1
                merged[g, 0], merged[g, 1] = pieces[first[g], 0], pieces[last, 1]
                mcid[g] = cid[first[g]]
            pieces, cid = merged, mcid
            n_p = n_g
            seg, theta, rms, cov = _refit(pts, pieces, pre, sigma0)
    keep = np.empty(n_p, dtype=np.bool_)
    for i in range(n_p):
        length = math.hypot(seg[i, 2] - seg[i, 0], seg[i, 3] - seg[i, 1])
        rng = math.hypot(0.5 * (seg[i, 0] + seg[i, 2]), 0.5 * (seg[i, 1] + seg[i, 3]))
        enough = pieces[i, 1] - pieces[i, 0] + 1 >= min_points + min_points_per_m * rng
        keep[i] = enough and length >= min_length and rms[i] <= max_rms
    # end kinds: joints between kept neighbours, then seen ends
    kind = np.zeros((n_p, 2), dtype=np.int64)
    for i in range(n_p - 1):
        if cid[i + 1] == cid[i] and pieces[i + 1, 0] - pieces[i, 1] <= 2 and keep[i + 1] and keep[i]:
            kind[i, 1] = END_JOINT
            kind[i + 1, 0] = END_JOINT
    for i in range(n_p):
        c = cid[i]
        if pieces[i, 0] == clusters[c, 0] and end_seen[c, 0]:
            kind[i, 0] = END_SEEN
        if pieces[i, 1] == clusters[c, 1] - 1 and end_seen[c, 1]:
            kind[i, 1] = END_SEEN
        # looked past an end: one of the next `seen_points` points of the cluster beyond it
        # lies more than `seen_margin` behind the line (away from the robot at the origin)
        dx, dy = seg[i, 2] - seg[i, 0], seg[i, 3] - seg[i, 1]
        norm = max(math.hypot(dx, dy), 1e-12)
        nx, ny = -dy / norm, dx / norm
        robot_side = np.sign(-(nx * seg[i, 0] + ny * seg[i, 1]))
        for end in range(2):
            if kind[i, end] == END_JOINT:
                continue
            for j in range(1, seen_points + 1):
                q = pieces[i, 0] - j if end == 0 else pieces[i, 1] + j
                if q < clusters[c, 0] or q >= clusters[c, 1]:
                    continue
                depth = (pts[q, 0] - seg[i, 0]) * nx
                depth += (pts[q, 1] - seg[i, 1]) * ny
                depth *= -robot_side
                if depth > seen_margin:
                    kind[i, end] = END_SEEN
                    break
    n_k = 0
    for i in range(n_p):
        n_k += keep[i]
    out_seg = np.empty((n_k, 4))
    out_pieces = np.empty((n_k, 2), dtype=np.int64)
    out_cid = np.empty(n_k, dtype=np.int64)
    out_kind = np.empty((n_k, 2), dtype=np.int64)
    out_rms = np.empty(n_k)
    out_cov = np.empty((n_k, 3))
    w = 0
    for i in range(n_p):
        if keep[i]:
            out_seg[w] = seg[i]
            out_pieces[w] = pieces[i]
            out_cid[w] = cid[i]
            out_kind[w] = kind[i]
            out_rms[w] = rms[i]
            out_cov[w] = cov[i]
            w += 1
    return out_seg, out_pieces, out_cid, out_kind, out_rms, out_cov


def _refit_example() -> tuple:
    pts = np.array([[1.0, 0.1 * i] for i in range(6)])
    return pts, np.array([[0, 5]], dtype=np.int64), prefix_sums(pts), 0.01


def prefix_sums(pts: np.ndarray) -> np.ndarray:
    """(M + 1, 6) running sums of 1, x, y, x^2, xy, y^2 (row 0 all zero), numpy."""
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


@kernel(_refit_example)
def _refit(
    pts: np.ndarray, pieces: np.ndarray, pre: np.ndarray, sigma0: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(Weighted) total-least-squares line of every piece, from the prefix sums `pre`:
    (segments (S, 4), direction (S,), rms (S,), covariance (S, 3) of (alpha, rho))."""
    n_p = pieces.shape[0]
    seg = np.empty((n_p, 4))
    theta = np.empty(n_p)
    rms = np.empty(n_p)
    cov = np.empty((n_p, 3))
    for i in range(n_p):
        s, e = pieces[i, 0], pieces[i, 1]
        fs, fe = (s + 1, e - 1) if e - s >= 4 else (s, e)  # leave out corner tips
        n = pre[fe + 1, 0] - pre[fs, 0]
        cx = (pre[fe + 1, 1] - pre[fs, 1]) / n
        cy = (pre[fe + 1, 2] - pre[fs, 2]) / n
        sxx = (pre[fe + 1, 3] - pre[fs, 3]) / n - cx * cx
        sxy = (pre[fe + 1, 4] - pre[fs, 4]) / n - cx * cy
        syy = (pre[fe + 1, 5] - pre[fs, 5]) / n - cy * cy
        th = 0.5 * math.atan2(2 * sxy, sxx - syy)
        h = (sxx - syy) / 2
        half = math.sqrt(h * h + sxy * sxy)
        lam_min = max((sxx + syy) / 2 - half, 0.0)
        dx, dy = math.cos(th), math.sin(th)
        t0 = (pts[s, 0] - cx) * dx + (pts[s, 1] - cy) * dy
        t1 = (pts[e, 0] - cx) * dx + (pts[e, 1] - cy) * dy
        seg[i, 0], seg[i, 1] = cx + t0 * dx, cy + t0 * dy
        seg[i, 2], seg[i, 3] = cx + t1 * dx, cy + t1 * dy
        theta[i] = th
        rms[i] = math.sqrt(lam_min)
        # covariance of the Hessian form (alpha, rho): normal (-dy, dx) flipped to rho >= 0
        nx, ny = -dy, dx
        if cx * nx + cy * ny < 0:
            nx, ny = -nx, -ny
        t_c = cx * (-ny) + cy * nx  # d rho / d alpha: the centroid along the line
        var_a = sigma0 * sigma0 / max(n * ((sxx + syy) / 2 + half), 1e-300)
        cov[i, 0] = var_a
        cov[i, 1] = sigma0 * sigma0 / n + t_c * t_c * var_a
        cov[i, 2] = t_c * var_a
    return seg, theta, rms, cov


def refit(pts: np.ndarray, pieces: np.ndarray, pre: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Total-least-squares lines through each piece's points: (segments, direction, rms)."""
    pts = np.ascontiguousarray(pts, dtype=np.float64)
    if pre is None:
        pre = prefix_sums(pts)
    seg, theta, rms, _ = _refit(pts, np.ascontiguousarray(pieces, dtype=np.int64), pre, 0.01)
    return seg, theta, rms
