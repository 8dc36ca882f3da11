"""What each layer draws, as plain numpy in the map frame (no viser here).

The page's view is the global map's frame. Robot-frame data (laser points, current map,
proximity) is placed at `Studio.robot_pose_in_map`; zero-frame data (local map, corners,
doors, behaviour target/plan) at `Studio.zero_frame_in_map`. Every field of the WorldModel
contract (`core.world_model.WorldModel`, typed: no guessing at fields) that is None or
empty draws nothing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from pico_studio.config import Config
from pico_studio.core.geometry import compose, invert, transform_points, transform_segments
from pico_studio.core.localisation.combined import CombinedMap
from pico_studio.core.world_model import WorldModel
from pico_studio.json_map import GlobalMap
from pico_studio.ui import style
from pico_studio.ui.clock import is_replay
from pico_studio.ui.runtime import Studio
from pico_studio.ui.timeline import FrameRecord

CIRCLE_SIDES = 48


@dataclass
class Prim:
    """One drawable: segments (N, 4) or points (N, 2), with one colour or one per item."""

    kind: str  # "segments" | "points" | "label"
    data: np.ndarray  # a label: its anchor (1, 2), or (0, 2) for none
    colors: np.ndarray | None = None  # (N, 3) uint8 per item; None = the prim's fixed colour
    text: str = ""  # a label's text

    def __len__(self) -> int:
        return len(self.data)


@dataclass(frozen=True)
class PrimSpec:
    name: str
    kind: str
    color: style.RGB
    thickness: float = style.THICK_LAYER  # screen pixels
    point_size: float = style.POINT_PX  # screen pixels (the page rescales as the view zooms)
    per_item: bool = False  # coloured item by item (the page's node is made so from the start)


@dataclass(frozen=True)
class LayerSpec:
    key: str
    label: str
    prims: tuple[PrimSpec, ...]
    static: bool = False  # drawn once per map rather than per frame
    default_on: bool = True


S, P, L = "segments", "points", "label"
# Drawn from the bottom up in this order (markers last, on top); line thickness and point
# sizes in screen pixels.
LAYERS: tuple[LayerSpec, ...] = (
    LayerSpec("map", "Global map", (
        PrimSpec("map_start", S, style.MAP_START, 3.0),
        PrimSpec("map_walls", S, style.MAP_WALL, style.THICK_MAP),
        PrimSpec("map_objects", S, style.MAP_OBJECT, 3.0),
        PrimSpec("map_fronts", S, style.MAP_OBJECT_FRONT, style.THICK_MAP),
        PrimSpec("map_doors", S, style.MAP_DOOR, 3.0),
        # the map's door openings (GlobalMap.openings): what the combined map confirms doors against
        PrimSpec("map_openings", S, style.MAP_OPENING, 2.0),
    ), static=True),
    LayerSpec("reference_map", "Reference map (true poses)", (
        PrimSpec("reference_map", P, style.REFERENCE_MAP, point_size=3.0),
    )),
    LayerSpec("sim_world", "Simulated doors / moving objects", (PrimSpec("sim_world", S, style.SIM_WORLD, 3.0),)),
    LayerSpec("trail", "Trail", (PrimSpec("trail", S, style.TRAIL, 2.0),)),
    LayerSpec("truth_path", "True trajectory (recording)", (PrimSpec("truth_path", S, style.TRUE_PATH, 2.0),)),
    LayerSpec("combined", "Combined map", (
        # as thick as the map's walls, so that its dashes hide the wall under them
        PrimSpec("combined_unseen", S, style.COMBINED_UNSEEN, style.THICK_MAP),
        PrimSpec("combined", S, style.COMBINED_MATCHED, 3.0, per_item=True),
    )),
    LayerSpec("local", "Local map", (
        PrimSpec("local_walls", S, style.LOCAL_WALL, 2.0),
        PrimSpec("local_endpoints", P, style.ENDPOINT[0], point_size=6.0, per_item=True),
        PrimSpec("corners", P, style.ENDPOINT[2], point_size=9.0, per_item=True),
    )),
    LayerSpec("current", "Current map segments", (PrimSpec("current", S, style.CURRENT_MAP, 2.0),)),
    LayerSpec("doors", "Doors and possible doors", (
        PrimSpec("doors", S, style.DOOR, 4.0),
        PrimSpec("possible_doors", S, style.POSSIBLE_DOOR, 3.0, per_item=True),
    )),
    LayerSpec("ab_diff", "A/B diff (B vs pinned A)", (  # filled by ui.ab_panel, not frame_prims
        PrimSpec("diff_walls_lost", S, style.DIFF_LOST, 5.0),
        PrimSpec("diff_walls_added", S, style.DIFF_ADDED, 5.0),
        PrimSpec("diff_doors_lost", S, style.DIFF_LOST, 7.0),
        PrimSpec("diff_doors_added", S, style.DIFF_ADDED, 7.0),
        PrimSpec("diff_corners_lost", P, style.DIFF_LOST, point_size=0.12),
        PrimSpec("diff_corners_added", P, style.DIFF_ADDED, point_size=0.12),
    )),
    LayerSpec("proximity", "Proximity bubble", (
        PrimSpec("bubble", S, style.PROXIMITY, 2.0),
        PrimSpec("flagged", S, style.PROXIMITY_FLAGGED, 1.5),
    )),
    LayerSpec("laser", "Laser points", (PrimSpec("laser", P, style.LASER, point_size=3.0),)),
    LayerSpec("entrance", "Entrance estimate / hallway", (PrimSpec("entrance", S, style.ENTRANCE, 3.0, per_item=True),)),
    LayerSpec("room", "Side room watch", (
        PrimSpec("room_side", S, style.ROOM_SIDE, 2.0, per_item=True),
        PrimSpec("room_label", L, style.ROOM_SIDE),
    )),
    LayerSpec("scan_corners", "Scan corners (spike / vector)", (
        PrimSpec("spike_corners", P, style.SPIKE_CORNER, point_size=8.0),
        PrimSpec("vector_corners", P, style.VECTOR_CORNER_INNER, point_size=7.0, per_item=True),
    ), default_on=False),
    LayerSpec("behaviour", "Behaviour target / plan", (
        PrimSpec("plan", S, style.BEHAVIOUR_PLAN, 2.0),
        PrimSpec("target", P, style.BEHAVIOUR_TARGET, point_size=12.0),
    )),
    LayerSpec("plugins", "Plugin outputs", (
        PrimSpec("plugin_segments", S, style.PLUGIN_OUTPUT, 2.0),
        PrimSpec("plugin_points", P, style.PLUGIN_OUTPUT, point_size=6.0),
    )),
    LayerSpec("robot", "Robot footprint", (
        PrimSpec("robot_true", S, style.ROBOT_TRUE, 2.0),
        PrimSpec("robot_estimate", S, style.ROBOT_ESTIMATE, 2.0),
    )),
)
PRIM_SPECS = {p.name: p for layer in LAYERS for p in layer.prims}


def _segs(a: Any) -> np.ndarray:
    if a is None:
        return np.zeros((0, 4))
    a = np.asarray(a, dtype=float)
    return a.reshape(-1, 4) if a.size else np.zeros((0, 4))


def _pts(a: Any) -> np.ndarray:
    if a is None:
        return np.zeros((0, 2))
    a = np.asarray(a, dtype=float)
    return a.reshape(-1, 2) if a.size else np.zeros((0, 2))


def polygon_segments(vertices: np.ndarray) -> np.ndarray:
    """A closed polygon's vertices (K, 2) as its K edges (K, 4)."""
    v = np.asarray(vertices, dtype=float)
    return np.hstack([v, np.roll(v, -1, axis=0)]) if len(v) >= 2 else np.zeros((0, 4))


def map_prims(m: GlobalMap | None) -> dict[str, Prim]:
    """The static global-map layer."""
    if m is None:
        empty = Prim(S, np.zeros((0, 4)))
        return {p.name: empty for p in LAYERS[0].prims}
    objects = [m.segments_of(p) for p in m.objects]
    doors = [polygon_segments(v) for v in m.door_polygons]
    start = [polygon_segments(v) for v in m.start_polygons]
    return {
        "map_walls": Prim(S, m.wall_segments),
        "map_objects": Prim(S, np.vstack(objects) if objects else np.zeros((0, 4))),
        "map_fronts": Prim(S, m.object_fronts),
        "map_doors": Prim(S, np.vstack(doors) if doors else np.zeros((0, 4))),
        "map_openings": Prim(S, m.openings()),
        "map_start": Prim(S, np.vstack(start) if start else np.zeros((0, 4))),
    }


def footprint_segments(pose: tuple[float, float, float], length: float, width: float) -> np.ndarray:
    """The robot's box and a heading tick (centre to front), map frame."""
    hl, hw = length / 2, width / 2
    box = np.array([[hl, hw], [-hl, hw], [-hl, -hw], [hl, -hw]])
    segs = np.vstack([polygon_segments(box), [[0.0, 0.0, hl + 0.1, 0.0]]])
    return transform_segments(segs, pose)


def circle_segments(radius: float, sides: int = CIRCLE_SIDES) -> np.ndarray:
    t = np.linspace(0.0, 2 * math.pi, sides + 1)
    v = np.column_stack([radius * np.cos(t), radius * np.sin(t)])
    return np.hstack([v[:-1], v[1:]])


def laser_points_robot(frame: FrameRecord) -> np.ndarray:
    """The scan's points in the robot frame: the WorldModel's when there is one, else the raw
    valid returns."""
    if frame.wm is not None:
        return _pts(frame.wm.points)
    return frame.laser.points if frame.laser is not None else np.zeros((0, 2))


def footprint_size(cfg: Config) -> tuple[float, float]:
    """PICO's footprint as the simulator's base declares it."""
    base = cfg.sim.base
    return (float(base.footprint_length), float(base.footprint_width))


def frame_prims(studio: Studio, frame: FrameRecord | None) -> dict[str, Prim]:
    """Every dynamic prim for one frame, map frame. Missing data -> empty prims."""
    out: dict[str, Prim] = {
        spec.name: Prim(spec.kind, np.zeros((0, 4 if spec.kind == S else 2)))
        for layer in LAYERS if not layer.static for spec in layer.prims
    }
    if studio.reference is not None:  # a replay with true poses: empty until built
        out["reference_map"] = Prim(P, studio.reference.points())
    if frame is None:
        return out
    wm = frame.wm
    robot = studio.robot_pose_in_map(frame)
    zero = studio.zero_frame_in_map(frame)
    length, width = footprint_size(studio.cfg)

    out["laser"] = Prim(P, transform_points(laser_points_robot(frame), robot))
    if frame.sim_world is not None:
        out["sim_world"] = Prim(S, frame.sim_world)
    if frame.truth_pose is not None:
        out["robot_true"] = Prim(S, footprint_segments(frame.truth_pose, length, width))
    g = wm.global_pose if wm is not None else None
    if g is not None:
        out["robot_estimate"] = Prim(S, footprint_segments(tuple(map(float, g)), length, width))
    elif frame.truth_pose is None:
        # no truth and no localisation: the only pose there is, drawn as the estimate
        out["robot_estimate"] = Prim(S, footprint_segments(robot, length, width))

    out["truth_path"] = Prim(S, truth_path(studio.source))
    trail = [f.map_xy for f in _trail_frames(studio, frame) if f.map_xy is not None]
    if len(trail) >= 2:
        t = np.asarray(trail)
        segs = np.hstack([t[:-1], t[1:]])
        jump = np.hypot(segs[:, 2] - segs[:, 0], segs[:, 3] - segs[:, 1]) > 1.0
        out["trail"] = Prim(S, segs[~jump])

    if wm is None:
        return out
    out["current"] = Prim(S, transform_segments(_segs(wm.current_map), robot))
    out.update(_scan_corner_prims(wm, robot))
    if zero is not None:
        lm = wm.local_map
        walls = _segs(lm.walls)
        out["local_walls"] = Prim(S, transform_segments(walls, zero))
        if len(walls):
            ends = transform_points(walls.reshape(-1, 2), zero)
            kinds = np.asarray(lm.endpoint_property, dtype=int).reshape(-1)
            kinds = kinds if len(kinds) == len(ends) else np.zeros(len(ends), int)
            out["local_endpoints"] = Prim(P, ends, _palette(kinds, style.ENDPOINT))
        corners = _pts(wm.corners)
        if len(corners):
            flags = np.asarray(wm.corner_convex, dtype=bool).reshape(-1)
            kinds = np.where(flags, 2, 3) if len(flags) == len(corners) else np.full(len(corners), 2)
            out["corners"] = Prim(P, transform_points(corners, zero), _palette(kinds, style.ENDPOINT))
    out.update(_door_prims(wm, zero))
    out.update(plugin_prims(wm.extras, zero))
    behaviour_frame = _behaviour_frame_in_map(frame, robot, zero)
    if behaviour_frame is not None:
        if frame.behaviour_target is not None:
            out["target"] = Prim(P, transform_points(_pts(frame.behaviour_target), behaviour_frame))
        if frame.behaviour_plan is not None:
            plan = transform_points(_pts(frame.behaviour_plan), behaviour_frame)
            if len(plan) >= 2:
                out["plan"] = Prim(S, np.hstack([plan[:-1], plan[1:]]))

    out.update(_combined_prims(wm.combined, studio.global_map))

    flags = wm.proximity
    radius = float(studio.cfg.perception.proximity.radius)
    if radius > 0:
        out["bubble"] = Prim(S, transform_segments(circle_segments(radius), robot))
    if flags is not None and frame.laser is not None:
        f = np.asarray(flags, dtype=bool).reshape(-1)
        r = np.asarray(frame.laser.ranges, dtype=float)
        if len(f) == len(r) and f.any():
            a = frame.laser.angles[f]
            ends = np.column_stack([r[f] * np.cos(a), r[f] * np.sin(a)])
            beams = np.hstack([np.zeros_like(ends), ends])
            out["flagged"] = Prim(S, transform_segments(beams, robot))

    entrance = wm.entrance
    if entrance is not None:
        angle, dist = float(entrance[0]), float(entrance[1])
        seg = np.array([[0.0, 0.0, dist * math.cos(angle), dist * math.sin(angle)]])
        colour = style.HALLWAY if wm.hallway else style.ENTRANCE
        out["entrance"] = Prim(S, transform_segments(seg, robot), np.array([colour], np.uint8))
    out.update(_room_prims(wm.room, robot, float(studio.cfg.perception.rooms.side_angle)))
    return out


def _scan_corner_prims(wm: WorldModel, robot: tuple[float, float, float]) -> dict[str, Prim]:
    """Seed 002's corner detectors on this scan (robot frame): spikes, and vector corners
    coloured inner / outer."""
    out = {"spike_corners": Prim(P, transform_points(_pts(wm.spike_corners), robot))}
    vc = _pts(wm.vector_corners)
    flags = np.asarray(wm.vector_corner_inner, dtype=bool).reshape(-1)
    flags = flags if len(flags) == len(vc) else np.ones(len(vc), bool)
    colours = np.where(flags[:, None], style.VECTOR_CORNER_INNER, style.VECTOR_CORNER_OUTER).astype(np.uint8)
    out["vector_corners"] = Prim(P, transform_points(vc, robot), colours)
    return out


def plugin_prims(extras: dict[str, np.ndarray], zero: tuple[float, float, float] | None) -> dict[str, Prim]:
    """Every plugin's extra outputs (zero frame): (K, 2) ones as points, (K, 4) as segments."""
    if zero is None or not extras:
        return {}
    arrays = [np.asarray(a, dtype=float) for a in extras.values()]
    segs = [a for a in arrays if a.ndim == 2 and a.shape[1] == 4]
    pts = [a for a in arrays if a.ndim == 2 and a.shape[1] == 2]
    return {"plugin_segments": Prim(S, transform_segments(np.vstack(segs) if segs else np.zeros((0, 4)), zero)),
            "plugin_points": Prim(P, transform_points(np.vstack(pts) if pts else np.zeros((0, 2)), zero))}


def _door_prims(wm: WorldModel, zero: tuple[float, float, float] | None) -> dict[str, Prim]:
    """Doors and possible doors (coloured by kind): the combined map's, in the global frame,
    when localised; else the perceptor's, zero frame placed on the map."""
    combined = wm.combined
    kinds: Any
    if combined is not None:
        doors = _segs(combined.doors)
        possible = _segs(combined.possible_doors)
        kinds = combined.possible_door_kind
    elif zero is not None:
        doors = transform_segments(_segs(wm.doors), zero)
        possible = transform_segments(_segs(wm.possible_doors), zero)
        kinds = wm.possible_door_kind
    else:
        return {}
    names = [str(k) for k in (kinds if kinds is not None else [])]
    names = names if len(names) == len(possible) else [""] * len(possible)
    colours = np.array([style.POSSIBLE_DOOR_KIND.get(k, style.POSSIBLE_DOOR) for k in names], np.uint8).reshape(-1, 3)
    # the perceptor's doors come first (the combined map's promoted ones after): a remembered
    # one, not found in this scan, in its own colour
    remembered = np.zeros(len(doors), dtype=bool)
    mine = np.asarray(wm.door_remembered, dtype=bool).reshape(-1)[: len(doors)]
    remembered[: len(mine)] = mine
    door_colours = np.where(remembered[:, None], style.DOOR_REMEMBERED, style.DOOR).astype(np.uint8).reshape(-1, 3)
    return {"doors": Prim(S, doors, door_colours), "possible_doors": Prim(S, possible, colours)}


def _combined_prims(combined: CombinedMap | None, global_map: GlobalMap | None) -> dict[str, Prim]:
    """The combined map: local walls in the global frame (matched / unmatched), and the map's
    walls never seen so far, dashed."""
    if combined is None:
        return {}
    cw = _segs(combined.walls)
    matched = np.asarray(combined.wall_matched, dtype=bool).reshape(-1)
    matched = matched if len(matched) == len(cw) else np.ones(len(cw), bool)
    colors = np.where(matched[:, None], style.COMBINED_MATCHED, style.COMBINED_UNMATCHED).astype(np.uint8)
    out = {"combined": Prim(S, cw, colors)}
    seen = combined.map_wall_seen
    if global_map is not None and seen is not None:
        seen = np.asarray(seen, dtype=bool).reshape(-1)
        if len(seen) == len(global_map.walls):
            dashes, owner = map_wall_dashes(global_map)
            out["combined_unseen"] = Prim(S, dashes[~seen[owner]])
    return out


_dash_cache: tuple[GlobalMap, np.ndarray, np.ndarray] | None = None


def map_wall_dashes(m: GlobalMap) -> tuple[np.ndarray, np.ndarray]:
    """The map's walls cut into dashes (K, 4) and each dash's wall index (K,); computed once
    per map."""
    global _dash_cache
    if _dash_cache is None or _dash_cache[0] is not m:
        _dash_cache = (m, *dash_segments(m.wall_segments, style.DASH, style.DASH_GAP))
    return _dash_cache[1], _dash_cache[2]


def dash_segments(segs: np.ndarray, dash: float, gap: float) -> tuple[np.ndarray, np.ndarray]:
    """Cut segments (N, 4) into dashes of `dash` metres every `dash + gap`, laid out from each
    segment's middle (so a dash always covers the middle; a segment shorter than a dash stays
    whole). Returns the dashes (K, 4) and their segment's index (K,)."""
    segs = _segs(segs)
    if not len(segs):
        return np.zeros((0, 4)), np.zeros(0, dtype=int)
    a, b = segs[:, :2], segs[:, 2:]
    length = np.hypot(*(b - a).T)
    period = dash + gap
    m = np.ceil(length / 2 / period).astype(int)  # dashes each side of the middle one
    owner = np.repeat(np.arange(len(segs)), 2 * m + 1)
    k = np.concatenate([np.arange(-j, j + 1) for j in m])
    half = length[owner] / 2
    lo = np.clip(k * period - dash / 2, -half, half)
    hi = np.clip(k * period + dash / 2, -half, half)
    keep = hi - lo > 1e-9
    owner, lo, hi = owner[keep], lo[keep], hi[keep]
    mid = (a[owner] + b[owner]) / 2
    unit = (b[owner] - a[owner]) / np.maximum(length[owner], 1e-12)[:, None]
    return np.hstack([mid + lo[:, None] * unit, mid + hi[:, None] * unit]), owner


def room_text(room: dict[str, Any]) -> str:
    """Seed 000's side-room watch in one line: side range, its jump, objects in view."""
    side, jump = room.get("side_range"), room.get("jump")
    parts = [f"side {side:.2f} m" if side is not None else "side –"]
    parts.append(f"jump {round(jump, 2) + 0.0:+.2f} m" if jump is not None else "jump –")  # no "-0.00"
    parts.append(f"objects {int(room.get('objects') or 0)}")
    if room.get("room"):
        parts.append("ROOM")
    return " · ".join(parts)


def _room_prims(room: dict[str, Any], robot: tuple[float, float, float], side_angle: float) -> dict[str, Prim]:
    """The watched side beam (coloured when its range jumped) and the watch's label beside
    the robot."""
    if not room:
        return {}
    out = {"room_label": Prim(L, np.array([[robot[0] + 0.3, robot[1] + 0.3]]), text=room_text(room))}
    side = room.get("side_range")
    if side is not None:
        beam = np.array([[0.0, 0.0, side * math.cos(side_angle), side * math.sin(side_angle)]])
        colour = style.ROOM_JUMP if room.get("room") else style.ROOM_SIDE
        out["room_side"] = Prim(S, transform_segments(beam, robot), np.array([colour], np.uint8))
    return out


def _behaviour_frame_in_map(frame: FrameRecord, robot: tuple[float, float, float],
                            zero: tuple[float, float, float] | None) -> tuple[float, float, float] | None:
    """The map-frame pose of the frame a behaviour's target and plan are in."""
    kind = frame.behaviour_frame
    if kind == "global":
        return (0.0, 0.0, 0.0)
    if kind == "odom":
        pose = frame.behaviour_pose
        return compose(robot, invert(tuple(map(float, pose)))) if pose is not None else None
    return zero


def _palette(kinds: np.ndarray, colours: dict[int, style.RGB]) -> np.ndarray:
    table = np.array([colours.get(k, colours[0]) for k in range(max(colours) + 1)], dtype=np.uint8)
    return table[np.clip(kinds, 0, len(table) - 1)]


def _trail_frames(studio: Studio, frame: FrameRecord) -> list[FrameRecord]:
    n = studio.cfg.ui.trail_length
    if n <= 0 or not len(studio.timeline):
        return []
    first = studio.timeline[0].index
    return studio.timeline.up_to(frame.index - first, n)


_truth_cache: tuple[Any, np.ndarray] | None = None


def truth_path(source: Any) -> np.ndarray:
    """A replay's whole recorded true trajectory (CARMEN's corrected poses, a simulated run's
    truth) as segments (K, 4), jumps over 1 m left out; empty for other sources."""
    global _truth_cache
    if not is_replay(source) or not source.has_truth:
        return np.zeros((0, 4))
    if _truth_cache is None or _truth_cache[0] is not source.recording:
        xy = np.array([p.pose[:2] for p in source.recording.truth], dtype=float).reshape(-1, 2)
        segs = np.hstack([xy[:-1], xy[1:]]) if len(xy) >= 2 else np.zeros((0, 4))
        keep = np.hypot(segs[:, 2] - segs[:, 0], segs[:, 3] - segs[:, 1]) < 1.0
        _truth_cache = (source.recording, segs[keep])
    return _truth_cache[1]
