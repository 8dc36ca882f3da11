"""Seeded generators of the behaviours' test worlds, as `GlobalMap`s with a start pose.

    from pico_studio.evaluation.worlds import escape_world, room_finder_world
    w = escape_world(3)        # w.map: GlobalMap, w.start: (x, y, a), w.rooms: expected contents

Escape rooms (issue 7): a rectangular room 3-6 m a side, an exit hallway 0.6-1.0 m wide and
1-2.5 m long on a random wall (at least 0.3 m from either corner), a `finish` segment across
the hallway's far end, and a random start pose at least 0.5 m from every wall.

Room-finder worlds (seed 000's assumptions): a rectangular main room with 2-4 side rooms, each
one panel wide and deep, never at a corner (at least a panel from it) nor next to another; each
holds one object (a box in its centre) or a person's two feet (two small boxes side by side,
toes to the entrance). The expected count is what the seed counts: a box is one object, two
feet are two. The robot starts at least 0.6 m from the walls, not in a side room.

Furnished worlds (`hall`, `cafe`, `ward`, `suite`: `furnished_worlds`): tables, beds and cabinets, and
people walking (the world's `sim_config`), for the door figures among furniture; `slant`
(`slanted_worlds`): a ward or a suite drawn askew, its walls meeting at 76-84 degrees.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pico_studio.evaluation.furnished_worlds import (
    cafe_world,
    clutter_world,
    suite_world,
    ward_world,
)
from pico_studio.evaluation.slanted_worlds import slanted_world
from pico_studio.json_map import GlobalMap, map_from_dict
from pico_studio.sim.sim_config import SimConfigFile, sim_config_from_dict

PANEL = 1.0  # side room width and depth [m]


@dataclass
class World:
    map: GlobalMap
    start: tuple[float, float, float]
    rooms: list[dict[str, object]] = field(default_factory=list)  # room finder: expected rooms
    seed: int = 0
    sim_config: SimConfigFile | None = None  # its moving people (the furnished worlds)


class _Builder:
    """Collects points and wall/polygon index pairs."""

    def __init__(self) -> None:
        self.points: list[tuple[float, float]] = []
        self.walls: list[tuple[int, int]] = []
        self.finish: list[tuple[int, int]] = []

    def point(self, x: float, y: float) -> int:
        self.points.append((float(x), float(y)))
        return len(self.points) - 1

    def polyline(self, pts: list[tuple[float, float]], closed: bool = False) -> None:
        idx = [self.point(*p) for p in pts]
        if closed:
            idx.append(idx[0])
        self.walls += list(zip(idx[:-1], idx[1:], strict=True))

    def build(self) -> GlobalMap:
        return GlobalMap(
            points=np.array(self.points, dtype=float),
            walls=np.array(self.walls, dtype=np.int64),
            finish=np.array(self.finish, dtype=np.int64).reshape(-1, 2),
            key_order=["points", "walls", "finish"],
        )


def _frame(side: int, w: float, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Wall `side` (0 bottom, 1 right, 2 top, 3 left) of a w x h room walked counter-clockwise:
    its start corner, its unit direction, its outward normal and its length."""
    corners = [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]
    a = np.array(corners[side])
    b = np.array(corners[(side + 1) % 4])
    d = (b - a) / np.hypot(*(b - a))
    return a, d, np.array([d[1], -d[0]]), float(np.hypot(*(b - a)))


def escape_world(seed: int) -> World:
    rng = np.random.default_rng(seed)
    w, h = rng.uniform(3.0, 6.0, size=2)
    width = rng.uniform(0.6, 1.0)
    length = rng.uniform(1.0, 2.5)
    side = int(rng.integers(4))
    b = _Builder()
    for k in range(4):
        a, d, n, L = _frame(k, w, h)
        if k != side:
            b.polyline([tuple(a), tuple(a + d * L)])
            continue
        s0 = rng.uniform(0.3, L - 0.3 - width)
        p0, p1 = a + d * s0, a + d * (s0 + width)
        b.polyline([tuple(a), tuple(p0), tuple(p0 + n * length)])
        b.polyline([tuple(p1 + n * length), tuple(p1), tuple(a + d * L)])
        b.finish.append((b.point(*(p0 + n * length)), b.point(*(p1 + n * length))))
    margin = 0.5
    x = rng.uniform(margin, w - margin)
    y = rng.uniform(margin, h - margin)
    heading = rng.uniform(-math.pi, math.pi)
    return World(map=b.build(), start=(float(x), float(y), float(heading)), seed=seed)


def _box(b: _Builder, cx: float, cy: float, sx: float, sy: float) -> None:
    b.polyline([(cx - sx / 2, cy - sy / 2), (cx + sx / 2, cy - sy / 2),
                (cx + sx / 2, cy + sy / 2), (cx - sx / 2, cy + sy / 2)], closed=True)


def room_finder_world(seed: int) -> World:
    """The room-finder world of `seed`: a hall with 2-4 side rooms, a person or an object in
    each, the robot somewhere not facing a room. A layout with no such start (a room on every
    wall, the hall small) is drawn again from the seed's next stream, so every seed has a world
    (and the seeds that had one keep it)."""
    for attempt in range(100):
        world = _room_finder_layout(seed, np.random.default_rng(seed if attempt == 0 else [seed, attempt]))
        if world is not None:
            return world
    raise RuntimeError(f"room-finder world {seed}: no layout with a start that faces no room")


def _room_finder_layout(seed: int, rng: np.random.Generator) -> World | None:
    """One draw of the room-finder world, or None when no start faces no room."""
    w, h = rng.uniform(4.0, 7.0, size=2)
    b = _Builder()
    rooms: list[dict[str, object]] = []
    n_rooms = int(rng.integers(2, 5))
    # candidate slots: (wall, offset of the room's near edge along the wall)
    slots: list[tuple[int, float]] = []
    for k in range(4):
        L = _frame(k, w, h)[3]
        pos = PANEL
        while pos + 2 * PANEL <= L + 1e-9:
            slots.append((k, pos))
            pos += 2 * PANEL  # never two rooms side by side
    chosen = sorted(rng.choice(len(slots), size=min(n_rooms, len(slots)), replace=False))
    by_wall: dict[int, list[float]] = {}
    for i in chosen:
        k, s0 = slots[int(i)]
        by_wall.setdefault(k, []).append(s0 + rng.uniform(0.0, 0.5))
    for k in range(4):
        a, d, n, L = _frame(k, w, h)
        pts = [tuple(a)]
        for s0 in sorted(by_wall.get(k, [])):
            p0, p1 = a + d * s0, a + d * (s0 + PANEL)
            pts += [tuple(p0), tuple(p0 + n * PANEL), tuple(p1 + n * PANEL), tuple(p1)]
            centre = (p0 + p1) / 2 + n * PANEL / 2
            person = bool(rng.integers(2))
            if person:
                # two feet, toes towards the entrance, 0.25 m apart
                for side in (-1, 1):
                    f = centre + d * side * 0.125
                    sx, sy = np.abs(d * 0.09 + n * 0.26)
                    _box(b, float(f[0]), float(f[1]), float(sx), float(sy))
            else:
                size = rng.uniform(0.2, 0.4)
                _box(b, float(centre[0]), float(centre[1]), size, size)
            rooms.append({"wall": k, "centre": [float(centre[0]), float(centre[1])],
                          "content": "person" if person else "object",
                          "objects": 2 if person else 1})
        pts.append(tuple(a + d * L))
        b.polyline(pts)
    # not facing a room (seed 000's assumption): along both axes the robot's perpendicular
    # foot on each wall stays 0.25 m clear of every opening
    spans = [(k, s0) for k, ss in by_wall.items() for s0 in ss]
    margin = 0.8
    for _ in range(10000):
        x = rng.uniform(margin, w - margin)
        y = rng.uniform(margin, h - margin)
        feet = {0: x, 1: y, 2: w - x, 3: h - y}
        if all(not (s0 - 0.25 <= feet[k] <= s0 + PANEL + 0.25) for k, s0 in spans):
            break
    else:
        return None
    heading = rng.uniform(-math.pi, math.pi)
    return World(map=b.build(), start=(float(x), float(y), float(heading)), rooms=rooms, seed=seed)


def _furnished(make: Callable[[int], tuple[dict, dict]], name: str) -> Callable[[int], World]:
    """A `furnished_worlds` generator as a `World`: its map, its start, its people."""
    def world(seed: int) -> World:
        doc, sim = make(seed)
        config = sim_config_from_dict(sim, file=f"{name}:{seed}")
        start = config.initial_pose or (0.0, 0.0, 0.0)
        return World(map=map_from_dict(doc, file=f"{name}:{seed}"), start=start, seed=seed, sim_config=config)
    return world


GENERATORS: dict[str, Callable[[int], World]] = {
    "escape": escape_world, "rooms": room_finder_world,
    "hall": _furnished(clutter_world, "hall"), "cafe": _furnished(cafe_world, "cafe"), "ward": _furnished(ward_world, "ward"),
    "suite": _furnished(suite_world, "suite"), "slant": _furnished(slanted_world, "slant"),
}


def make_world(spec: str) -> World:
    """`escape:SEED`, `rooms:SEED`, `hall:SEED`, `cafe:SEED`, `ward:SEED`, `suite:SEED` or
    `slant:SEED` as a `World` (the spec is checked by `parse_world`)."""
    kind, seed = parse_world(spec)
    return GENERATORS[kind](seed)


def parse_world(spec: str) -> tuple[str, int]:
    """(generator name, seed) of `KIND:SEED` (a `GENERATORS` kind); ValueError saying what is wrong."""
    kind, _, seed = spec.partition(":")
    if kind not in GENERATORS:
        raise ValueError(f"unknown world {kind!r}; use {' or '.join(f'{k}:SEED' for k in GENERATORS)}")
    try:
        return kind, int(seed)
    except ValueError:
        raise ValueError(f"{kind}: needs an integer seed, e.g. {kind}:3, got {seed!r}") from None
