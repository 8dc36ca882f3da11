"""The matcher's compiled loops: distance-field lookups, Gauss-Newton refinement, beams
through walls. The maths is in matcher.py's and distance_field.py's docstrings; these are
the same algorithms as single loops over the points (numpy's per-call overhead on ~300
points is most of the cost otherwise).

Grid node (r, c) of a field sits at (x0 + c * res, y0 + r * res).
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel, njit


def _field_example() -> tuple:
    field = np.arange(16, dtype=np.float32).reshape(4, 4) * np.float32(0.01)
    return field, 0.0, 0.0, 0.1, np.array([[0.05, 0.12], [0.3, 0.31], [-1.0, 5.0]])


@njit
def _bilinear(field: np.ndarray, x0: float, y0: float, res: float, x: float, y: float) -> float:
    """Bilinear distance at (x, y); off the grid: the border value."""
    h, w = field.shape
    c = min(max((x - x0) / res, 0.0), w - 1.000001)
    r = min(max((y - y0) / res, 0.0), h - 1.000001)
    c0, r0 = int(c), int(r)
    fc, fr = c - c0, r - r0
    top = field[r0, c0] * (1 - fc) + field[r0, c0 + 1] * fc
    bottom = field[r0 + 1, c0] * (1 - fc) + field[r0 + 1, c0 + 1] * fc
    return top * (1 - fr) + bottom * fr


@njit
def _nearest(index: np.ndarray, x0: float, y0: float, res: float, x: float, y: float) -> int:
    """Index of the nearest segment at (x, y) (nearest node, ties to even); -1 off the grid."""
    h, w = index.shape
    c = int(np.rint((x - x0) / res))
    r = int(np.rint((y - y0) / res))
    if c < 0 or c >= w or r < 0 or r >= h:
        return -1
    return int(index[r, c])


@njit
def _nearest_exact(index: np.ndarray, segments: np.ndarray, x0: float, y0: float, res: float, x: float,
                   y: float) -> int:
    """Of the segments labelled at the four nodes around (x, y), the one really nearest (the
    point-to-segment distance); -1 off the grid. One node's label is the segment nearest to
    that node, up to res / sqrt(2) away from the point: within a wall a few cells thick, a point
    just behind its near face (range noise) takes the far face's label at the node past it,
    and its residual to that line (the wall's thickness) pulls the fit off the true pose."""
    h, w = index.shape
    c0 = int(math.floor((x - x0) / res))
    r0 = int(math.floor((y - y0) / res))
    best, best_d = -1, math.inf
    for dr in range(2):
        for dc in range(2):
            r, c = r0 + dr, c0 + dc
            if r < 0 or r >= h or c < 0 or c >= w:
                continue
            k = int(index[r, c])
            if k < 0 or k == best:
                continue
            ax, ay = segments[k, 0], segments[k, 1]
            bx, by = segments[k, 2] - ax, segments[k, 3] - ay
            t = min(max(((x - ax) * bx + (y - ay) * by) / max(bx * bx + by * by, 1e-24), 0.0), 1.0)
            d = math.hypot(x - ax - t * bx, y - ay - t * by)
            if d < best_d:
                best, best_d = k, d
    return best


@kernel(_field_example)
def field_distance(field: np.ndarray, x0: float, y0: float, res: float, points: np.ndarray) -> np.ndarray:
    """(N,) bilinear distance at every point (N, 2)."""
    out = np.empty(points.shape[0])
    for i in range(points.shape[0]):
        out[i] = _bilinear(field, x0, y0, res, points[i, 0], points[i, 1])
    return out


def _index_example() -> tuple:
    return np.zeros((4, 4), dtype=np.int32), 0.0, 0.0, 0.1, np.array([[0.05, 0.12], [-1.0, 5.0]])


@kernel(_index_example)
def field_nearest(index: np.ndarray, x0: float, y0: float, res: float, points: np.ndarray) -> np.ndarray:
    """(N,) int32 nearest segment at every point (N, 2); -1 off the grid."""
    out = np.empty(points.shape[0], dtype=np.int32)
    for i in range(points.shape[0]):
        out[i] = _nearest(index, x0, y0, res, points[i, 0], points[i, 1])
    return out


@njit
def _wrap(a: float) -> float:
    """math.remainder(a, 2 pi): fmod is exact, and so is the one subtraction (Sterbenz)."""
    two_pi = 2 * math.pi
    r = np.fmod(a, two_pi)
    if abs(r) > math.pi:
        r -= math.copysign(two_pi, r)
    return r


def _refine_example() -> tuple:
    field, x0, y0, res, _ = _field_example()
    index = np.zeros((4, 4), dtype=np.int32)
    segs = np.array([[0.0, 0.0, 0.3, 0.0]])
    normals = np.array([[0.0, 1.0]])
    pts = np.array([[0.1, 0.02], [0.2, 0.01], [0.15, 0.0], [0.05, 0.01]])
    return (field, index, x0, y0, res, segs, normals, pts, 0.0, 0.0, 0.0,
            4, 0.5, 0.1, 0.05, 0.05)


@kernel(_refine_example)
def refine_kernel(field: np.ndarray, index: np.ndarray, x0: float, y0: float, res: float,
                  segments: np.ndarray, normals: np.ndarray, pts: np.ndarray,
                  px: float, py: float, pa: float, iterations: int, outlier_distance: float,
                  final_outlier_distance: float, huber: float, inlier_distance: float,
                  ) -> tuple[float, float, float, int, bool, float]:
    """Gauss-Newton point-to-line alignment of `pts` from (px, py, pa), as matcher.refine:
    (x, y, a, points used in the last step, converged, constraint)."""
    x = np.array([px, py, pa])
    converged = False
    used = 0
    i00 = i01 = i11 = 0.0  # the last step's per-point x-y information
    n = pts.shape[0]
    for it in range(iterations):
        # 1. outlier distance shrinks linearly over the first half of the iterations
        f = min(1.0, it / max(1, iterations // 2))
        outlier = outlier_distance + f * (final_outlier_distance - outlier_distance)
        # 2.-3. every point into the map, its residual to its nearest segment's line, Huber
        # weights, summed straight into the normal equations H d = -g
        c, s = math.cos(x[2]), math.sin(x[2])
        h = np.zeros((3, 3))
        g = np.zeros(3)
        w_sum = 0.0
        used = 0
        for i in range(n):
            qx = pts[i, 0] * c + pts[i, 1] * -s + x[0]
            qy = pts[i, 0] * s + pts[i, 1] * c + x[1]
            k = _nearest_exact(index, segments, x0, y0, res, qx, qy)
            if k < 0:
                continue
            nx, ny = normals[k, 0], normals[k, 1]
            r = (qx - segments[k, 0]) * nx + (qy - segments[k, 1]) * ny
            # a point beyond the segment's ends is not on that line: the true distance too
            if abs(r) > outlier or _bilinear(field, x0, y0, res, qx, qy) > outlier:
                continue
            used += 1
            w = 1.0 if abs(r) <= huber else huber / max(abs(r), 1e-12)
            j0, j1 = nx, ny
            j2 = nx * -(qy - x[1]) + ny * (qx - x[0])
            h[0, 0] += w * j0 * j0
            h[0, 1] += w * j0 * j1
            h[0, 2] += w * j0 * j2
            h[1, 1] += w * j1 * j1
            h[1, 2] += w * j1 * j2
            h[2, 2] += w * j2 * j2
            g[0] += w * j0 * r
            g[1] += w * j1 * r
            g[2] += w * j2 * r
            w_sum += w
        if used < 3:
            break
        h[1, 0], h[2, 0], h[2, 1] = h[0, 1], h[0, 2], h[1, 2]
        i00, i01, i11 = h[0, 0] / w_sum, h[0, 1] / w_sum, h[1, 1] / w_sum
        for d in range(3):
            h[d, d] += 1e-9
        ok, dx = _solve3(h, -g)
        if not ok:
            break
        x += dx
        x[2] = _wrap(x[2])
        if it >= iterations // 2 and abs(dx[0]) + abs(dx[1]) < 1e-4 and abs(dx[2]) < 1e-4:
            converged = True
            break
    # how well the points pin down x and y: the smaller eigenvalue of the 2 x 2 information
    half = (i00 - i11) / 2
    constraint = (i00 + i11) / 2 - math.sqrt(half * half + i01 * i01)
    return x[0], x[1], x[2], used, converged, constraint


@njit
def _solve3(a: np.ndarray, b: np.ndarray) -> tuple[bool, np.ndarray]:
    """a x = b for a 3 x 3 `a` by LU with partial pivoting (as LAPACK's gesv); False if singular."""
    m = a.copy()
    v = b.copy()
    for col in range(3):
        p = col
        for r in range(col + 1, 3):
            if abs(m[r, col]) > abs(m[p, col]):
                p = r
        if m[p, col] == 0.0:
            return False, v
        if p != col:
            for k in range(3):
                m[col, k], m[p, k] = m[p, k], m[col, k]
            v[col], v[p] = v[p], v[col]
        for r in range(col + 1, 3):
            f = m[r, col] / m[col, col]
            for k in range(col, 3):
                m[r, k] -= f * m[col, k]
            v[r] -= f * v[col]
    out = np.empty(3)
    for r in range(2, -1, -1):
        acc = v[r]
        for k in range(r + 1, 3):
            acc -= m[r, k] * out[k]
        out[r] = acc / m[r, r]
    return True, out


def _quality_example() -> tuple:
    field, x0, y0, res, pts = _field_example()
    return field, x0, y0, res, pts, 0.1, 0.2, 0.3, 0.05


@kernel(_quality_example)
def quality_kernel(field: np.ndarray, x0: float, y0: float, res: float, pts: np.ndarray,
                   px: float, py: float, pa: float, inlier_distance: float) -> float:
    """Fraction of `pts` (robot frame) within `inlier_distance` of the map at (px, py, pa)."""
    if pts.shape[0] == 0:
        return 0.0
    c, s = math.cos(pa), math.sin(pa)
    hits = 0
    for i in range(pts.shape[0]):
        qx = pts[i, 0] * c + pts[i, 1] * -s + px
        qy = pts[i, 0] * s + pts[i, 1] * c + py
        hits += _bilinear(field, x0, y0, res, qx, qy) <= inlier_distance
    return hits / pts.shape[0]


def _through_example() -> tuple:
    field, x0, y0, res, _ = _field_example()
    index = np.zeros((4, 4), dtype=np.int32)
    segs = np.array([[0.0, 0.15, 0.3, 0.15]])
    return (index, x0, y0, res, segs, np.array([[0.0, 1.0]]), np.zeros(1, dtype=np.bool_),
            np.array([[0.3, 0.25], [0.1, 0.05]]), 0.05, 0.1, 0.05, 0.05, 0.0)


@kernel(_through_example)
def through_kernel(index: np.ndarray, x0: float, y0: float, res: float, segments: np.ndarray,
                   normals: np.ndarray, passable: np.ndarray, pts: np.ndarray,
                   step: float, clearance: float, px: float, py: float, pa: float) -> float:
    """Fraction of the beams to `pts` that cross a map wall before their end point, as
    matcher.beams_through_walls: samples every `step` along each beam up to `clearance`
    before its end; a crossing is a sign change of the signed distance to the same nearest
    (not passable) segment between two samples, at a point within that segment."""
    nb = pts.shape[0]
    if nb == 0:
        return 0.0
    r_max = 0.0
    for b in range(nb):
        r_max = max(r_max, math.hypot(pts[b, 0], pts[b, 1]))
    n_s = int(np.ceil(r_max / step))
    c, s = math.cos(pa), math.sin(pa)
    crossed = 0
    for b in range(nb):
        rng = math.hypot(pts[b, 0], pts[b, 1])
        last = max(rng - clearance, 0.0)
        norm = max(rng, 1e-9)
        dxr, dyr = pts[b, 0] / norm, pts[b, 1] / norm
        prev_k = -1
        prev_side = 0.0
        prev_x = prev_y = 0.0
        for t_i in range(1, n_s + 1):
            t = min(t_i * step, last)
            ex, ey = dxr * t, dyr * t
            qx = ex * c + ey * -s + px
            qy = ex * s + ey * c + py
            k = _nearest(index, x0, y0, res, qx, qy)
            kk = max(k, 0)
            side = (qx - segments[kk, 0]) * normals[kk, 0] + (qy - segments[kk, 1]) * normals[kk, 1]
            if t_i > 1 and t > 0.0 and k == prev_k and k >= 0 and not passable[k] \
                    and np.signbit(prev_side) != np.signbit(side):
                # where the beam crosses the line, and whether that is on the segment
                w = prev_side / (prev_side - side)
                cx = prev_x + w * (qx - prev_x)
                cy = prev_y + w * (qy - prev_y)
                ax, ay = segments[kk, 0], segments[kk, 1]
                abx, aby = segments[kk, 2] - ax, segments[kk, 3] - ay
                u = ((cx - ax) * abx + (cy - ay) * aby) / max(abx * abx + aby * aby, 1e-12)
                if 0.0 <= u <= 1.0:
                    crossed += 1
                    break
            prev_k, prev_side, prev_x, prev_y = k, side, qx, qy
    return crossed / nb


def _coarse_example() -> tuple:
    grid = np.ones((6, 6), dtype=np.float32)
    return grid, np.zeros((2, 3, 2), dtype=np.int64), 2, 2, 2, 2


@kernel(_coarse_example)
def coarse_scores(grid: np.ndarray, offsets: np.ndarray, r0: int, c0: int, ny: int, nx: int) -> np.ndarray:
    """(H, ny, nx) float32: per heading h and grid position (i, j), the sum over the points of
    the padded coarse field at the point's node, grid[r0 + di + i, c0 + dj + j] with
    (dj, di) = offsets[h, point] — matcher.coarse_candidates' shifted-slice sums, in the
    same order (float32, point by point)."""
    n_h, n_p = offsets.shape[0], offsets.shape[1]
    scores = np.zeros((n_h, ny, nx), dtype=np.float32)
    for h in range(n_h):
        for k in range(n_p):
            r = r0 + offsets[h, k, 1]
            q = c0 + offsets[h, k, 0]
            for i in range(ny):
                for j in range(nx):
                    scores[h, i, j] += grid[r + i, q + j]
    return scores


def _usable_example() -> tuple:
    return np.array([[1.0, 0.0], [np.nan, 1.0], [20.0, 0.0], [0.5, -0.5]]), 10.0


@kernel(_usable_example)
def usable_kernel(points: np.ndarray, max_range: float) -> np.ndarray:
    """The points (N, 2) with finite coordinates and |p| <= max_range, in order (a copy)."""
    keep = np.empty(points.shape[0], dtype=np.bool_)
    for i in range(points.shape[0]):
        x, y = points[i, 0], points[i, 1]
        keep[i] = np.isfinite(x) and np.isfinite(y) and np.hypot(x, y) <= max_range
    return points[keep]


def _hits_example() -> tuple:
    field, x0, y0, res, pts = _field_example()
    return field, np.zeros((4, 4), dtype=np.int32), x0, y0, res, pts, 0.0, 0.0, 0.1, 0.05, np.zeros(2, dtype=np.int64)


@kernel(_hits_example)
def seen_hits_kernel(field: np.ndarray, index: np.ndarray, x0: float, y0: float, res: float, pts: np.ndarray,
                     px: float, py: float, pa: float, inlier_distance: float, hits: np.ndarray) -> np.ndarray:
    """`hits` (a copy) plus one for every point (robot frame) that lands, at the pose, within
    `inlier_distance` of the map, on its nearest segment (those beyond len(hits) and off the
    grid uncounted)."""
    out = hits.copy()
    c, s = math.cos(pa), math.sin(pa)
    for i in range(pts.shape[0]):
        qx = pts[i, 0] * c + pts[i, 1] * -s + px
        qy = pts[i, 0] * s + pts[i, 1] * c + py
        if _bilinear(field, x0, y0, res, qx, qy) <= inlier_distance:
            k = _nearest(index, x0, y0, res, qx, qy)
            if 0 <= k < out.shape[0]:
                out[k] += 1
    return out
