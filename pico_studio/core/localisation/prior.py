"""The initial pose: a box of possible positions and a range of headings in the global map.

Sources, in order of preference:
1. a pose given by the caller (the simulator config's `initial_pose`, heading included) or by
   the config (`prior.source: pose`) — uncertain by `position_uncertainty` around it;
2. the map's `start_area` polygon — its bounding box (about 1 x 1 m in the challenges);
3. neither: where the source says the robot starts, when it knows (`prior_pose`: the
   simulator's chosen start, the origin facing +x by the official simulator's default), else
   the whole map (a symmetric building localises to its mirror image from there).
The heading is unknown (any) unless given: by the caller's pose, or `heading_known` in the
config; a given heading is uncertain by `heading_uncertainty`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pico_studio.config.localisation_params import PriorParams
from pico_studio.json_map.model import GlobalMap


@dataclass(frozen=True)
class PosePrior:
    """Where the robot may be: centre, half-widths in x and y, heading centre and half-range.

    `heading_range >= pi` means the heading is unknown.
    """

    x: float
    y: float
    half_x: float
    half_y: float
    a: float = 0.0
    heading_range: float = math.pi
    origin: str = "start_area"  # start_area | pose | map

    @property
    def heading_known(self) -> bool:
        return self.heading_range < math.pi


def initial_prior(
    global_map: GlobalMap,
    params: PriorParams,
    pose: tuple[float, float, float] | None = None,
) -> PosePrior:
    """The prior for `global_map`; `pose` (e.g. from a sim config) overrides the config."""
    heading_range = params.heading_uncertainty if params.heading_known else math.pi
    if pose is not None:
        u = params.position_uncertainty
        return PosePrior(pose[0], pose[1], u, u, pose[2], params.heading_uncertainty, "pose")
    if params.source == "pose":
        u = params.position_uncertainty
        return PosePrior(params.x, params.y, u, u, params.a, heading_range, "pose")

    polygons = global_map.start_polygons
    if polygons:
        v = polygons[0]
        lo, hi = v.min(axis=0), v.max(axis=0)
        c = (lo + hi) / 2
        return PosePrior(float(c[0]), float(c[1]), float(hi[0] - c[0]), float(hi[1] - c[1]),
                         params.a, heading_range, "start_area")

    x0, y0, x1, y1 = global_map.bounds
    return PosePrior((x0 + x1) / 2, (y0 + y1) / 2, (x1 - x0) / 2, (y1 - y0) / 2,
                     params.a, heading_range, "map")


def prior_pose(given: tuple[float, float, float] | None, global_map: GlobalMap, params: PriorParams,
               start: tuple[float, float, float] | None) -> tuple[float, float, float] | None:
    """The pose to hand `initial_prior`: `given` (a sim config's `initial_pose`) when there is
    one; else, when neither the config (`source: pose`) nor the map (`start_area`) says where
    the robot starts, the source's own `start` (the simulator's: what a user placing the robot
    knows); else None (the config or the start area decides)."""
    if given is not None:
        return given
    if params.source == "pose" or global_map.start_polygons:
        return None
    return start
