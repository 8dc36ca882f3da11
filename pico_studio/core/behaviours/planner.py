"""A* on the rasterised, inflated global map.

The map is rasterised (`json_map.rasterise`: walls and cabinets/tables occupied; doors stay
passable, the robot asks for them to open) and one OpenCV distance transform gives every
cell's clearance. A cell is blocked when it lies closer than `inflation` to a
segment (the robot's half-size plus a margin: the robot is then planned as a point), and a
free cell within `cost_margin` more carries a penalty so plans keep to the middle of
corridors:

    step cost = length * (1 + cost_weight * max(0, 1 - (d - inflation) / cost_margin))

A* over the 8-connected grid with the Euclidean heuristic (admissible: every step costs at
least its length) returns the cheapest cell path; it is then thinned to the cells where the
direction changes. The search is one compiled loop (`_astar`) with its own binary heap
ordered by (f, g, row, column) — the order Python's `heapq` gives tuples (f, g, (row,
column)) — so it expands the cells the plain Python A* did, in the same order.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from pico_studio.config.behaviour_params import HospitalParams
from pico_studio.jit import kernel, njit
from pico_studio.json_map import GlobalMap
from pico_studio.json_map.raster import OCCUPIED, rasterise


@dataclass
class PlanGrid:
    """The inflated map: per-cell clearance, blocked flags and step penalty."""

    x0: float
    y0: float
    resolution: float
    clearance: np.ndarray  # (H, W) metres to the nearest solid segment
    blocked: np.ndarray  # (H, W) bool
    penalty: np.ndarray  # (H, W) float >= 0

    @classmethod
    def from_map(cls, global_map: GlobalMap, p: HospitalParams) -> PlanGrid:
        """Rasterise the map (`json_map.rasterise`: walls and cabinets/tables occupied,
        doors passable) at `p.cell`, then inflate it by a distance transform."""
        r = rasterise(global_map, resolution=p.cell)
        # the image's rows run down from the top; the grid's rows run up with y
        occupied = np.flipud(r.image == OCCUPIED)
        free = np.where(occupied, 0, 255).astype(np.uint8)
        d = cv2.distanceTransform(free, cv2.DIST_L2, cv2.DIST_MASK_PRECISE).astype(float) * p.cell
        blocked = d < p.inflation
        penalty = p.cost_weight * np.clip(1.0 - (d - p.inflation) / max(p.cost_margin, 1e-9), 0.0, 1.0)
        ox, oy = r.frame.origin
        return cls(ox + p.cell / 2, oy + p.cell / 2, p.cell, d, blocked, penalty)

    @classmethod
    def from_segments(cls, segments: np.ndarray, p: HospitalParams) -> PlanGrid:
        """The grid of a map that is just these wall segments (N, 4)."""
        segs = np.asarray(segments, dtype=float).reshape(-1, 4)
        points = segs.reshape(-1, 2)
        walls = np.arange(len(points)).reshape(-1, 2)
        return cls.from_map(GlobalMap(points=points, walls=walls), p)

    def cell(self, xy: tuple[float, float] | np.ndarray) -> tuple[int, int]:
        return (int(round((xy[1] - self.y0) / self.resolution)), int(round((xy[0] - self.x0) / self.resolution)))

    def xy(self, rc: tuple[int, int]) -> tuple[float, float]:
        return (self.x0 + rc[1] * self.resolution, self.y0 + rc[0] * self.resolution)

    def inside(self, rc: tuple[int, int]) -> bool:
        return 0 <= rc[0] < self.blocked.shape[0] and 0 <= rc[1] < self.blocked.shape[1]

    def free(self, xy: tuple[float, float] | np.ndarray) -> bool:
        rc = self.cell(xy)
        return self.inside(rc) and not self.blocked[rc]

    def clearance_at(self, xy: tuple[float, float] | np.ndarray) -> float:
        rc = self.cell(xy)
        return float(self.clearance[rc]) if self.inside(rc) else 0.0

    def with_obstacles(self, points: np.ndarray, radius: float) -> PlanGrid:
        """A copy with discs of `radius` around `points` (N, 2) blocked as well."""
        blocked = self.blocked.copy()
        r = int(math.ceil(radius / self.resolution))
        dr, dc = np.mgrid[-r:r + 1, -r:r + 1]
        disc = (dr**2 + dc**2) * self.resolution**2 <= radius**2
        offs_r, offs_c = dr[disc], dc[disc]
        h, w = blocked.shape
        for x, y in np.asarray(points, dtype=float).reshape(-1, 2):
            rr = offs_r + int(round((y - self.y0) / self.resolution))
            cc = offs_c + int(round((x - self.x0) / self.resolution))
            ok = (rr >= 0) & (rr < h) & (cc >= 0) & (cc < w)
            blocked[rr[ok], cc[ok]] = True
        return PlanGrid(self.x0, self.y0, self.resolution, self.clearance, blocked, self.penalty)

    def nearest_free(self, xy: tuple[float, float], search: float) -> tuple[float, float] | None:
        """The free cell nearest to `xy` within `search` metres (xy itself when free)."""
        if self.free(xy):
            return (float(xy[0]), float(xy[1]))
        r0, c0 = self.cell(xy)
        n = int(math.ceil(search / self.resolution))
        best: tuple[float, tuple[int, int]] | None = None
        for r in range(r0 - n, r0 + n + 1):
            for c in range(c0 - n, c0 + n + 1):
                if self.inside((r, c)) and not self.blocked[r, c]:
                    d = math.hypot(r - r0, c - c0)
                    if d <= n and (best is None or d < best[0]):
                        best = (d, (r, c))
        return None if best is None else self.xy(best[1])


def _astar_example() -> tuple:
    blocked = np.zeros((5, 6), dtype=np.bool_)
    blocked[1:4, 3] = True
    return blocked, np.zeros((5, 6)), 2, 0, 2, 5


@kernel(_astar_example)
def _astar(blocked: np.ndarray, penalty: np.ndarray, sr: int, sc: int, gr: int, gc: int) -> np.ndarray:
    """(K, 2) int64 cells of the cheapest path from (sr, sc) to (gr, gc); empty when none."""
    h, w = blocked.shape
    best = np.full((h, w), np.inf)
    parent = np.full((h, w), -1, dtype=np.int64)  # flat index of the cell we came from
    closed = np.zeros((h, w), dtype=np.bool_)
    # the open set: a binary min-heap of (f, g, row, col)
    cap = 1024
    hf = np.empty(cap)
    hg = np.empty(cap)
    hr = np.empty(cap, dtype=np.int64)
    hc = np.empty(cap, dtype=np.int64)
    n = 0
    best[sr, sc] = 0.0
    hf[0], hg[0], hr[0], hc[0] = math.hypot(sr - gr, sc - gc), 0.0, sr, sc
    n = 1
    while n > 0:
        # pop the smallest
        cost, r, c = hg[0], hr[0], hc[0]
        n -= 1
        if n > 0:
            hf[0], hg[0], hr[0], hc[0] = hf[n], hg[n], hr[n], hc[n]
            i = 0
            while True:
                left, right, m = 2 * i + 1, 2 * i + 2, i
                if left < n and _before(hf[left], hg[left], hr[left], hc[left], hf[m], hg[m], hr[m], hc[m]):
                    m = left
                if right < n and _before(hf[right], hg[right], hr[right], hc[right], hf[m], hg[m], hr[m], hc[m]):
                    m = right
                if m == i:
                    break
                hf[i], hf[m] = hf[m], hf[i]
                hg[i], hg[m] = hg[m], hg[i]
                hr[i], hr[m] = hr[m], hr[i]
                hc[i], hc[m] = hc[m], hc[i]
                i = m
        if closed[r, c]:
            continue
        if r == gr and c == gc:
            break
        closed[r, c] = True
        for dr in range(-1, 2):
            for dc in range(-1, 2):
                if dr == 0 and dc == 0:
                    continue
                nr, nc = r + dr, c + dc
                if not (0 <= nr < h and 0 <= nc < w) or blocked[nr, nc]:
                    continue
                if dr != 0 and dc != 0 and (blocked[r, nc] or blocked[nr, c]):
                    continue  # no corner cutting between two blocked cells
                new = cost + math.hypot(dr, dc) * (1.0 + penalty[nr, nc])
                if new < best[nr, nc]:
                    best[nr, nc] = new
                    parent[nr, nc] = r * w + c
                    if n == cap:  # grow the heap
                        cap *= 2
                        hf, hg, hr, hc = _grow(hf, cap), _grow(hg, cap), _grow(hr, cap), _grow(hc, cap)
                    # push and sift up
                    i = n
                    hf[i], hg[i], hr[i], hc[i] = new + math.hypot(nr - gr, nc - gc), new, nr, nc
                    n += 1
                    while i > 0:
                        up = (i - 1) // 2
                        if not _before(hf[i], hg[i], hr[i], hc[i], hf[up], hg[up], hr[up], hc[up]):
                            break
                        hf[i], hf[up] = hf[up], hf[i]
                        hg[i], hg[up] = hg[up], hg[i]
                        hr[i], hr[up] = hr[up], hr[i]
                        hc[i], hc[up] = hc[up], hc[i]
                        i = up
    if best[gr, gc] == np.inf:
        return np.zeros((0, 2), dtype=np.int64)
    # walk the parents back from the goal
    k = 1
    at = gr * w + gc
    while at != sr * w + sc:
        at = parent[at // w, at % w]
        k += 1
    cells = np.empty((k, 2), dtype=np.int64)
    at = gr * w + gc
    for i in range(k - 1, -1, -1):
        cells[i, 0], cells[i, 1] = at // w, at % w
        if i > 0:
            at = parent[at // w, at % w]
    return cells


@njit
def _before(f1: float, g1: float, r1: int, c1: int, f2: float, g2: float, r2: int, c2: int) -> bool:
    """(f1, g1, r1, c1) < (f2, g2, r2, c2), lexicographically (heapq's tuple order)."""
    if f1 != f2:
        return f1 < f2
    if g1 != g2:
        return g1 < g2
    if r1 != r2:
        return r1 < r2
    return c1 < c2


@njit
def _grow(a: np.ndarray, cap: int) -> np.ndarray:
    out = np.empty(cap, dtype=a.dtype)
    out[: a.shape[0]] = a
    return out


def astar(grid: PlanGrid, start: tuple[float, float], goal: tuple[float, float]) -> np.ndarray | None:
    """The cheapest path (K, 2) of cell centres from start to goal, or None when there is none.

    The start cell is allowed to be blocked (the robot may stand inside an inflated zone); the
    search then leaves it by the cheapest way out.
    """
    s, g = grid.cell(start), grid.cell(goal)
    if not (grid.inside(s) and grid.inside(g)) or grid.blocked[g]:
        return None
    cells = _astar(np.ascontiguousarray(grid.blocked, dtype=np.bool_), np.ascontiguousarray(grid.penalty, dtype=np.float64),
                   s[0], s[1], g[0], g[1])
    if len(cells) == 0:
        return None
    return np.array([grid.xy(rc) for rc in thin([(int(r), int(c)) for r, c in cells])])


def thin(cells: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """Keep the end cells and the cells where the step direction changes."""
    if len(cells) <= 2:
        return cells
    out = [cells[0]]
    for a, b, c in zip(cells, cells[1:], cells[2:], strict=False):
        if (b[0] - a[0], b[1] - a[1]) != (c[0] - b[0], c[1] - b[1]):
            out.append(b)
    out.append(cells[-1])
    return out


def densify(path: np.ndarray, step: float) -> np.ndarray:
    """Points every `step` metres along a polyline (K, 2), ends kept."""
    if len(path) < 2:
        return path
    out = [path[0]]
    for a, b in zip(path[:-1], path[1:], strict=True):
        n = max(1, int(math.ceil(np.hypot(*(b - a)) / step)))
        out += [a + (b - a) * (k / n) for k in range(1, n + 1)]
    return np.array(out)
