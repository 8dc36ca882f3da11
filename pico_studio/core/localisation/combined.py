"""The combined map: the robot's local map brought into the global map's frame, tagged.

With the robot's pose in the global map g and in the zero (odometry) frame z, a zero-frame
point p lands at  compose(g, invert(z)) (x) p  in the global frame. Each local wall is sampled
every `sample_spacing`; it is *matched* when at least `match_fraction` of its samples lie
within `match_distance` of a map wall (the distance field says), otherwise *unmatched* — an
obstacle, a person, a moved object. A map wall is *seen* once `seen_hits` explained beams
have landed on it (counted by the tracker while not lost). Doors and possible doors are
carried into the global frame as they are.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pico_studio.config.localisation_params import CombinedParams
from pico_studio.core.geometry import compose, invert, segment_lengths, transform_segments
from pico_studio.core.localisation.distance_field import DistanceField
from pico_studio.core.localisation.matcher import Pose


@dataclass
class CombinedMap:
    walls: np.ndarray  # (W, 4) local walls in the global frame
    wall_matched: np.ndarray  # (W,) bool: on the map
    map_wall_seen: np.ndarray  # (N,) bool per wall of the global map (GlobalMap.walls order)
    doors: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))  # (D, 4) global frame
    possible_doors: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))  # (E, 4)
    possible_door_kind: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=object))

    def to_dict(self) -> dict[str, Any]:
        return {
            "walls": self.walls.tolist(),
            "wall_matched": self.wall_matched.tolist(),
            "map_wall_seen": self.map_wall_seen.tolist(),
            "doors": self.doors.tolist(),
            "possible_doors": self.possible_doors.tolist(),
            "possible_door_kind": [str(k) for k in self.possible_door_kind],
        }


def zero_to_global(global_pose: Pose, zero_pose: Pose) -> Pose:
    """The transform taking zero-frame coordinates into the global map, given the robot's pose
    in both frames."""
    return compose(global_pose, invert(zero_pose))


def walls_on_map(walls: np.ndarray, dfield: DistanceField, params: CombinedParams) -> np.ndarray:
    """(W,) bool: whether each wall (global frame) lies on the map."""
    if len(walls) == 0:
        return np.zeros(0, dtype=bool)
    n = np.maximum(2, np.ceil(segment_lengths(walls) / params.sample_spacing).astype(int) + 1)
    owner = np.repeat(np.arange(len(walls)), n)
    t = np.concatenate([np.linspace(0.0, 1.0, k) for k in n])
    a, b = walls[owner, 0:2], walls[owner, 2:4]
    samples = a + t[:, None] * (b - a)
    on = dfield.distance(samples) <= params.match_distance
    fraction = np.bincount(owner, weights=on, minlength=len(walls)) / n
    return fraction >= params.match_fraction


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
) -> CombinedMap:
    """The combined map for one step; every input array in the zero frame."""
    t = zero_to_global(global_pose, zero_pose)
    walls = transform_segments(np.asarray(local_walls, dtype=float).reshape(-1, 4), t)
    kinds = np.asarray(possible_door_kind if possible_door_kind is not None else [], dtype=object)
    return CombinedMap(
        walls=walls,
        wall_matched=walls_on_map(walls, dfield, params),
        map_wall_seen=np.asarray(seen_hits[:n_map_walls] >= params.seen_hits, dtype=bool),
        doors=_carry(doors, t),
        possible_doors=_carry(possible_doors, t),
        possible_door_kind=kinds,
    )


def _carry(segments: np.ndarray | None, t: Pose) -> np.ndarray:
    if segments is None:
        return np.zeros((0, 4))
    return transform_segments(np.asarray(segments, dtype=float).reshape(-1, 4), t)


__all__ = ["CombinedMap", "combine", "walls_on_map", "zero_to_global"]
