"""Reading and writing the challenge's JSON map format, with validation that names the path.

Errors (MapError, naming file and JSON path): unreadable or non-JSON file, missing or empty
`walls`, missing/non-numeric/NaN coordinates or one beyond `MAX_COORDINATE_M` (10 km), an
index out of range, a zero-length wall, a polygon that does not close. Warnings (listed on
the map, never silently fixed): duplicate points, unused points, duplicate walls, a
self-intersecting wall loop or polygon (it still loads: the simulator draws the segments as
they are, but a rasteriser's even-odd fill of such a loop is not what was meant).
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from pico_studio.errors import MapError, short
from pico_studio.json_map.model import (
    MAX_COORDINATE_M,
    GlobalMap,
    cycle_vertices,
    first_crossing,
    wall_loops,
)
from pico_studio.user_files import read_json

OBJECT_KEYS = ("cabinets", "tables")
POLYGON_KEYS = ("doors", "start_area")
KNOWN_KEYS = ("points", "walls", *OBJECT_KEYS, *POLYGON_KEYS, "finish")


def load_json_map(path: str | Path) -> GlobalMap:
    p = Path(path)
    return map_from_dict(read_json(p, MapError, "a JSON map"), file=p)


def map_from_dict(data: Any, *, file: str | Path | None = None) -> GlobalMap:
    """Validate a parsed JSON map and build the model."""
    if not isinstance(data, dict):
        raise MapError("the top level must be an object with 'points' and 'walls'", file=file)
    points, point_extras = _points(data, file)
    n = len(points)
    if "walls" not in data:
        raise MapError("missing key", file=file, field="walls")
    walls = _pairs(data["walls"], "walls", n, file)
    if len(walls) == 0:
        raise MapError("is empty: a map needs at least one wall", file=file, field="walls")
    _no_zero_length(points, walls, "walls", file)

    present = [k for k in OBJECT_KEYS if k in data]
    if len(present) > 1:
        raise MapError("has both 'cabinets' and 'tables'; use one", file=file, field=present[1])
    object_key = present[0] if present else "cabinets"
    objects = _polygons(data.get(object_key, []), object_key, n, points, file)
    doors = _polygons(data.get("doors", []), "doors", n, points, file)
    start = _polygons(data.get("start_area", []), "start_area", n, points, file)
    finish = _pairs(data.get("finish", []), "finish", n, file)

    m = GlobalMap(
        points=points,
        walls=walls,
        objects=objects,
        object_key=object_key,
        doors=doors,
        start_area=start,
        finish=finish,
        extra={k: v for k, v in data.items() if k not in KNOWN_KEYS},
        point_extras=point_extras,
        key_order=list(data.keys()),
        source=Path(file) if file is not None else None,
    )
    m.warnings = map_warnings(m)
    return m


def _points(data: dict[str, Any], file: str | Path | None) -> tuple[np.ndarray, list[dict[str, Any]]]:
    raw = data.get("points")
    if raw is None:
        raise MapError("missing key", file=file, field="points")
    if not isinstance(raw, list):
        raise MapError("must be a list of {x, y} objects", file=file, field="points")
    pts = np.zeros((len(raw), 2))
    extras: list[dict[str, Any]] = []
    for i, p in enumerate(raw):
        if not isinstance(p, dict):
            raise MapError(f"must be an object {{x, y}}, got {short(p)}", file=file, field=f"points[{i}]")
        for j, key in enumerate(("x", "y")):
            if key not in p:
                raise MapError("missing coordinate", file=file, field=f"points[{i}].{key}")
            v = p[key]
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise MapError(f"must be a number, got {short(v)}", file=file, field=f"points[{i}].{key}")
            if isinstance(v, float) and not math.isfinite(v):
                raise MapError(f"must be finite, got {v!r}", file=file, field=f"points[{i}].{key}")
            if abs(v) > MAX_COORDINATE_M:  # before float(): a 400-digit integer overflows it
                raise MapError(
                    f"{short(v) if isinstance(v, int) else f'{v:g}'} m is beyond the "
                    f"{MAX_COORDINATE_M / 1000:g} km a map may extend from the origin",
                    file=file, field=f"points[{i}].{key}",
                )
            pts[i, j] = float(v)
        extras.append({k: v for k, v in p.items() if k not in ("x", "y")})
    return pts, extras


def _pairs(raw: Any, where: str, n_points: int, file: str | Path | None) -> np.ndarray:
    if not isinstance(raw, list):
        raise MapError("must be a list of [i, j] point-index pairs", file=file, field=where)
    out = np.zeros((len(raw), 2), dtype=np.int64)
    for k, pair in enumerate(raw):
        if not isinstance(pair, list) or len(pair) != 2:
            raise MapError(f"must be a pair [i, j], got {short(pair)}", file=file, field=f"{where}[{k}]")
        for j, idx in enumerate(pair):
            if isinstance(idx, bool) or not isinstance(idx, int):
                raise MapError(f"must be a point index, got {short(idx)}", file=file, field=f"{where}[{k}][{j}]")
            if not 0 <= idx < n_points:
                raise MapError(
                    f"point index {short(idx)} out of range (the map has {n_points} points)",
                    file=file,
                    field=f"{where}[{k}][{j}]",
                )
            out[k, j] = idx
    return out


def _no_zero_length(points: np.ndarray, pairs: np.ndarray, where: str, file: str | Path | None) -> None:
    d = np.linalg.norm(points[pairs[:, 0]] - points[pairs[:, 1]], axis=1)
    bad = np.flatnonzero(d < 1e-9)
    if len(bad):
        k = int(bad[0])
        i, j = pairs[k]
        raise MapError(
            f"zero-length segment between points {i} and {j} at ({points[i, 0]:g}, {points[i, 1]:g})",
            file=file,
            field=f"{where}[{k}]",
        )


def _polygons(
    raw: Any, where: str, n_points: int, points: np.ndarray, file: str | Path | None
) -> list[np.ndarray]:
    if not isinstance(raw, list):
        raise MapError("must be a list of polygons (each a list of [i, j] segments)", file=file, field=where)
    polys: list[np.ndarray] = []
    for k, poly in enumerate(raw):
        pairs = _pairs(poly, f"{where}[{k}]", n_points, file)
        if len(pairs) < 3:
            raise MapError(f"a polygon needs at least 3 segments, got {len(pairs)}", file=file, field=f"{where}[{k}]")
        _no_zero_length(points, pairs, f"{where}[{k}]", file)
        if cycle_vertices(pairs) is None:
            raise MapError(
                "polygon is not closed: its segments do not form one closed loop "
                f"(segments {pairs.tolist()})",
                file=file,
                field=f"{where}[{k}]",
            )
        polys.append(pairs)
    return polys


MAX_LISTED = 20  # a generated map can hold 10^5 duplicates: list these, count the rest


def map_warnings(m: GlobalMap) -> list[str]:
    """Problems worth listing but not fatal: duplicate points, unused points, duplicate
    walls, self-intersecting loops. Vectorised: linear-ish in the map's size."""
    out: list[str] = []
    dup, first = _repeats(np.round(m.points, 9))
    for i in dup[:MAX_LISTED]:
        x, y = np.round(m.points[i], 9)
        out.append(f"points[{i}] duplicates points[{first[i]}] at ({x:g}, {y:g})")
    if len(dup) > MAX_LISTED:
        out.append(f"{len(dup) - MAX_LISTED} more duplicate points")
    unused = np.setdiff1d(np.arange(len(m.points)), m.used_point_indices())
    if len(unused):
        listed = ", ".join(f"points[{i}]" for i in unused[:MAX_LISTED])
        more = f" and {len(unused) - MAX_LISTED} more" if len(unused) > MAX_LISTED else ""
        out.append(f"unused points: {listed}{more}")
    # duplicate walls: same end coordinates in either direction
    seg = np.round(m.wall_segments, 9)
    a, b = seg[:, :2], seg[:, 2:]
    swap = (a[:, 0] > b[:, 0]) | ((a[:, 0] == b[:, 0]) & (a[:, 1] > b[:, 1]))
    key = np.hstack([np.where(swap[:, None], b, a), np.where(swap[:, None], a, b)])
    dup, first = _repeats(key)
    out += [f"walls[{k}] duplicates walls[{first[k]}]" for k in dup[:MAX_LISTED]]
    if len(dup) > MAX_LISTED:
        out.append(f"{len(dup) - MAX_LISTED} more duplicate walls")
    out += _crossing_warnings(m)
    return out


def _repeats(rows: np.ndarray) -> tuple[list[int], np.ndarray]:
    """Indices of the rows equal to an earlier row, in order, and for every row the index of
    the first row equal to it."""
    if len(rows) == 0:
        return [], np.zeros(0, dtype=np.int64)
    _, first, inverse = np.unique(rows, axis=0, return_index=True, return_inverse=True)
    first_of = first[inverse.reshape(-1)]
    return np.flatnonzero(first_of != np.arange(len(rows))).tolist(), first_of


def _crossing_warnings(m: GlobalMap) -> list[str]:
    """A loop of walls, or a polygon, whose segments cross each other."""
    out: list[str] = []
    for loop in wall_loops(m.walls):
        hit = first_crossing(m.points, m.walls[loop])
        if hit is not None:
            k, j, x, y = hit
            out.append(
                f"walls[{int(loop[k])}] and walls[{int(loop[j])}] of a closed wall loop cross at "
                f"({x:.3f}, {y:.3f}): the loop intersects itself"
            )
    groups = [(m.object_key, m.objects), ("doors", m.doors), ("start_area", m.start_area)]
    for key, polys in groups:
        for n, pairs in enumerate(polys):
            hit = first_crossing(m.points, pairs)
            if hit is not None:
                k, j, x, y = hit
                out.append(f"{key}[{n}]: segments {k} and {j} cross at ({x:.3f}, {y:.3f}): the polygon intersects itself")
    return out


def map_to_dict(m: GlobalMap) -> dict[str, Any]:
    """The JSON form, with unknown keys written back where they were."""
    def pairs(a: np.ndarray) -> list[list[int]]:
        return [[int(i), int(j)] for i, j in a]

    known: dict[str, Any] = {
        "points": [
            {"x": _num(x), "y": _num(y), **(m.point_extras[i] if i < len(m.point_extras) else {})}
            for i, (x, y) in enumerate(m.points)
        ],
        "walls": pairs(m.walls),
    }
    if m.objects:
        known[m.object_key] = [pairs(p) for p in m.objects]
    if m.doors:
        known["doors"] = [pairs(p) for p in m.doors]
    if m.start_area:
        known["start_area"] = [pairs(p) for p in m.start_area]
    if len(m.finish):
        known["finish"] = pairs(m.finish)
    out: dict[str, Any] = {}
    for k in m.key_order:
        if k in known:
            out[k] = known.pop(k)
        elif k in m.extra:
            out[k] = m.extra[k]
    out.update(known)
    for k, v in m.extra.items():
        out.setdefault(k, v)
    return out


def _num(v: float) -> float | int:
    r = round(float(v), 6)
    return int(r) if r == int(r) and abs(r) < 1e15 else r


def save_json_map(m: GlobalMap, path: str | Path) -> Path:
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(json.dumps(map_to_dict(m), indent=2) + "\n", encoding="utf-8")
    return p
