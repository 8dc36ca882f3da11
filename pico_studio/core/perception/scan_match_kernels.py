"""The scan matcher's compiled loops (scan_match.py's maths).

`fit_pose` is the whole point-to-line ICP: association, Tukey weights, the odometry-whitened
Gauss-Newton with its free and held directions, the heading search, quality and evidence.
Its association takes, of the walls whose foot lies inside them and whose direction agrees
with the scan's at the point, the one nearest to the point's line distance, skipping walls
whose bounding box is already farther than the best so far.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.jit import kernel, njit


@njit
def _solve_spd(a: np.ndarray, b: np.ndarray, n: int) -> None:
    """Solve a[:n, :n] y = b[:n] in place (y into b) for a symmetric positive definite a:
    Cholesky a = L L^T, then the two triangular solves (n <= 3)."""
    for j in range(n):
        s = a[j, j]
        for k in range(j):
            s -= a[j, k] * a[j, k]
        a[j, j] = math.sqrt(max(s, 1e-300))
        for i in range(j + 1, n):
            s = a[i, j]
            for k in range(j):
                s -= a[i, k] * a[j, k]
            a[i, j] = s / a[j, j]
    for i in range(n):  # L y' = b
        s = b[i]
        for k in range(i):
            s -= a[i, k] * b[k]
        b[i] = s / a[i, i]
    for i in range(n - 1, -1, -1):  # L^T y = y'
        s = b[i]
        for k in range(i + 1, n):
            s -= a[k, i] * b[k]
        b[i] = s / a[i, i]

def _fit_example() -> tuple:
    walls = np.array([[0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 1.0, 1.0]])
    pts = np.array([[0.5, -1.0], [0.6, -1.0], [0.7, -1.0], [1.0, 0.5], [1.0, 0.6], [1.0, 0.7]])
    x0 = np.array([0.0, 1.0, 0.0])
    sig = np.array([0.1, 0.1, 0.05])
    settings = np.array([200.0, 0.3, 0.4, 0.05, 0.03, 0.8, 5.0, 0.1, 0.03, 0.6, 8.0, 0.05, 50.0])
    return pts, walls, x0, sig, settings


# the order of `settings` in fit_pose (scan_match.py packs them from ScanMatchParams)
S_MAX_POINTS, S_NEIGHBOUR, S_GATE, S_INLIER, S_SIGMA, S_GOOD, S_INFORMATION, S_SEARCH_ANGLE, S_SEARCH_STEP, \
    S_NORMAL_ANGLE, S_ITERATIONS, S_CONDITIONING, S_SEARCH_POINTS = range(13)
N_SETTINGS = 13


@kernel(_fit_example)
def fit_pose(points: np.ndarray, walls: np.ndarray, x0: np.ndarray, sig: np.ndarray,
             settings: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Point-to-line ICP of scan `points` (M, 2, robot frame, scan order; non-finite ones
    skipped) against `walls` (W, 4, zero frame) from the odometry pose `x0`, odometry noise
    `sig` (3,): scan_match.py's maths.

    Returns (x (3,), info (6,)): the fitted pose and [quality, matched, quality at x0, free
    directions (of x, y, heading; the rest held to odometry), position conditioning (weaker /
    stronger eigenvalue of the position's information), evidence (the objective's drop from
    x0 to x)]; x0 and quality 0 when nothing fitted."""
    neighbour, gate0, inlier = settings[S_NEIGHBOUR], settings[S_GATE], settings[S_INLIER]
    sigma_p, good, min_info = settings[S_SIGMA], settings[S_GOOD], settings[S_INFORMATION]
    min_cond = settings[S_CONDITIONING]
    search_angle, search_step = settings[S_SEARCH_ANGLE], settings[S_SEARCH_STEP]
    max_sin = math.sin(settings[S_NORMAL_ANGLE])
    iterations = int(settings[S_ITERATIONS])
    search_points = max(int(settings[S_SEARCH_POINTS]), 1)
    info = np.zeros(6)
    x = x0.copy()
    # the finite points, then at most max_points of them evenly spread, each with its direction
    # along the scan (its neighbours within `neighbour`: a wall's points lie along it, so only
    # walls of that direction can be its wall)
    fin = np.empty((points.shape[0], 2))
    m_all = 0
    for i in range(points.shape[0]):
        if math.isfinite(points[i, 0]) and math.isfinite(points[i, 1]):
            fin[m_all, 0], fin[m_all, 1] = points[i, 0], points[i, 1]
            m_all += 1
    stride = max(1, -(-m_all // max(int(settings[S_MAX_POINTS]), 1)))
    m = (m_all + stride - 1) // stride
    p = np.empty((m, 2))
    tan = np.zeros((m, 2))
    has_tan = np.zeros(m, dtype=np.bool_)
    for s in range(m):
        i = s * stride
        p[s, 0], p[s, 1] = fin[i, 0], fin[i, 1]
        lo, hi = i, i
        if i > 0 and math.hypot(fin[i, 0] - fin[i - 1, 0], fin[i, 1] - fin[i - 1, 1]) <= neighbour:
            lo = i - 1
        if i + 1 < m_all and math.hypot(fin[i + 1, 0] - fin[i, 0], fin[i + 1, 1] - fin[i, 1]) <= neighbour:
            hi = i + 1
        dx, dy = fin[hi, 0] - fin[lo, 0], fin[hi, 1] - fin[lo, 1]
        dn = math.hypot(dx, dy)
        if dn > 1e-9:
            tan[s, 0], tan[s, 1], has_tan[s] = dx / dn, dy / dn, True
    # the walls: start a, direction ab, length, unit normal (finite, not degenerate ones)
    a = np.empty((walls.shape[0], 2))
    ab = np.empty((walls.shape[0], 2))
    length = np.empty(walls.shape[0])
    normal = np.empty((walls.shape[0], 2))
    w = 0
    for j in range(walls.shape[0]):
        ex, ey = walls[j, 2] - walls[j, 0], walls[j, 3] - walls[j, 1]
        el = math.hypot(ex, ey)
        if not (el > 1e-9 and math.isfinite(el) and math.isfinite(walls[j, 0]) and math.isfinite(walls[j, 1])):
            continue
        a[w, 0], a[w, 1], ab[w, 0], ab[w, 1], length[w] = walls[j, 0], walls[j, 1], ex, ey, el
        normal[w, 0], normal[w, 1] = -ey / el, ex / el
        w += 1
    if m < 3 or w == 0:
        return x, info
    search_every = max(1, -(-m // search_points))
    lo_x, hi_x = np.empty(w), np.empty(w)
    lo_y, hi_y = np.empty(w), np.empty(w)
    for j in range(w):
        bx, by = a[j, 0] + ab[j, 0], a[j, 1] + ab[j, 1]
        lo_x[j], hi_x[j] = min(a[j, 0], bx), max(a[j, 0], bx)
        lo_y[j], hi_y[j] = min(a[j, 1], by), max(a[j, 1], by)
    k_of = np.empty(m, dtype=np.int64)
    r_of = np.empty(m)
    q = np.empty((m, 2))

    def match(x: np.ndarray, gate: float, every: int = 1) -> int:
        """Each point's nearest wall of a compatible direction whose foot lies inside it,
        within `gate` (k_of -1 otherwise); r_of the signed distance to its line. Every
        `every`-th point only (the others keep their last match)."""
        c, s = math.cos(x[2]), math.sin(x[2])
        n_ok = 0
        for i in range(0, m, every):
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

    def explained(x: np.ndarray) -> tuple[int, float, float]:
        """(points matched, share within `inlier_distance`, the walls' robust cost) at x: the
        cost sums Tukey's rho(r) = c^2/6 (1 - (1 - (r/c)^2)^3) over sigma_p^2, c = 2 x
        inlier_distance, an unmatched point costing rho's ceiling c^2/6."""
        c = 2.0 * inlier
        match(x, c)
        n_in = 0
        n_ok = 0
        cost = 0.0
        for i in range(m):
            rho = c * c / 6.0
            if k_of[i] >= 0:
                n_ok += 1
                u = r_of[i] / c
                rho *= 1.0 - (1.0 - u * u) ** 3
                if abs(r_of[i]) <= inlier:
                    n_in += 1
            cost += rho / (sigma_p * sigma_p)
        return n_ok, n_in / max(m, 1), cost

    _, quality0, cost0 = explained(x0)
    info[2] = quality0
    trial = x0.copy()
    h = np.empty((3, 3))
    g = np.empty(3)
    jw = np.empty(3)
    z = np.empty(3)
    dz = np.empty(3)
    fit = np.empty(3)  # free directions, position conditioning, fitted (1) or too few matches (0)
    basis = np.zeros((3, 3))
    red = np.zeros((3, 3))
    rhs = np.zeros(3)
    w_ = np.zeros(3)

    def refine(x: np.ndarray) -> None:
        """Gauss-Newton in odometry-whitened coordinates z = (x - x0) / sig, in place."""
        fit[0], fit[1], fit[2] = 0.0, 0.0, 0.0
        for it in range(iterations):
            gate = max(gate0 * 0.6**it, 2.0 * inlier)
            if match(x, gate) < 3:
                return
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
            z[0] = (x[0] - x0[0]) / sig[0]
            z[1] = (x[1] - x0[1]) / sig[1]
            da = x[2] - x0[2]
            z[2] = math.atan2(math.sin(da), math.cos(da)) / sig[2]  # wrapped to (-pi, pi]
            # which directions the walls pin down: the heading by its own information; the
            # position by the eigenvalues of its information once the heading is solved with it
            # (the Schur complement T = H_tt - H_ta H_aa^-1 H_at), the weaker direction also
            # relative to the stronger (along a corridor it is a sliver of the cross-track one)
            heading_free = h[2, 2] >= min_info
            t00, t01, t11 = h[0, 0], h[0, 1], h[1, 1]
            if heading_free:
                t00 -= h[0, 2] * h[0, 2] / h[2, 2]
                t01 -= h[0, 2] * h[1, 2] / h[2, 2]
                t11 -= h[1, 2] * h[1, 2] / h[2, 2]
            mid, rad = 0.5 * (t00 + t11), math.sqrt(0.25 * (t00 - t11) ** 2 + t01 * t01)
            l1, l2 = mid + rad, mid - rad
            if abs(t01) > 1e-12 * (abs(t00) + abs(t11)):
                ux, uy = t01, l1 - t00
            elif t00 >= t11:
                ux, uy = 1.0, 0.0
            else:
                ux, uy = 0.0, 1.0
            un = math.hypot(ux, uy)
            ux, uy = ux / un, uy / un
            # the free directions (columns of basis, in whitened coordinates); the rest held
            n_free = 0
            basis[:, :] = 0.0
            if l1 >= min_info:
                basis[0, n_free], basis[1, n_free] = ux, uy
                n_free += 1
                if l2 >= min_info and l2 >= min_cond * l1:
                    basis[0, n_free], basis[1, n_free] = -uy, ux
                    n_free += 1
            if heading_free:
                basis[2, n_free] = 1.0
                n_free += 1
            z[0] = (x[0] - x0[0]) / sig[0]
            z[1] = (x[1] - x0[1]) / sig[1]
            da = x[2] - x0[2]
            z[2] = math.atan2(math.sin(da), math.cos(da)) / sig[2]  # wrapped to (-pi, pi]
            # MAP step in the free coordinates w = B^T z: (B^T H' B + I) dw = -(B^T g' + w);
            # the held components of z go to 0 (odometry's)
            for c1 in range(n_free):
                w_[c1] = basis[0, c1] * z[0] + basis[1, c1] * z[1] + basis[2, c1] * z[2]
                rhs[c1] = -w_[c1]
                for u1 in range(3):
                    rhs[c1] -= basis[u1, c1] * g[u1]
                for c2 in range(n_free):
                    acc = 1.0 if c1 == c2 else 0.0
                    for u1 in range(3):
                        for u2 in range(3):
                            acc += basis[u1, c1] * h[u1, u2] * basis[u2, c2]
                    red[c1, c2] = acc
            _solve_spd(red, rhs, n_free)
            for u1 in range(3):
                znew = 0.0
                for c1 in range(n_free):
                    znew += basis[u1, c1] * (w_[c1] + rhs[c1])
                dz[u1] = znew - z[u1]
            fit[0], fit[1], fit[2] = n_free, max(l2, 0.0) / max(l1, 1e-12), 1.0
            d0, d1, d2 = dz[0] * sig[0], dz[1] * sig[1], dz[2] * sig[2]
            x[0] += d0
            x[1] += d1
            x[2] += d2
            if abs(d0) + abs(d1) < 1e-4 and abs(d2) < 1e-4:
                break

    # refine from the odometry pose; when that leaves the scan poorly explained, also from the
    # searched heading: the one explaining more of the scan wins (a tie: odometry's)
    best_q = -1.0
    for start in range(2):
        trial[:] = x0
        if start == 1:
            if best_q >= good or search_angle <= 0.0 or search_step <= 0.0:
                break
            # heading search: of the headings within search_angle (nearest the odometry's
            # first, so a tie keeps the nearer), the one under which most of (at most
            # search_points of) the points lie within half the gate
            best_a, best_n = x0[2], -1
            for o in range(2 * int(search_angle / search_step) + 1):
                trial[2] = x0[2] + ((o + 1) // 2) * search_step * (1.0 if o % 2 else -1.0)
                n = match(trial, gate0 / 2.0, search_every)
                if n > best_n:
                    best_a, best_n = trial[2], n
            if best_a == x0[2] and best_q >= 0.0:
                break  # the same start again
            trial[:] = x0
            trial[2] = best_a
        refine(trial)
        if fit[2] == 0.0:
            continue
        matched, quality, cost = explained(trial)
        if quality > best_q:
            best_q = quality
            x[:] = trial
            # the evidence for the correction: how much lower the whole objective (walls +
            # odometry prior |z|^2) is at the fit than at the odometry pose
            zx, zy = (trial[0] - x0[0]) / sig[0], (trial[1] - x0[1]) / sig[1]
            dza = trial[2] - x0[2]
            za = math.atan2(math.sin(dza), math.cos(dza)) / sig[2]
            info[0], info[1], info[3], info[4] = quality, matched, fit[0], fit[1]
            info[5] = cost0 - (cost + zx * zx + zy * zy + za * za)
    if best_q < 0.0:
        return x0.copy(), info
    return x, info

