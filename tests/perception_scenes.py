"""Hand-built scenes with known answers for the perceptor tests: walls, an exact raycast, scans.

`scan_of(walls, pose)` raycasts the PICO simulator's laser layout (1000 beams, -2..2 rad)
against map-frame walls (N, 4) from `pose`, with optional uniform noise, so every test knows
exactly which walls, corners and doors the perceptor should find.
"""

from __future__ import annotations

import numpy as np

from pico_studio.core.io import LaserData, OdometryData

PICO = {"n": 1000, "amin": -2.0, "amax": 2.0, "rmin": 0.01, "rmax": 10.0}


def raycast(walls: np.ndarray, pose: tuple[float, float, float], angles: np.ndarray) -> np.ndarray:
    """Exact range per beam (inf where nothing is hit)."""
    x, y, a = pose
    d = np.column_stack([np.cos(angles + a), np.sin(angles + a)])
    p = walls[:, 0:2]
    e = walls[:, 2:4] - p
    den = d[:, None, 0] * e[None, :, 1] - d[:, None, 1] * e[None, :, 0]
    q = p[None, :, :] - np.array([x, y])
    safe = np.where(np.abs(den) > 1e-12, den, 1.0)
    t = (q[..., 0] * e[None, :, 1] - q[..., 1] * e[None, :, 0]) / safe
    u = (q[..., 0] * d[:, None, 1] - q[..., 1] * d[:, None, 0]) / safe
    ok = (np.abs(den) > 1e-12) & (t > 0) & (u >= 0) & (u <= 1)
    return np.where(ok, t, np.inf).min(axis=1)


def scan_of(
    walls: np.ndarray, pose: tuple[float, float, float], *, noise: float = 0.0, seed: int = 0,
    n: int = PICO["n"], amin: float = PICO["amin"], amax: float = PICO["amax"],
    rmax: float = PICO["rmax"], t: float = 0.0,
) -> LaserData:
    inc = (amax - amin) / (n - 1)
    angles = amin + np.arange(n) * inc
    r = raycast(np.asarray(walls, dtype=float), pose, angles)
    if noise:
        r = r + np.random.default_rng(seed).uniform(-noise, noise, n)
    r = np.where(np.isfinite(r) & (r <= rmax), r, 0.0)  # the official simulator's "no return"
    return LaserData(PICO["rmin"], rmax, amin, amax, inc, t, r)


def odom(pose: tuple[float, float, float], t: float = 0.0) -> OdometryData:
    return OdometryData(pose[0], pose[1], pose[2], t)


def poly(*pts: tuple[float, float], closed: bool = True) -> np.ndarray:
    """Walls along a polyline through the points (closed by default)."""
    p = np.array(pts, dtype=float)
    q = np.roll(p, -1, axis=0) if closed else p[1:]
    p = p if closed else p[:-1]
    return np.hstack([p, q])


SQUARE = poly((-2, -2), (2, -2), (2, 2), (-2, 2))  # a 4 x 4 m room around the origin
# a room with a 0.9 m door gap in its top wall (x from -0.45 to 0.45), thin walls
DOOR_ROOM = np.vstack([
    poly((-0.45, 2), (-2, 2), (-2, -2), (2, -2), (2, 2), (0.45, 2), closed=False),
])
# a 1.2 m wide hallway along x
HALLWAY = np.array([[-1.0, 0.6, 6.0, 0.6], [-1.0, -0.6, 6.0, -0.6]])
