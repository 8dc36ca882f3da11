"""The world model: plain data out of the perceptor, easy to draw and to serialise.

Frames: `points`, `current_map`, `spike_corners`, `vector_corners` are in the robot frame;
everything else (local map, corners, doors, pose) is in the robot's *zero frame* (the pose
of the first odometry reading), unless the field's name says otherwise. See
docs/ARCHITECTURE.md, "The perceptor contract".

Local-map end-point properties (`endpoint_property`): 0 floating (a loose end, its true end
not seen), 1 connected (to another wall, not a corner seen from here), 2 convex, 3 concave.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np

FLOATING, CONNECTED, CONVEX, CONCAVE = 0, 1, 2, 3
ENDPOINT_PROPERTY_NAMES = ("floating", "connected", "convex", "concave")

Pose = tuple[float, float, float]


def _empty(cols: int) -> np.ndarray:
    return np.zeros((0, cols)) if cols else np.zeros(0)


@dataclass
class LocalMap:
    """The local map's walls (W, 4) in the zero frame and their end points' properties (W, 2)."""

    walls: np.ndarray = field(default_factory=lambda: _empty(4))
    endpoint_property: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=np.int64))


@dataclass
class WorldModel:
    time: float = 0.0
    pose: Pose = (0.0, 0.0, 0.0)  # in the zero frame
    zero_pose: Pose | None = None  # the odometry reading taken as zero
    # laser, robot frame
    points: np.ndarray = field(default_factory=lambda: _empty(2))  # (M, 2) valid laser points
    beam_valid: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))  # (n,)
    proximity: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))  # (n,)
    too_close: bool = False
    current_map: np.ndarray = field(default_factory=lambda: _empty(4))  # (S, 4) robot frame
    # (S, 3) per current_map wall, its line (normal angle alpha, distance rho) in the robot frame:
    # var(alpha) rad^2, var(rho) m^2, cov(alpha, rho) (segment_refit: Pfister et al. 2003)
    current_map_covariance: np.ndarray = field(default_factory=lambda: _empty(3))
    # (S,) per current_map wall, the rms distance (m) of its scan points from its fitted line
    current_map_rms: np.ndarray = field(default_factory=lambda: np.zeros(0))
    spike_corners: np.ndarray = field(default_factory=lambda: _empty(2))  # (K, 2) robot frame
    vector_corners: np.ndarray = field(default_factory=lambda: _empty(2))  # (V, 2) robot frame
    vector_corner_inner: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))  # (V,)
    # local map, zero frame
    local_map: LocalMap = field(default_factory=lambda: LocalMap())
    corners: np.ndarray = field(default_factory=lambda: _empty(2))  # (C, 2)
    corner_convex: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))  # (C,)
    doors: np.ndarray = field(default_factory=lambda: _empty(4))  # (D, 4)
    # (D,) "jambs" (two convex ends), "end_face" (T-opening) or "bay" (seen through: identify.bay_deep_rays)
    door_kind: list[str] = field(default_factory=list)
    # (D,) bool: the door is remembered (door_memory: found from places apart, open still), not
    # found in this scan
    door_remembered: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    object_walls: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))  # (W,) local wall is a small object's
    objects: np.ndarray = field(default_factory=lambda: _empty(4))  # (O, 4) static objects' boxes xmin, ymin, xmax, ymax
    dynamic_obstacles: np.ndarray = field(default_factory=lambda: _empty(4))  # (K, 4) moving objects' boxes
    dynamic_points: np.ndarray = field(default_factory=lambda: _empty(2))  # (M, 2) their points, robot frame
    possible_doors: np.ndarray = field(default_factory=lambda: _empty(4))  # (E, 4)
    possible_door_kind: list[str] = field(default_factory=list)  # (E,) one of POSSIBLE_DOOR_KINDS
    # higher-level estimates
    entrance: tuple[float, float] | None = None  # (angle, distance) from the robot
    hallway: bool = False  # the entrance estimate comes from two parallel walls
    room: dict[str, Any] = field(default_factory=dict)  # seed 000: side jump, edges, objects
    laser_motion: Pose | None = None  # robot motion since the previous scan, from the laser
    laser_motion_matches: int = 0
    pose_correction_quality: float = 0.0  # share of the scan explained by the local map after matching
    pose_corrected: bool = False  # the pose was corrected by matching the scan to the local map
    # filled by localisation, not by the perceptor
    global_pose: Pose | None = None
    localisation_quality: float = 0.0
    lost: bool = False
    combined: Any = None  # a localisation CombinedMap
    # plugins' extra named outputs, "plugin/name" -> (K, 2) points or (K, 4) segments, zero frame
    extras: dict[str, np.ndarray] = field(default_factory=dict)
    # bookkeeping
    timings_ms: dict[str, float] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """JSON-friendly: arrays become nested lists, tuples lists."""
        out: dict[str, Any] = {}
        for f in fields(self):
            out[f.name] = _plain(getattr(self, f.name))
        return out


def _plain(v: Any) -> Any:
    if isinstance(v, LocalMap):
        return {"walls": v.walls.tolist(), "endpoint_property": v.endpoint_property.tolist()}
    if hasattr(v, "to_dict"):
        return v.to_dict()
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, (np.floating, np.integer, np.bool_)):
        return v.item()
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    if isinstance(v, dict):
        return {str(k): _plain(x) for k, x in v.items()}
    return v
