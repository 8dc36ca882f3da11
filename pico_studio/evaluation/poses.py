"""Random free poses of a map: where `eval` puts the robot to score the perceptor."""

from __future__ import annotations

import math

import cv2
import numpy as np

from pico_studio.sim.world import KIND_MOVING, World


def random_free_poses(segments: np.ndarray, start: tuple[float, float], k: int, clearance: float,
                      rng: np.random.Generator, bounds: tuple[float, float, float, float],
                      resolution: float = 0.05, avoid: np.ndarray | None = None) -> list[tuple[float, float, float]]:
    """K poses the robot could drive to from `start`: every segment is drawn into a grid
    grown by `clearance`, the free cells connected to the start cell are flood-filled, and K
    of them are drawn (a random point in the cell, a random heading). So poses lie inside the
    building, outside objects and thick walls, whatever way the map draws its walls; never
    outside `bounds` (the map's extent), even where an open exit leads out.

    `avoid`: segments no pose may lie within `clearance` of, that do not bound the fill — the
    people walking (`sim.world.KIND_MOVING`): where one stands now says nothing of where the
    robot can go (a person in a corridor narrowed askew closed off all but 2 m of it)."""
    x0, y0, x1, y1 = bounds
    x0, y0 = x0 - 2 * clearance, y0 - 2 * clearance
    w = int(math.ceil((x1 + 2 * clearance - x0) / resolution)) + 1
    h = int(math.ceil((y1 + 2 * clearance - y0) / resolution)) + 1
    grid = np.zeros((h + 2, w + 2), np.uint8)  # floodFill's mask needs a 1-cell border
    cells = _cells(segments, x0, y0, resolution)
    img = np.zeros((h, w), np.uint8)
    thick = max(1, int(math.ceil(2 * clearance / resolution)))
    cv2.polylines(img, list(cells), False, 255, thick)
    grid[1:-1, 1:-1] = img
    # nothing outside the map's extent: through an open exit (an escape room's) the fill would
    # run round the building's outside, where the map has nothing to localise against
    inside_x0, inside_y0 = int(round(2 * clearance / resolution)), int(round(2 * clearance / resolution))
    inside_x1, inside_y1 = int(round((x1 - x0) / resolution)), int(round((y1 - y0) / resolution))
    grid[1:-1, 1:-1][:, :inside_x0] = 1
    grid[1:-1, 1:-1][:, inside_x1 + 1:] = 1
    grid[1:-1, 1:-1][:inside_y0, :] = 1
    grid[1:-1, 1:-1][inside_y1 + 1:, :] = 1
    sx, sy = (int(round((start[0] - x0) / resolution)), int(round((start[1] - y0) / resolution)))
    if not (0 <= sx < w and 0 <= sy < h):
        return []
    if img[sy, sx]:  # the start itself is tight: begin at the nearest free cell
        fy, fx = np.nonzero(img == 0)
        if len(fx) == 0:
            return []
        n = int(np.argmin((fx - sx) ** 2 + (fy - sy) ** 2))
        sx, sy = int(fx[n]), int(fy[n])
    filled = np.zeros((h, w), np.uint8)
    cv2.floodFill(filled, grid, (sx, sy), 1, flags=4)
    if avoid is not None and len(avoid):
        near = np.zeros((h, w), np.uint8)
        cv2.polylines(near, list(_cells(avoid, x0, y0, resolution)), False, 1, thick)
        filled[near > 0] = 0
    ys, xs = np.nonzero(filled)
    if len(xs) == 0:
        return []
    pick = rng.choice(len(xs), size=k, replace=len(xs) < k)
    jitter = rng.uniform(-0.5, 0.5, size=(k, 2)) * resolution
    out = []
    for (cx, cy), (jx, jy) in zip(zip(xs[pick], ys[pick], strict=True), jitter, strict=True):
        out.append((float(x0 + cx * resolution + jx), float(y0 + cy * resolution + jy),
                    float(rng.uniform(-math.pi, math.pi))))
    return out


def world_free_poses(world: World, start: tuple[float, float], k: int, clearance: float,
                     rng: np.random.Generator, bounds: tuple[float, float, float, float]) -> list[tuple[float, float, float]]:
    """`random_free_poses` in a simulated world as it is now: its walls, objects and doors (a
    closed door closes its room) bound the fill; its moving objects are only kept clear of."""
    moving = world.kinds() == KIND_MOVING
    segments = world.segments()
    return random_free_poses(segments[~moving], start, k, clearance, rng, bounds, avoid=segments[moving])


def _cells(segments: np.ndarray, x0: float, y0: float, resolution: float) -> np.ndarray:
    """(N, 2, 2) int32 grid cells of each segment's two ends (for cv2.polylines)."""
    return np.round((np.asarray(segments, dtype=float).reshape(-1, 2) - (x0, y0)) / resolution).astype(np.int32).reshape(-1, 2, 2)
