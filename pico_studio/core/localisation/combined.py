"""The combined map: the robot's local map brought into the global map's frame, tagged.

With the robot's pose in the global map g and in the zero (odometry) frame z, a zero-frame
point p lands at  compose(g, invert(z)) (x) p  in the global frame. Each local wall is sampled
every `sample_spacing`; it is *matched* when at least `match_fraction` of its samples lie
within `match_distance` of a map wall (the distance field says), otherwise *unmatched* — an
obstacle, a person, a moved object. A map wall is *seen* once `seen_hits` explained beams
have landed on it (counted by the tracker while not lost). Doors and possible doors are
carried into the global frame and *confirmed* by the map when they are one of the map's door
openings (`GlobalMap.openings`: its doors, the gaps between its wall ends, its passage mouths —
the openings the simulator's truth scores against): the middles within `door_confirm_distance`
and the directions within `door_confirm_angle` (`geometry.door_matches`, the truth's test). The
rest are unconfirmed (a gap between two tables, a person beside a wall, a table's corner facing
a wall). A possible door of
kind "end_face" (a T-opening still waiting for the evidence of several scans) or "bay" (a
door's shape between block corners: a table bay or a thin-walled room's mouth) that the map
confirms is *promoted* to a door (`door_promoted`): the map is that evidence. A "jamb" (a
building wall's end with nothing ahead, its other side out of view) is promoted to the map
opening at its end, leaving along it or, failing that, across its end (a passage's mouth)
(`opening_at_jamb`), unless a door stands there already.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pico_studio.config.localisation_params import CombinedParams
from pico_studio.core.geometry import compose, door_matches, invert, transform_segments
from pico_studio.core.localisation.combined_kernels import walls_on_map as on_map_kernel
from pico_studio.core.localisation.distance_field import DistanceField
from pico_studio.core.localisation.matcher import Pose
from pico_studio.core.perception.identify import JAMB_KIND, MAP_PROVEN_KINDS


@dataclass
class CombinedMap:
    walls: np.ndarray  # (W, 4) local walls in the global frame
    wall_matched: np.ndarray  # (W,) bool: on the map
    map_wall_seen: np.ndarray  # (N,) bool per wall of the global map (GlobalMap.walls order)
    doors: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))  # (D, 4) global frame
    possible_doors: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))  # (E, 4)
    possible_door_kind: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=object))
    door_confirmed: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))  # (D,) by a map door
    possible_door_confirmed: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))  # (E,)
    door_promoted: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))  # (D,) a possible door the map made one

    def to_dict(self) -> dict[str, Any]:
        return {
            "walls": self.walls.tolist(),
            "wall_matched": self.wall_matched.tolist(),
            "map_wall_seen": self.map_wall_seen.tolist(),
            "doors": self.doors.tolist(),
            "possible_doors": self.possible_doors.tolist(),
            "possible_door_kind": [str(k) for k in self.possible_door_kind],
            "door_confirmed": self.door_confirmed.tolist(),
            "possible_door_confirmed": self.possible_door_confirmed.tolist(),
            "door_promoted": self.door_promoted.tolist(),
        }


def zero_to_global(global_pose: Pose, zero_pose: Pose) -> Pose:
    """The transform taking zero-frame coordinates into the global map, given the robot's pose
    in both frames."""
    return compose(global_pose, invert(zero_pose))


def walls_on_map(walls: np.ndarray, dfield: DistanceField, params: CombinedParams) -> np.ndarray:
    """(W,) bool: whether each wall (global frame) lies on the map (the samples' loop:
    combined_kernels.walls_on_map)."""
    return on_map_kernel(dfield.field, dfield.x0, dfield.y0, dfield.resolution,
                         np.ascontiguousarray(walls, dtype=float).reshape(-1, 4), float(params.sample_spacing),
                         float(params.match_distance), float(params.match_fraction))


def confirmed_by_map(doors: np.ndarray, openings: np.ndarray, params: CombinedParams) -> np.ndarray:
    """(D,) bool: doors (global frame) that are one of the map's door openings (K, 4), their
    middles within `door_confirm_distance` and directions within `door_confirm_angle`."""
    if len(doors) == 0 or len(openings) == 0:
        return np.zeros(len(doors), dtype=bool)
    match = door_matches(np.ascontiguousarray(doors, dtype=float).reshape(-1, 4),
                         np.ascontiguousarray(openings, dtype=float).reshape(-1, 4),
                         float(params.door_confirm_distance), math.cos(params.door_confirm_angle))
    return np.asarray(match.any(axis=1), dtype=bool)


def combine(
    global_pose: Pose,
    zero_pose: Pose,
    local_walls: np.ndarray,
    dfield: DistanceField,
    seen_hits: np.ndarray,
    n_map_walls: int,
    params: CombinedParams,
    *,
    doors: np.ndarray | None = None,
    possible_doors: np.ndarray | None = None,
    possible_door_kind: np.ndarray | list[str] | None = None,
    map_openings: np.ndarray | None = None,
) -> CombinedMap:
    """The combined map for one step; every input array in the zero frame but `map_openings`
    (`GlobalMap.openings`, in the global frame)."""
    t = zero_to_global(global_pose, zero_pose)
    walls = transform_segments(np.asarray(local_walls, dtype=float).reshape(-1, 4), t)
    kinds = np.asarray(possible_door_kind if possible_door_kind is not None else [], dtype=object)
    found, possible = _carry(doors, t), _carry(possible_doors, t)
    openings = np.zeros((0, 4)) if map_openings is None else np.asarray(map_openings, dtype=float).reshape(-1, 4)
    door_ok = confirmed_by_map(found, openings, params)
    possible_ok = confirmed_by_map(possible, openings, params)
    # a T-opening that passed every test but the evidence over scans (possible kind "end_face"),
    # or a door's shape the furniture rules refused ("bay"), is a door once the map has an
    # opening there: the map is the evidence
    promote = (possible_ok & np.isin(kinds, MAP_PROVEN_KINDS) if len(kinds) == len(possible)
               else np.zeros(len(possible), dtype=bool))
    # a jamb whose other side is out of view is the door of the map opening at its end, leaving
    # along it, unless a door already stands there
    promoted = possible[promote]
    if len(kinds) == len(possible) and len(openings):
        for m in np.flatnonzero(kinds == JAMB_KIND).tolist():
            opening = opening_at_jamb(possible[m], openings, params)
            if opening is None:
                continue
            known = np.concatenate([found, promoted])
            if len(known) and confirmed_by_map(known, opening[None], params).any():
                continue
            promote[m] = True
            promoted = np.concatenate([promoted, opening[None]])
    return CombinedMap(
        walls=walls,
        wall_matched=walls_on_map(walls, dfield, params),
        map_wall_seen=np.asarray(seen_hits[:n_map_walls] >= params.seen_hits, dtype=bool),
        doors=np.concatenate([found, promoted]),
        possible_doors=possible[~promote],
        possible_door_kind=kinds[~promote] if len(kinds) == len(possible) else kinds,
        door_confirmed=np.concatenate([door_ok, np.ones(int(promote.sum()), dtype=bool)]),
        possible_door_confirmed=possible_ok[~promote],
        door_promoted=np.concatenate([np.zeros(len(found), dtype=bool), np.ones(int(promote.sum()), dtype=bool)]),
    )


def opening_at_jamb(jamb: np.ndarray, openings: np.ndarray, params: CombinedParams) -> np.ndarray | None:
    """The map opening (4,), from the end nearest the jamb's point P (within
    `door_confirm_distance`) to its other end, leaving P's way: within `door_confirm_angle` of
    the jamb's direction (P to its far point: a door in the wall's line); failing that, across
    it, within that angle of square to it (a passage's mouth: the wall is a hallway's side
    ending there); None when there is none."""
    p, q = jamb[:2], jamb[2:]
    d = q - p
    norm = float(np.hypot(*d))
    if norm <= 1e-12:
        return None
    u = d / norm
    cos_max, sin_max = math.cos(params.door_confirm_angle), math.sin(params.door_confirm_angle)
    for way in ("along", "across"):
        best, best_dist = None, float(params.door_confirm_distance)
        for a, b in ((openings[:, :2], openings[:, 2:]), (openings[:, 2:], openings[:, :2])):
            dist = np.hypot(*(a - p).T)
            v = b - a
            along = (v @ u) / np.maximum(np.hypot(*v.T), 1e-12)
            dist[(along < cos_max) if way == "along" else (np.abs(along) > sin_max)] = np.inf  # leaving another way
            k = int(np.argmin(dist))
            if dist[k] <= best_dist:
                best, best_dist = np.concatenate([a[k], b[k]]), float(dist[k])
        if best is not None:
            return best
    return None


def _carry(segments: np.ndarray | None, t: Pose) -> np.ndarray:
    if segments is None:
        return np.zeros((0, 4))
    return transform_segments(np.asarray(segments, dtype=float).reshape(-1, 4), t)


__all__ = ["CombinedMap", "combine", "confirmed_by_map", "opening_at_jamb", "walls_on_map", "zero_to_global"]
