"""The door openings of a map: where a door is, as a pure function of its segments.

One definition for everyone who asks: the simulator's truth scores doors against these, and
once localised the combined map confirms a door where one of these is (`GlobalMap.openings`).

Door openings (`door_openings`), in this order:
1. every door polygon of the map: its centre line from jamb to jamb;
2. gaps between two *wall ends* (of walls, not cabinets or tables) that face each other, with a width within
   [min_width, max_width] and nothing solid in between; a wall end is a loose end of a thin
   wall (pointing away from its wall), or the middle of the end cap of a thick wall (a
   segment no longer than `max_thickness` whose neighbours both leave it on the same side
   and are at least twice as long, pointing along the wall, away from it); the nearest
   pairs are taken first, each end used once;
3. a wall end left over that faces a wall (not a cabinet or table) within [min_width, max_width] straight ahead:
   from the end to that wall.
4. passage mouths: where a passage (corridor, room exit) of a door's width opens into a
   larger free area — two convex corners or loose ends J1, J2 of walls (convex: the
   direction to the other lies in a sector wider than pi + `straight_tolerance`) with
   |J1 J2| in [min_width, max_width], nothing solid between them nor within `mouth_probe`
   of the middle straight ahead either side, and, measured across
   (parallel to J1 J2) at `mouth_probe` either side of the middle, a free width of at most
   |J1 J2| + `mouth_margin` on one side (the passage, walled on both sides) and at least
   |J1 J2| + min_width on the other (the room, or the open outside), and at both corners a
   wall at least `mouth_wall_length` long leaving towards the passage side (within 15 degrees of square to J1 J2),
   and the passage running on free at least `mouth_depth` in from the mouth (straight in from one
   of five points across it: a box standing in a side room leaves its sides free): the niche
   between two tables standing against a wall, their outlines fused with the wall's on a
   heightmap, is closed behind its mouth, no passage. An escape room's
   corridor has one at each end; a corridor joining a wider one has one at the junction.
   A doorway in a wall (free area on both sides) is not a mouth: rules 1-3 find it.
Openings within `min_width / 2` of an earlier one (e.g. a map door's own gap) are dropped.

The vertex graph (`vertex_graph`) is the simulator truth's too: its corners
(`sim.map_features`) are classified at its vertices.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import cv2
import numpy as np

from pico_studio.config.map_params import OpeningParams

_DEFAULTS = OpeningParams()  # the config's defaults (map.openings), declared there once
_FACING = math.cos(math.radians(45))  # a gap is "straight ahead" of an end within 45 degrees
_SQUARE = math.cos(math.radians(15))  # a passage wall leaves its mouth within 15 degrees of square
_PARALLEL = math.cos(math.radians(10))  # a thick wall's two faces run within 10 degrees of each other


@dataclass(frozen=True)
class Vertices:
    """The vertex graph of a set of segments."""

    points: np.ndarray  # (V, 2)
    seg_ends: np.ndarray  # (N, 2) vertex index of each segment's two ends
    # for every vertex: the segments leaving it and their directions (angles), as lists
    leaving: tuple[tuple[int, ...], ...]
    directions: tuple[np.ndarray, ...]
    cache: dict = field(default_factory=dict, compare=False, repr=False)


def vertex_graph(segments: np.ndarray, snap: float = 1e-3, abut: float = 0.03) -> Vertices:
    """End points closer than `snap` are one vertex. A vertex within `abut` of another segment
    (one not leaving it) is where two walls or polygons abut: it also gets
    that segment's directions, both ways on its inside (a T-junction, a rectangle's corner on
    another's face), the one way along it near an end (two corners a few mm apart), so the
    sector seen from a viewpoint is the real free one."""
    ends = segments.reshape(-1, 2)
    keys = np.round(ends / snap).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    points = ends[first]
    seg_ends = inverse.reshape(-1, 2)
    leaving: list[list[int]] = [[] for _ in range(len(points))]
    dirs: list[list[float]] = [[] for _ in range(len(points))]
    for k, (a, b) in enumerate(seg_ends):
        if a == b:
            continue
        pa, pb = points[a], points[b]
        leaving[a].append(k)
        dirs[a].append(math.atan2(pb[1] - pa[1], pb[0] - pa[0]))
        leaving[b].append(k)
        dirs[b].append(math.atan2(pa[1] - pb[1], pa[0] - pb[0]))
    neighbours = [{int(x) for k in ks for x in seg_ends[k]} for ks in leaving]
    touching = _vertices_near_segments(points, segments, seg_ends, max(abut, snap), np.arange(len(points)))
    for v, k, where in touching:
        if where < 2 and seg_ends[k, where] in neighbours[v]:
            continue  # near the end of a segment of its own polyline: a segment shorter than `abut` between
        d = math.atan2(segments[k, 3] - segments[k, 1], segments[k, 2] - segments[k, 0])
        extra = {0: [d], 1: [d + math.pi]}.get(where, [d, d + math.pi])
        leaving[v] += [k] * len(extra)
        dirs[v] += extra
    return Vertices(points, seg_ends, tuple(map(tuple, leaving)), tuple(np.array(d) for d in dirs))


def _vertices_near_segments(
    points: np.ndarray, segments: np.ndarray, seg_ends: np.ndarray, tol: float, which: np.ndarray, chunk: int = 256
) -> list[tuple[int, int, int]]:
    """(vertex, segment, where) for the vertices `which` within `tol` of a segment that does not
    leave them: where = 0 near its first end (within `tol` along it), 1 near its second, 2 inside."""
    a = segments[:, 0:2]
    ab = segments[:, 2:4] - a
    length = np.sqrt((ab * ab).sum(1))
    length2 = np.maximum(length * length, 1e-18)
    out: list[tuple[int, int, int]] = []
    for i in range(0, len(which), chunk):
        v_idx = which[i : i + chunk]
        p = points[v_idx][:, None, :]
        t = ((p - a) * ab).sum(-1) / length2
        d = p - (a + np.clip(t, 0.0, 1.0)[..., None] * ab)
        # within `tol`, the bound included, with a micrometre of slack: a map written to the mm
        # puts a vertex exactly `tol` off a segment (a table 3 cm off a wall, abut = 0.03) a hair
        # beyond it in floating point
        on = ((d * d).sum(-1) <= (tol + 1e-6) ** 2) & (length[None, :] > tol)
        on &= (seg_ends[None, :, 0] != v_idx[:, None]) & (seg_ends[None, :, 1] != v_idx[:, None])
        for v, k in zip(*np.nonzero(on), strict=True):
            along = t[v, k] * length[k]
            where = 0 if along < tol else 1 if along > length[k] - tol else 2
            out.append((int(v_idx[v]), int(k), where))
    return out


def sector_width(directions: np.ndarray, toward: float) -> float:
    """Width of the sector between consecutive `directions` (angles) that contains `toward`."""
    if len(directions) == 0:
        return 0.0
    if len(directions) == 1:
        return 2 * math.pi
    d = np.sort(np.mod(directions - toward, 2 * math.pi))
    # toward is at 0: the sector runs from the last direction (as a negative angle) to the first
    return float(d[0] + (2 * math.pi - d[-1]))


def wall_ends(graph: Vertices, segments: np.ndarray, max_thickness: float) -> tuple[np.ndarray, np.ndarray]:
    """Wall ends (E, 2) and their outward unit directions (E, 2): loose ends of thin walls and
    the middles of end caps of thick walls."""
    pts, outs = [], []
    for v, segs in enumerate(graph.leaving):
        if len(segs) == 1:
            d = graph.directions[v][0]
            pts.append(graph.points[v])
            outs.append((-math.cos(d), -math.sin(d)))
    for k, (a, b) in enumerate(graph.seg_ends):
        if len(graph.leaving[a]) != 2 or len(graph.leaving[b]) != 2:
            continue
        pa, pb = graph.points[a], graph.points[b]
        cap = pb - pa
        length = float(np.hypot(*cap))
        if length == 0.0 or length > max_thickness:
            continue
        da = _other_direction(graph, a, k)
        db = _other_direction(graph, b, k)
        if da is None or db is None or float(da @ db) < 0.7:
            continue  # the neighbours do not both leave on the same side: not an end cap
        if min(_other_length(graph, segments, a, k), _other_length(graph, segments, b, k)) < 2 * length:
            continue  # a small block (pillar, box), not the end of a wall
        if abs(float(cap @ da)) / length > 0.5:
            continue  # the neighbours run along the cap, not away from it
        # a wall's end (its two faces parallel) points along the wall, away from it, not along
        # the cap's normal: a cap askew (a sheared drawing, a wall meeting another at a slant)
        # tilts its normal by degrees, and a ray from it 1 m on passes a 0.1 m jamb. A blob's
        # faces diverge: its cap's normal is all there is
        out = -(da + db) if float(da @ db) >= _PARALLEL else np.array([-cap[1], cap[0]])
        if float(out @ da) > 0:
            out = -out
        pts.append((pa + pb) / 2)
        outs.append(tuple(out / float(np.hypot(*out))))
    if not pts:
        return np.zeros((0, 2)), np.zeros((0, 2))
    return np.array(pts, dtype=float), np.array(outs, dtype=float)


def _other_length(graph: Vertices, segments: np.ndarray, v: int, seg: int) -> float:
    for k in graph.leaving[v]:
        if k != seg:
            s = segments[k]
            return float(math.hypot(s[2] - s[0], s[3] - s[1]))
    return 0.0


def _other_direction(graph: Vertices, v: int, seg: int) -> np.ndarray | None:
    for k, ang in zip(graph.leaving[v], graph.directions[v], strict=True):
        if k != seg:
            return np.array([math.cos(ang), math.sin(ang)])
    return None


def door_openings(
    walls: np.ndarray,
    door_polygons: list[np.ndarray] | None = None,
    *,
    obstacles: np.ndarray | None = None,
    min_width: float = _DEFAULTS.door_min_width,
    max_width: float = _DEFAULTS.door_max_width,
    max_thickness: float = _DEFAULTS.max_wall_thickness,
    mouth_probe: float = _DEFAULTS.mouth_probe,
    mouth_margin: float = _DEFAULTS.mouth_margin,
    mouth_wall_length: float = _DEFAULTS.mouth_wall_length,
    straight_tolerance: float = _DEFAULTS.straight_tolerance,
    abut: float = _DEFAULTS.abut_tolerance,
    mouth_depth: float = _DEFAULTS.mouth_depth,
) -> np.ndarray:
    """The map's door openings (D, 4), each from one jamb to the other (see the module doc).

    `walls`: the wall segments (map frame), where wall ends are looked for; `obstacles`: other
    solid segments (cabinets, tables) that may block a gap but have no doors of their own;
    `door_polygons`: the map's door polygons (vertices (K, 2) each)."""
    out: list[np.ndarray] = []
    for poly in door_polygons or []:
        out.append(_door_centre_line(np.asarray(poly, dtype=float)))
    if len(walls):
        solid = walls if obstacles is None or len(obstacles) == 0 else np.vstack([walls, obstacles])
        graph = vertex_graph(walls, abut=abut)
        ends, outward = wall_ends(graph, walls, max_thickness)
        out += _paired_gaps(ends, outward, walls, solid, min_width, max_width, out)
        out += _passage_mouths(
            graph, solid, min_width, max_width, mouth_probe, mouth_margin, mouth_wall_length, straight_tolerance, out,
            mouth_depth,
        )
    return np.array(out).reshape(-1, 4)


def _passage_mouths(
    graph: Vertices,
    solid: np.ndarray,
    lo: float,
    hi: float,
    probe: float,
    margin: float,
    wall_length: float,
    straight_tolerance: float,
    found: list[np.ndarray],
    depth: float = 0.0,
) -> list[np.ndarray]:
    """Rule 4 of the module doc: where a passage of a door's width opens into a larger area."""
    cand = np.array([v for v, d in enumerate(graph.directions) if len(d) >= 1], dtype=np.int64)
    if len(cand) < 2:
        return []
    pairs = _pairs_within(graph.points[cand], lo, hi)
    out: list[np.ndarray] = []

    def convex(v: int, toward: np.ndarray) -> bool:
        p = graph.points[v]
        return sector_width(graph.directions[v], math.atan2(toward[1] - p[1], toward[0] - p[0])) > math.pi + straight_tolerance

    def along(v: int, direction: np.ndarray) -> bool:
        """A wall at least `wall_length` long leaves vertex v along `direction` (within 15 degrees)."""
        d = graph.directions[v]
        seg = solid[list(graph.leaving[v])]
        long_enough = np.hypot(seg[:, 2] - seg[:, 0], seg[:, 3] - seg[:, 1]) >= wall_length
        return bool(np.any((np.cos(d) * direction[0] + np.sin(d) * direction[1] > _SQUARE) & long_enough))

    def free_width(origin: np.ndarray, u: np.ndarray) -> float:
        ang = math.atan2(u[1], u[0])
        r = cast_rays(tuple(origin), np.array([ang, ang + math.pi]), solid)
        return float(r.sum())

    for i, j, width in pairs:
        a, b = graph.points[cand[i]], graph.points[cand[j]]
        if not (convex(cand[i], b) and convex(cand[j], a)):
            continue
        u = (b - a) / width
        eps = 1e-3
        if cast_rays(tuple(a + u * eps), np.array([math.atan2(u[1], u[0])]), solid)[0] < width - 2 * eps:
            continue  # something solid between the two corners
        mid, n = (a + b) / 2, np.array([-u[1], u[0]])
        ahead = math.atan2(n[1], n[0])
        if cast_rays(tuple(mid), np.array([ahead, ahead + math.pi]), solid).min() < probe:
            continue  # not free on both sides: the line runs along (or into) a wall
        sides = [free_width(mid + s * probe * n, u) for s in (1.0, -1.0)]
        narrow, wide = min(sides), max(sides)
        if not (narrow <= width + margin and wide >= width + lo):
            continue
        inward = n if sides[0] <= sides[1] else -n  # towards the passage
        if not (along(cand[i], inward) and along(cand[j], inward)):
            continue  # the passage is not walled at both corners: two unrelated corners
        if depth > 0 and max(cast_rays(tuple(a + f * (b - a)), np.array([math.atan2(inward[1], inward[0])]), solid)[0]
                             for f in (0.1, 0.3, 0.5, 0.7, 0.9)) < depth:
            continue  # closed within `depth` all across: a niche (between two tables by a wall), no passage
        if any(float(np.hypot(*(mid - (f[:2] + f[2:]) / 2))) < lo / 2 for f in found + out):
            continue
        out.append(np.concatenate([a, b]))
    return out


def _pairs_within(pts: np.ndarray, lo: float, hi: float, chunk: int = 512) -> list[tuple[int, int, float]]:
    """(i, j, |P_j - P_i|) for i < j with lo <= |P_j - P_i| <= hi, nearest first (ties in row
    order): `chunk` rows of the distance matrix at a time, so a heightmap's thousands of
    vertices never need the whole (V x V) matrix in memory."""
    found: list[tuple[int, int, float]] = []
    for i0 in range(0, len(pts), chunk):
        diff = pts[None, :, :] - pts[i0 : i0 + chunk, None, :]
        dist = np.hypot(diff[..., 0], diff[..., 1])
        rows, cols = np.nonzero((dist >= lo) & (dist <= hi))
        keep = cols > rows + i0
        found += [(int(r) + i0, int(c), float(d)) for r, c, d in
                  zip(rows[keep], cols[keep], dist[rows[keep], cols[keep]], strict=True)]
    found.sort(key=lambda ijd: ijd[2])  # stable: equal distances keep the row order
    return found


def _door_centre_line(v: np.ndarray) -> np.ndarray:
    c, axis, size, _ = door_frame(v)
    return np.concatenate([c - axis * size / 2, c + axis * size / 2])


def _paired_gaps(
    ends: np.ndarray,
    outward: np.ndarray,
    walls: np.ndarray,
    segments: np.ndarray,
    lo: float,
    hi: float,
    found: list[np.ndarray],
) -> list[np.ndarray]:
    out: list[np.ndarray] = []

    def duplicate(a: np.ndarray, b: np.ndarray) -> bool:
        mid = (a + b) / 2
        return any(float(np.hypot(*(mid - (f[:2] + f[2:]) / 2))) < lo / 2 for f in found + out)

    def clear(a: np.ndarray, b: np.ndarray) -> bool:
        d = b - a
        dist = float(np.hypot(*d))
        # start a little off each end so the end's own wall does not count
        eps = 1e-3
        t = cast_rays(tuple(a + d / dist * eps), np.array([math.atan2(d[1], d[0])]), segments)[0]
        return t >= dist - 2 * eps

    n = len(ends)
    used = np.zeros(n, dtype=bool)
    if n >= 2:
        diff = ends[None, :, :] - ends[:, None, :]
        dist = np.hypot(diff[..., 0], diff[..., 1])
        with np.errstate(invalid="ignore", divide="ignore"):
            unit = diff / dist[..., None]
        facing_i = (unit * outward[:, None, :]).sum(-1) > _FACING
        facing_j = (-unit * outward[None, :, :]).sum(-1) > _FACING
        ok = (dist >= lo) & (dist <= hi) & facing_i & facing_j
        ok &= np.triu(np.ones((n, n), dtype=bool), 1)
        for i, j in sorted(zip(*np.nonzero(ok), strict=True), key=lambda ij: dist[ij[0], ij[1]]):
            if used[i] or used[j] or not clear(ends[i], ends[j]) or duplicate(ends[i], ends[j]):
                continue
            used[i] = used[j] = True
            out.append(np.concatenate([ends[i], ends[j]]))
    for i in np.flatnonzero(~used):
        a, o = ends[i], outward[i]
        start, angle = tuple(a + o * 1e-3), np.array([math.atan2(o[1], o[0])])
        t = cast_rays(start, angle, segments)[0] + 1e-3
        t_wall = cast_rays(start, angle, walls)[0] + 1e-3
        if lo <= t <= hi and t_wall == t:  # facing a wall, not a cabinet or table
            b = a + o * t
            if not duplicate(a, b):
                out.append(np.concatenate([a, b]))
    return out


def door_frame(vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, float]:
    """(centre, unit axis along the door, size along it, thickness) of a door polygon: its
    minimum-area bounding rectangle, so a heightmap's ragged door outline works as well as a
    JSON map's rectangle."""
    (cx, cy), (w, h), deg = cv2.minAreaRect(np.asarray(vertices, dtype=np.float32))
    a = math.radians(deg)
    axis = np.array([math.cos(a), math.sin(a)])
    if h > w:
        axis, w, h = np.array([-axis[1], axis[0]]), h, w
    # the rectangle comes from float32 maths: measure size and centre again in float64
    v = np.asarray(vertices, dtype=float)
    along = v @ axis
    normal = np.array([-axis[1], axis[0]])
    across = v @ normal
    center = axis * (along.max() + along.min()) / 2 + normal * (across.max() + across.min()) / 2
    return center, axis, float(along.max() - along.min()), float(across.max() - across.min())


def cast_rays(origin: tuple[float, float], angles: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """Distance along rays from `origin` at arbitrary map-frame `angles` to the nearest of
    `segments` (map frame), inf where none: the plain (K x N) test, for a few rays."""
    angles = np.asarray(angles, dtype=float)
    if len(segments) == 0:
        return np.full(angles.shape, np.inf)
    c = np.cos(angles)[:, None]
    s = np.sin(angles)[:, None]
    p1 = segments[None, :, 0:2] - np.asarray(origin)
    d = segments[None, :, 2:4] - segments[None, :, 0:2]
    with np.errstate(divide="ignore", invalid="ignore"):
        den = c * d[..., 1] - s * d[..., 0]
        t = (p1[..., 0] * d[..., 1] - p1[..., 1] * d[..., 0]) / den
        # where along the segment the ray crosses: cross(p1, (c, s)) / den
        u = (p1[..., 0] * s - p1[..., 1] * c) / den
    ok = (t >= 0.0) & (u >= 0.0) & (u <= 1.0)
    return np.where(ok, t, np.inf).min(axis=1)
