"""Small built scenes for the clutter rules: walls as segments, a ray-cast laser, a robot.

Everything in metres, the laser at the robot's centre (no footprint)."""

from __future__ import annotations

import math

import numpy as np

from pico_studio.core.io import LaserData, OdometryData

Pose = tuple[float, float, float]


def cast(walls: np.ndarray, pose: Pose, n: int = 720, fov: float = 2 * math.pi, max_range: float = 10.0) -> LaserData:
    """A scan of `walls` (W, 4) from `pose`: beam i at -fov/2 + i fov/n (robot frame)."""
    inc = fov / n
    rel = -fov / 2 + np.arange(n) * inc
    ang = rel + pose[2]
    d = np.column_stack([np.cos(ang), np.sin(ang)])
    a, e = walls[:, 0:2], walls[:, 2:4] - walls[:, 0:2]
    ao = a[None] - np.array(pose[:2])
    den = d[:, None, 0] * e[None, :, 1] - d[:, None, 1] * e[None, :, 0]
    safe = np.where(np.abs(den) > 1e-12, den, 1.0)
    t = (ao[..., 0] * e[None, :, 1] - ao[..., 1] * e[None, :, 0]) / safe
    u = (ao[..., 0] * d[:, None, 1] - ao[..., 1] * d[:, None, 0]) / safe
    t = np.where((np.abs(den) > 1e-12) & (t > 1e-9) & (u >= 0) & (u <= 1), t, np.inf).min(axis=1)
    ranges = np.where(t <= max_range, t, np.inf)
    return LaserData(0.01, max_range, float(rel[0]), float(rel[-1]), inc, 0.0, ranges)


def box(cx: float, cy: float, w: float, h: float | None = None) -> np.ndarray:
    """(4, 4) the sides of an axis-aligned box centred at (cx, cy)."""
    h = w if h is None else h
    x0, x1, y0, y1 = cx - w / 2, cx + w / 2, cy - h / 2, cy + h / 2
    return np.array([[x0, y0, x1, y0], [x1, y0, x1, y1], [x1, y1, x0, y1], [x0, y1, x0, y0]], dtype=float)


def room(w: float = 6.0, h: float = 4.0) -> np.ndarray:
    """(4, 4) a w x h room with a corner at the origin."""
    return box(w / 2, h / 2, w, h)


def odometry(pose: Pose, t: float) -> OdometryData:
    return OdometryData(pose[0], pose[1], pose[2], t)


def clutter_world(seed: int) -> tuple[dict, dict]:
    """A JSON map (the restaurant's format) and a sim config for it: a rectangular hall split by
    a 0.2 m thick wall with two doorways (0.8-1.1 m), tables (0.7 x 1.2 m) standing 1-3 cm off
    the outer walls, and a person (0.4 m box) walking across when the robot comes near."""
    rng = np.random.default_rng(seed)
    w, h = float(rng.uniform(7.0, 9.0)), float(rng.uniform(5.0, 6.5))
    pts: list[dict] = []
    walls: list[list[int]] = []
    tables: list[list[list[int]]] = []

    def p(x: float, y: float) -> int:
        pts.append({"x": round(x, 3), "y": round(y, 3)})
        return len(pts) - 1

    def poly(corners: list[tuple[float, float]]) -> list[list[int]]:
        ids = [p(x, y) for x, y in corners]
        return [[ids[i], ids[(i + 1) % len(ids)]] for i in range(len(ids))]

    def rect(x0: float, y0: float, x1: float, y1: float) -> list[list[int]]:
        return poly([(x0, y0), (x1, y0), (x1, y1), (x0, y1)])

    t = 0.2
    walls += rect(0, 0, w, t) + rect(0, h - t, w, h) + rect(0, t, t, h - t) + rect(w - t, t, w, h - t)
    # the dividing wall at x = xm with two doorways
    xm = float(rng.uniform(0.45, 0.55)) * w
    d1, d2 = (float(rng.uniform(0.8, 1.1)) for _ in range(2))
    y1 = float(rng.uniform(0.8, h / 2 - d1 - 0.4))
    y2 = float(rng.uniform(h / 2 + 0.2, h - 0.8 - d2))
    for lo, hi in ((t, y1), (y1 + d1, y2), (y2 + d2, h - t)):
        walls += rect(xm - t / 2, lo, xm + t / 2, hi)
    # tables against the outer walls, a few cm off, away from the doorways and corners
    for k, (side_x, lo_y) in enumerate(((t, 1.0), (w - t, 1.0), (t, h - 2.5))):
        gap = float(rng.uniform(0.01, 0.03))
        ty = lo_y + float(rng.uniform(0.0, 0.5))
        x0 = side_x + gap if k != 1 else side_x - gap - 0.7
        tables.append(rect(x0, ty, x0 + 0.7, ty + 1.2))
    doc = {"walls": walls, "tables": tables, "doors": [], "points": pts}
    start = (xm / 2, h / 2, 0.0)
    sim = {
        "initial_pose": list(start), "uncertain_odom": False, "provide_internal_pose": True,
        "objects": [{"length": 0.4, "width": 0.4, "trigger_radius": 2.5, "repeat": True, "velocity": 0.4,
                     "init_pose": [xm + 1.2, 0.8, 0.0], "final_pose": [xm + 1.2, h - 0.8, 0.0]}],
    }
    return doc, sim


def cafe_world(seed: int) -> tuple[dict, dict]:
    """A JSON map and a sim config unlike `clutter_world`'s: a hall (8-10 x 6-7 m, 0.2 m walls)
    with two T-openings (a partition from the floor wall ending 0.8-1.1 m short of the top
    wall; one from the right wall ending that far from the first's face), tables in rows along
    the walls (1-3 cm off, 0.5-0.8 m apart: bays that are no doors), tables standing free in
    the rooms, and two people (0.4 m boxes) crossing, one walking to and fro."""
    rng = np.random.default_rng(seed)
    u = rng.uniform
    w, h, t = float(u(8.0, 10.0)), float(u(6.0, 7.0)), 0.2
    pts: list[dict] = []
    walls: list[list[int]] = []
    tables: list[list[list[int]]] = []

    def rect(x0: float, y0: float, x1: float, y1: float) -> list[list[int]]:
        ids = []
        for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1)):
            pts.append({"x": round(x, 3), "y": round(y, 3)})
            ids.append(len(pts) - 1)
        return [[ids[i], ids[(i + 1) % 4]] for i in range(4)]

    walls += rect(0, 0, w, t) + rect(0, h - t, w, h) + rect(0, t, t, h - t) + rect(w - t, t, w, h - t)
    xm = float(u(0.45, 0.55)) * w  # the partition from the floor wall, its top a T-opening
    d1, d2 = float(u(0.8, 1.1)), float(u(0.8, 1.1))
    walls += rect(xm - t / 2, t, xm + t / 2, h - t - d1)
    ym = float(u(0.4, 0.5)) * h  # the partition from the right wall, ending d2 from the first
    walls += rect(xm + t / 2 + d2, ym - t / 2, w - t, ym + t / 2)
    # a row of tables along the floor wall of the left room, bays between them
    x = t + float(u(0.6, 0.9))
    while True:
        tw = float(u(1.0, 1.4))
        if x + tw > xm - t / 2 - 0.6:
            break
        gap = float(u(0.01, 0.03))
        tables.append(rect(x, t + gap, x + tw, t + gap + 0.7))
        x += tw + float(u(0.5, 0.8))
    # one table standing free in the left room, one against the right wall below the partition,
    # a row of two along the top wall of the right room
    cx, cy = (t + xm) / 2 + float(u(-0.3, 0.3)), h * 0.62 + float(u(-0.2, 0.2))
    tables.append(rect(cx - 0.6, cy - 0.4, cx + 0.6, cy + 0.4))
    gap = float(u(0.01, 0.03))
    ty = t + float(u(0.5, 1.0))
    tables.append(rect(w - t - gap - 0.7, ty, w - t - gap, min(ty + 1.2, ym - t / 2 - 0.9)))
    x = xm + t / 2 + d2 + float(u(0.3, 0.6))
    for _ in range(2):
        tw = float(u(1.0, 1.3))
        if x + tw > w - t - 0.3:
            break
        gap = float(u(0.01, 0.03))
        tables.append(rect(x, h - t - gap - 0.7, x + tw, h - t - gap))
        x += tw + float(u(0.5, 0.8))
    doc = {"walls": walls, "tables": tables, "doors": [], "points": pts}
    start = (xm / 2, h * 0.4, 0.0)
    sim = {
        "initial_pose": list(start), "uncertain_odom": False, "provide_internal_pose": True,
        "objects": [
            {"length": 0.4, "width": 0.4, "trigger_radius": 2.5, "repeat": False, "velocity": 0.4,
             "init_pose": [t + 0.6, h * 0.45, 0.0], "final_pose": [xm - 0.6, h * 0.45, 0.0]},
            {"length": 0.4, "width": 0.4, "trigger_radius": 3.0, "repeat": True, "velocity": 0.3,
             "init_pose": [xm + 1.0, ym - 1.2, 0.0], "final_pose": [w - 1.5, ym - 1.2, 0.0]},
        ],
    }
    return doc, sim


def ward_world(seed: int) -> tuple[dict, dict]:
    """A JSON map and a sim config unlike the halls': a hospital ward. A corridor (10-14 m by
    1.6-2.4 m) with rooms on both sides (2.5-4 m wide, 3-4 m deep), one wall thickness per world
    (0.05-0.25 m), each room's door (0.7-1.1 m) anywhere along the corridor wall or right by its
    side wall (a T-opening); in each room a bed (0.9 x 2 m, 1-3 cm off the back wall: its 2 m
    side is as long as a building's wall) and mostly a cabinet (0.5 m), and a person walking to
    and fro along the corridor."""
    rng = np.random.default_rng(seed)
    u = rng.uniform
    t = float(rng.choice([0.05, 0.1, 0.2, 0.25]))
    L, wc = float(u(10.0, 14.0)), float(u(1.6, 2.4))
    pts: list[dict] = []
    walls: list[list[int]] = []
    tables: list[list[list[int]]] = []

    def rect(x0: float, y0: float, x1: float, y1: float, into: list | None = None) -> None:
        ids = []
        for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1)):
            pts.append({"x": round(x, 3), "y": round(y, 3)})
            ids.append(len(pts) - 1)
        e = [[ids[i], ids[(i + 1) % 4]] for i in range(4)]
        if into is None:
            walls.extend(e)
        else:
            into.append(e)

    # the corridor walls' lower edges: the corridor runs between y = t and y = wc + t
    ylo, yhi = 0.0, wc + t
    ys: list[float] = []
    for wy0, sign in ((ylo, -1), (yhi, 1)):
        D = float(u(3.0, 4.0))
        # room boundaries
        xs = [0.0]
        while xs[-1] < L - 2.5:
            xs.append(min(xs[-1] + float(u(2.5, 4.0)), L))
        if L - xs[-1] < 2.5:
            xs[-1] = L
        else:
            xs.append(L)
        gaps = []
        for a, b in zip(xs[:-1], xs[1:], strict=True):
            dw = float(u(0.7, 1.1))
            if rng.random() < 0.25:  # the door by the room's side wall: a T-opening
                s = a + t / 2 if rng.random() < 0.5 else b - t / 2 - dw
            else:
                s = float(u(a + t / 2 + 0.3, b - t / 2 - 0.3 - dw))
            gaps.append((s, s + dw))
        # corridor wall pieces between doors
        x = 0.0
        for s, e in gaps:
            if s - x > 1e-3:
                rect(x, wy0, s, wy0 + t)
            x = e
        if L - x > 1e-3:
            rect(x, wy0, L, wy0 + t)
        # back wall and dividers
        if sign < 0:
            back0, back1 = wy0 - D - t, wy0 - D
            rect(0, back0, L, back1)
            for xb in xs[1:-1]:
                rect(xb - t / 2, back1, xb + t / 2, wy0)
            inner = (back1, wy0)
            ys.append(back0)
        else:
            back0, back1 = wy0 + t + D, wy0 + 2 * t + D
            rect(0, back0, L, back1)
            for xb in xs[1:-1]:
                rect(xb - t / 2, wy0 + t, xb + t / 2, back0)
            inner = (wy0 + t, back0)
            ys.append(back1)
        # furniture: a bed against the back wall, a cabinet by a side wall
        for a, b in zip(xs[:-1], xs[1:], strict=True):
            g = float(u(0.01, 0.03))
            bx = float(u(a + t / 2 + 0.2, b - t / 2 - 1.1))
            if sign < 0:
                rect(bx, inner[0] + g, bx + 0.9, inner[0] + g + 2.0, tables)
            else:
                rect(bx, inner[1] - g - 2.0, bx + 0.9, inner[1] - g, tables)
            if rng.random() < 0.7:
                c = 0.5
                cx0 = a + t / 2 + g if rng.random() < 0.5 else b - t / 2 - g - c
                if abs((cx0 + c / 2) - (bx + 0.45)) > 1.0:
                    cy0 = inner[1] - 0.6 - c if sign < 0 else inner[0] + 0.6
                    rect(cx0, cy0, cx0 + c, cy0 + c, tables)
    # end walls
    rect(-t, min(ys), 0.0, max(ys))
    rect(L, min(ys), L + t, max(ys))
    doc = {"walls": walls, "tables": tables, "doors": [], "points": pts}
    cy = t + wc / 2
    start = (1.0, cy, 0.0)
    sim = {
        "initial_pose": list(start), "uncertain_odom": False, "provide_internal_pose": True,
        "objects": [{"length": 0.4, "width": 0.4, "trigger_radius": 3.0, "repeat": True, "velocity": 0.4,
                     "init_pose": [2.5, cy + 0.3, 0.0], "final_pose": [L - 2.5, cy + 0.3, 0.0]}],
    }
    return doc, sim
