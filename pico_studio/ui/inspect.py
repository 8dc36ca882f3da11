"""Click-to-inspect and measuring, as plain geometry in the map frame (no viser here).

`features_near` looks at everything drawn that has numbers worth reading — global-map
walls and doors, local-map walls, corners, detected and possible doors — and returns every
one under the clicked point, nearest first, each with a short description.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pico_studio.core.geometry import point_segment_distance
from pico_studio.ui import style
from pico_studio.ui.scene_data import Prim

# Which drawn prims can be inspected, and what a hit on them is called.
SEGMENT_KINDS = {
    "map_walls": "map wall",
    "map_objects": "cabinet/table edge",
    "map_doors": "map door edge",
    "local_walls": "local-map wall",
    "current": "current-map segment",
    "combined": "combined-map wall",
    "doors": "door",
    "possible_doors": "possible door",
}
POINT_KINDS = {
    "corners": "corner", "local_endpoints": "local-map end point",
    "spike_corners": "spike corner (this scan)", "vector_corners": "vector corner (this scan)",
}


@dataclass
class Feature:
    kind: str
    distance: float  # from the click, m
    segment: np.ndarray | None = None  # (4,) when a segment
    point: np.ndarray | None = None  # (2,) when a point
    detail: str = ""

    def describe(self) -> str:
        if self.segment is not None:
            x1, y1, x2, y2 = self.segment
            length = math.hypot(x2 - x1, y2 - y1)
            angle = math.degrees(math.atan2(y2 - y1, x2 - x1))
            text = (
                f"**{self.kind}** ({x1:.3f}, {y1:.3f}) → ({x2:.3f}, {y2:.3f}), "
                f"length {length:.3f} m, direction {angle:.1f}°"
            )
        else:
            assert self.point is not None
            text = f"**{self.kind}** at ({self.point[0]:.3f}, {self.point[1]:.3f})"
        if self.detail:
            text += f", {self.detail}"
        return text + f"; {self.distance:.3f} m from the click"


def features_near(xy: tuple[float, float], prims: dict[str, Prim], radius: float = 0.25,
                  max_distance: float = 1.0) -> list[Feature]:
    """Every inspectable feature under the click (within `radius`), nearest first; when none
    is that close, the one nearest within `max_distance`."""
    p = np.array([xy], dtype=float)
    found: list[Feature] = []
    for name, kind in (POINT_KINDS | SEGMENT_KINDS).items():
        prim = prims.get(name)
        if prim is None or not len(prim):
            continue
        data = np.asarray(prim.data, dtype=float)
        if name in POINT_KINDS:
            d = np.hypot(*(data - p).T)
        else:
            d = point_segment_distance(p, data)[0]
        hits = np.flatnonzero(d <= radius)
        if not len(hits):
            hits = np.array([int(np.argmin(d))]) if d.min() <= max_distance else hits
        for i in hits:
            found.append(_feature(name, kind, prim, int(i), float(d[i])))
    found.sort(key=lambda f: (f.distance - (0.05 if f.point is not None else 0.0)))
    close = [f for f in found if f.distance <= radius]
    return close if close else found[:1]


def nearest_feature(xy: tuple[float, float], prims: dict[str, Prim], max_distance: float = 1.0) -> Feature | None:
    """The inspectable feature nearest `xy` within `max_distance` (a point within 5 cm of a
    segment wins over it)."""
    found = features_near(xy, prims, radius=0.0, max_distance=max_distance)
    return found[0] if found else None


def _feature(name: str, kind: str, prim: Prim, i: int, distance: float) -> Feature:
    if name in POINT_KINDS:
        detail = _endpoint_kind(prim.colors[i]) if prim.colors is not None else ""
        return Feature(kind, distance, point=np.asarray(prim.data[i], dtype=float).copy(), detail=detail)
    s = np.asarray(prim.data[i], dtype=float)
    detail = ""
    if name == "combined" and prim.colors is not None:
        detail = "matched" if tuple(int(v) for v in prim.colors[i]) == style.COMBINED_MATCHED else "unmatched"
    if name in ("doors", "possible_doors", "map_doors"):
        detail = f"width {math.hypot(s[2] - s[0], s[3] - s[1]):.3f} m"
    return Feature(kind, distance, segment=s.copy(), detail=detail)


def _endpoint_kind(colour: np.ndarray) -> str:
    for k, c in style.ENDPOINT.items():
        if tuple(int(v) for v in colour) == c:
            return style.ENDPOINT_NAMES[k]
    return ""


def measure_text(a: tuple[float, float], b: tuple[float, float]) -> str:
    dx, dy = b[0] - a[0], b[1] - a[1]
    return (
        f"**measure** ({a[0]:.3f}, {a[1]:.3f}) → ({b[0]:.3f}, {b[1]:.3f}): "
        f"distance {math.hypot(dx, dy):.3f} m, dx {dx:.3f} m, dy {dy:.3f} m, "
        f"direction {math.degrees(math.atan2(dy, dx)):.1f}°"
    )


def ray_to_ground(origin: tuple[float, float, float], direction: tuple[float, float, float]) -> tuple[float, float] | None:
    """Where a click ray meets the map plane z = 0 (None when it points away from it)."""
    if abs(direction[2]) < 1e-9:
        return None
    t = -origin[2] / direction[2]
    if t < 0:
        return None
    return (origin[0] + t * direction[0], origin[1] + t * direction[1])
