"""The scan matcher's compiled loop: each point's nearest local wall (scan_match.py's maths).

For a point q (zero frame) and a wall from a with direction ab (length L, unit normal n):

    t = (q - a) . ab / L^2,   closest = a + clip(t, 0, 1) ab,   dist = |q - closest|

The nearest wall k is the one with the smallest dist (the first such); the point is usable
when its foot falls inside that wall (0 <= t_k <= 1) and dist_k < gate; its residual is the
signed distance to the wall's line, r = n_k . (q - a_k). One pass over points and walls, no
(points x walls) arrays; a wall whose bounding box is already farther than the nearest wall
so far is skipped (it cannot be nearer: the same answer, fewer exact distances).
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel, njit

_SLACK = 1e-9  # m: far above the rounding of a distance in a map of metres (~1e-13)


def _example() -> tuple:
    walls = np.array([[0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 1.0, 1.0]])
    a = np.ascontiguousarray(walls[:, 0:2])
    ab = np.ascontiguousarray(walls[:, 2:4] - a)
    length = np.hypot(ab[:, 0], ab[:, 1])
    normal = np.ascontiguousarray(np.column_stack([-ab[:, 1], ab[:, 0]]) / length[:, None])
    q = np.array([[0.5, 0.05], [0.9, 0.5], [2.0, 2.0]])
    return q, a, ab, normal, length, 0.2


@kernel(_example)
def associate(q: np.ndarray, a: np.ndarray, ab: np.ndarray, normal: np.ndarray, length: np.ndarray,
              gate: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(nearest wall (M,) int64, signed distance to its line (M,), usable (M,) bool)."""
    m, w = q.shape[0], a.shape[0]
    k_out = np.zeros(m, dtype=np.int64)
    r_out = np.zeros(m)
    ok_out = np.zeros(m, dtype=np.bool_)
    # each wall's box: no point of the wall is nearer to q than the box, so a wall whose box
    # lies farther than the best distance so far (by more than any rounding, _SLACK) cannot
    # be the nearest, and its exact distance is not needed (the answer stays the same)
    lo_x, hi_x = np.empty(w), np.empty(w)
    lo_y, hi_y = np.empty(w), np.empty(w)
    for j in range(w):
        bx, by = a[j, 0] + ab[j, 0], a[j, 1] + ab[j, 1]
        lo_x[j], hi_x[j] = min(a[j, 0], bx), max(a[j, 0], bx)
        lo_y[j], hi_y[j] = min(a[j, 1], by), max(a[j, 1], by)
    for i in range(m):
        best = np.inf
        best_k = 0
        best_t = 0.0
        for j in range(w):
            if j > 0:
                ox = max(lo_x[j] - q[i, 0], 0.0, q[i, 0] - hi_x[j])
                oy = max(lo_y[j] - q[i, 1], 0.0, q[i, 1] - hi_y[j])
                if ox * ox + oy * oy > (best + _SLACK) * (best + _SLACK):
                    continue
            rx, ry = q[i, 0] - a[j, 0], q[i, 1] - a[j, 1]
            t = (rx * ab[j, 0] + ry * ab[j, 1]) / (length[j] * length[j])
            c = min(max(t, 0.0), 1.0)
            d = math.hypot(q[i, 0] - (a[j, 0] + c * ab[j, 0]), q[i, 1] - (a[j, 1] + c * ab[j, 1]))
            if j == 0 or d < best:  # the first smallest, as numpy's argmin
                best, best_k, best_t = d, j, t
        k = best_k
        k_out[i] = k
        ok_out[i] = best_t >= 0.0 and best_t <= 1.0 and best < gate
        rx, ry = q[i, 0] - a[k, 0], q[i, 1] - a[k, 1]
        r_out[i] = rx * normal[k, 0] + ry * normal[k, 1]
    return k_out, r_out, ok_out


@njit
def _eig3(h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (3,) and eigenvectors (columns) of a symmetric 3x3 matrix: cyclic Jacobi
    rotations, each zeroing one off-diagonal entry, until they are all negligible."""
    m = h.copy()
    v = np.eye(3)
    for _ in range(50):
        off = m[0, 1] ** 2 + m[0, 2] ** 2 + m[1, 2] ** 2
        if off <= 1e-30 * (m[0, 0] ** 2 + m[1, 1] ** 2 + m[2, 2] ** 2) + 1e-300:
            break
        for pi_, qi in ((0, 1), (0, 2), (1, 2)):
            if m[pi_, qi] == 0.0:
                continue
            theta = (m[qi, qi] - m[pi_, pi_]) / (2.0 * m[pi_, qi])
            t = (1.0 if theta >= 0 else -1.0) / (abs(theta) + math.sqrt(theta * theta + 1.0))
            c = 1.0 / math.sqrt(t * t + 1.0)
            s = t * c
            for k in range(3):  # m <- J^T m J with J the rotation in the (p, q) plane
                mkp, mkq = m[k, pi_], m[k, qi]
                m[k, pi_], m[k, qi] = c * mkp - s * mkq, s * mkp + c * mkq
            for k in range(3):
                mpk, mqk = m[pi_, k], m[qi, k]
                m[pi_, k], m[qi, k] = c * mpk - s * mqk, s * mpk + c * mqk
            for k in range(3):
                vkp, vkq = v[k, pi_], v[k, qi]
                v[k, pi_], v[k, qi] = c * vkp - s * vkq, s * vkp + c * vkq
    return np.array([m[0, 0], m[1, 1], m[2, 2]]), v


def _fit_example() -> tuple:
    q, a, ab, normal, length, _ = _example()
    pts = np.array([[0.5, -1.0], [0.6, -1.0], [0.7, -1.0], [1.0, 0.5], [1.0, 0.6], [1.0, 0.7]])
    x0 = np.array([0.0, 1.0, 0.0])
    sig = np.array([0.1, 0.1, 0.05])
    settings = np.array([1.0, 0.3, 0.4, 0.05, 0.03, 0.8, 0.05, 0.1, 0.03, 0.6, 8.0])
    return pts, a, ab, normal, length, x0, sig, settings


# the order of `settings` in fit_pose (scan_match.py packs them from ScanMatchParams)
S_STRIDE, S_NEIGHBOUR, S_GATE, S_INLIER, S_SIGMA, S_GOOD, S_INFORMATION, S_SEARCH_ANGLE, S_SEARCH_STEP, \
    S_NORMAL_ANGLE, S_ITERATIONS = range(11)
N_SETTINGS = 11


@kernel(_fit_example)
def fit_pose(pts: np.ndarray, a: np.ndarray, ab: np.ndarray, normal: np.ndarray, length: np.ndarray,
             x0: np.ndarray, sig: np.ndarray, settings: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Point-to-line ICP of scan points `pts` (M, 2, robot frame, scan order) against walls
    (zero frame) from the odometry pose `x0`, odometry noise `sig` (3,): scan_match.py's maths.

    Returns (x (3,), info (6,)): the fitted pose and [quality, matched, quality at x0,
    observable directions, conditioning (smallest / largest whitened eigenvalue), skipped
    (1: x0 already good, nothing fitted)]."""
    stride = max(int(settings[S_STRIDE]), 1)
    neighbour, gate0, inlier = settings[S_NEIGHBOUR], settings[S_GATE], settings[S_INLIER]
    sigma_p, good, min_info = settings[S_SIGMA], settings[S_GOOD], settings[S_INFORMATION]
    search_angle, search_step = settings[S_SEARCH_ANGLE], settings[S_SEARCH_STEP]
    max_sin = math.sin(settings[S_NORMAL_ANGLE])
    iterations = int(settings[S_ITERATIONS])
    m_all, w = pts.shape[0], a.shape[0]
    info = np.zeros(6)
    x = x0.copy()
    # the subsampled points and each one's direction along the scan (its neighbours within
    # `neighbour`: a wall's points lie along it, so only walls of that direction can be its wall)
    m = (m_all + stride - 1) // stride
    p = np.empty((m, 2))
    tan = np.zeros((m, 2))
    has_tan = np.zeros(m, dtype=np.bool_)
    for s in range(m):
        i = s * stride
        p[s, 0], p[s, 1] = pts[i, 0], pts[i, 1]
        lo, hi = i, i
        if i > 0 and math.hypot(pts[i, 0] - pts[i - 1, 0], pts[i, 1] - pts[i - 1, 1]) <= neighbour:
            lo = i - 1
        if i + 1 < m_all and math.hypot(pts[i + 1, 0] - pts[i, 0], pts[i + 1, 1] - pts[i, 1]) <= neighbour:
            hi = i + 1
        dx, dy = pts[hi, 0] - pts[lo, 0], pts[hi, 1] - pts[lo, 1]
        dn = math.hypot(dx, dy)
        if dn > 1e-9:
            tan[s, 0], tan[s, 1], has_tan[s] = dx / dn, dy / dn, True
    lo_x, hi_x = np.empty(w), np.empty(w)
    lo_y, hi_y = np.empty(w), np.empty(w)
    for j in range(w):
        bx, by = a[j, 0] + ab[j, 0], a[j, 1] + ab[j, 1]
        lo_x[j], hi_x[j] = min(a[j, 0], bx), max(a[j, 0], bx)
        lo_y[j], hi_y[j] = min(a[j, 1], by), max(a[j, 1], by)
    k_of = np.empty(m, dtype=np.int64)
    r_of = np.empty(m)
    q = np.empty((m, 2))

    def match(x: np.ndarray, gate: float) -> int:
        """Each point's nearest wall of a compatible direction whose foot lies inside it,
        within `gate` (k_of -1 otherwise); r_of the signed distance to its line."""
        c, s = math.cos(x[2]), math.sin(x[2])
        n_ok = 0
        for i in range(m):
            qx = c * p[i, 0] - s * p[i, 1] + x[0]
            qy = s * p[i, 0] + c * p[i, 1] + x[1]
            q[i, 0], q[i, 1] = qx, qy
            tx, ty = c * tan[i, 0] - s * tan[i, 1], s * tan[i, 0] + c * tan[i, 1]
            best, best_k = gate, -1
            for j in range(w):
                ox = max(lo_x[j] - qx, 0.0, qx - hi_x[j])
                oy = max(lo_y[j] - qy, 0.0, qy - hi_y[j])
                if ox * ox + oy * oy >= best * best:
                    continue  # its box is already farther than the best wall so far
                if has_tan[i] and abs(tx * normal[j, 0] + ty * normal[j, 1]) > max_sin:
                    continue  # the scan runs across this wall here: not its wall
                rx, ry = qx - a[j, 0], qy - a[j, 1]
                t = (rx * ab[j, 0] + ry * ab[j, 1]) / (length[j] * length[j])
                if t < 0.0 or t > 1.0:
                    continue  # beyond the wall's end: where the map stops knowing
                d = abs(rx * normal[j, 0] + ry * normal[j, 1])
                if d < best:
                    best, best_k = d, j
            k_of[i] = best_k
            if best_k >= 0:
                n_ok += 1
                r_of[i] = (qx - a[best_k, 0]) * normal[best_k, 0] + (qy - a[best_k, 1]) * normal[best_k, 1]
        return n_ok

    def explained(x: np.ndarray) -> tuple[int, float]:
        match(x, 2.0 * inlier)
        n_in = 0
        n_ok = 0
        for i in range(m):
            if k_of[i] >= 0:
                n_ok += 1
                if abs(r_of[i]) <= inlier:
                    n_in += 1
        return n_ok, n_in / max(m, 1)

    _, quality0 = explained(x0)
    info[2] = quality0
    if quality0 >= good:
        info[0], info[5] = quality0, 1.0
        return x, info
    # heading search: of the headings within search_angle (nearest the odometry's first, so a
    # tie keeps the nearer), the one under which most points lie within half the gate
    n_steps = int(search_angle / search_step) if search_step > 0 else 0
    best_a, best_n = x0[2], -1
    trial = x0.copy()
    for o in range(2 * n_steps + 1):
        off = ((o + 1) // 2) * search_step * (1.0 if o % 2 else -1.0)
        trial[2] = x0[2] + off
        n = match(trial, gate0 / 2.0)
        if n > best_n:
            best_a, best_n = trial[2], n
    x[2] = best_a
    # Gauss-Newton in odometry-whitened coordinates z = (x - x0) / sig
    h = np.empty((3, 3))
    g = np.empty(3)
    jw = np.empty(3)
    for it in range(iterations):
        gate = max(gate0 * 0.6**it, 2.0 * inlier)
        n_ok = match(x, gate)
        if n_ok < 3:
            return x0.copy(), info
        h[:, :] = 0.0
        g[:] = 0.0
        for i in range(m):
            k = k_of[i]
            if k < 0:
                continue
            r = r_of[i]
            u = r / gate
            wt = (1.0 - u * u) ** 2 / (sigma_p * sigma_p)  # Tukey's biweight, zero at the gate
            nx, ny = normal[k, 0], normal[k, 1]
            jw[0] = nx * sig[0]
            jw[1] = ny * sig[1]
            jw[2] = (nx * -(q[i, 1] - x[1]) + ny * (q[i, 0] - x[0])) * sig[2]
            for u1 in range(3):
                g[u1] += wt * jw[u1] * r
                for u2 in range(3):
                    h[u1, u2] += wt * jw[u1] * jw[u2]
        z = np.empty(3)
        z[0] = (x[0] - x0[0]) / sig[0]
        z[1] = (x[1] - x0[1]) / sig[1]
        da = x[2] - x0[2]
        z[2] = math.atan2(math.sin(da), math.cos(da)) / sig[2]  # wrapped to (-pi, pi]
        vals, vecs = _eig3(h)
        top = max(vals[0], vals[1], vals[2], 1e-12)
        dz = np.zeros(3)
        observable = 0
        for e in range(3):
            v = vecs[:, e]
            vz = v[0] * z[0] + v[1] * z[1] + v[2] * z[2]
            if vals[e] >= min_info:  # the walls know this direction min_info x better than odometry: MAP step
                vg = v[0] * g[0] + v[1] * g[1] + v[2] * g[2]
                step = -(vg + vz) / (vals[e] + 1.0)
                observable += 1
            else:  # along a corridor: held where odometry put it
                step = -vz
            for u1 in range(3):
                dz[u1] += step * v[u1]
        info[3] = observable
        info[4] = max(min(vals[0], vals[1], vals[2]), 0.0) / top
        d0, d1, d2 = dz[0] * sig[0], dz[1] * sig[1], dz[2] * sig[2]
        x[0] += d0
        x[1] += d1
        x[2] += d2
        if abs(d0) + abs(d1) < 1e-4 and abs(d2) < 1e-4:
            break
    matched, quality = explained(x)
    info[0], info[1] = quality, matched
    return x, info

