"""The possible doors only the global map can prove (identify.MAP_PROVEN_KINDS): shapes the
local map alone cannot tell from furniture.

- Bays (`bays`): a gap of a door's shape between two convex corners that the jamb rules refuse,
  and a passage's mouth. In thin walls a side room's mouth between two 1 m wall
  pieces has exactly the shape of the bay between two tables by a wall. A passage's far end
  seen down the passage, one side grazed so thinly that its end floats short, is one too
  (`hidden_mouths`: from the other side's seen free end across to the grazed side's line).
- Lone end caps (`lone_caps`): a partition's end seen only face on, facing a building wall's
  face a door's width on; a person's foot looks the same.

A bay seen through opens a building's walls by the shape of its jambs' walls (identify); a block
standing against a wall, seen closed (`map_proven_kernels.block_sides`), joins the wall's
walls but opens none.

Once localised the combined map promotes them where the map's walls open
(localisation.combined.combine). The loops and their maths: map_proven_kernels.
"""

from __future__ import annotations

import numpy as np

from pico_studio.config.perception_params import IdentifyParams
from pico_studio.core.perception.door_kernels import away_from
from pico_studio.core.perception.identify_kernels import blocked_many
from pico_studio.core.perception.map_proven_kernels import bay_gaps, hidden_mouths, lone_cap_gaps
from pico_studio.core.world_model import CONVEX, FLOATING


def bays(walls: np.ndarray, prop: np.ndarray, connected: np.ndarray, objects: np.ndarray, doors: np.ndarray,
         robot: tuple[float, float], params: IdentifyParams) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Gaps (K, 4) of a door's shape between two convex corners that the jamb rules refuse: a block's
    corner or face (its cap longer than a wall's thickness, the wall shorter than a building's),
    or the gap backed or never seen through. Between two tables by a wall that is a bay; in a
    thin-walled building it is a room's mouth (a side room between two wall pieces, a hallway's
    inner end) — from the local map alone the two look the same, so it is a possible door ("bay")
    for the map to prove. The door's shape: `door_pairs` with every convex end a jamb (any cap,
    no block face), and no wall across the gap; none that is the same opening as one of `doors`
    (D, 4) (found from the same corner in about the same direction); with each gap's two jambs'
    walls (K,), (K,), for looking through it."""
    w = np.ascontiguousarray(walls, dtype=float)
    c = np.ascontiguousarray(connected, dtype=np.int64)
    p = np.ascontiguousarray(prop, dtype=np.int64)
    o = np.ascontiguousarray(objects, dtype=bool)
    d = np.ascontiguousarray(np.reshape(doors, (-1, 4)), dtype=float)
    gaps, own_a, own_b = bay_gaps(
        w, c, p, o, d, float(robot[0]), float(robot[1]), float(params.jamb_cap_max), float(params.door_wall_min_length),
        FLOATING, CONVEX, float(params.door_min_width), float(params.door_max_width), float(params.door_angle),
        float(params.door_offset), float(params.door_offset_short), float(params.door_cap_noise))
    # a passage's far end, one side's end unresolved: not crossed, not a door or a bay already
    hidden, ha, hb = hidden_mouths(w, c, p, o, float(robot[0]), float(robot[1]), float(params.door_wall_min_length),
                                   FLOATING, CONVEX,
                                   float(params.door_min_width), float(params.door_max_width), float(params.door_angle))
    if len(hidden):
        found = np.vstack([d, gaps]) if len(gaps) else d
        keep = ~blocked_many(hidden, w, ha, hb)
        if len(found):
            keep &= away_from(hidden, np.ascontiguousarray(found, dtype=float), float(params.door_min_width) / 2)
        gaps = np.vstack([gaps.reshape(-1, 4), hidden[keep]])
        own_a, own_b = np.concatenate([own_a, ha[keep]]), np.concatenate([own_b, hb[keep]])
    return gaps, own_a, own_b


def lone_caps(walls: np.ndarray, connected: np.ndarray, objects: np.ndarray, lengths: np.ndarray,
               robot: tuple[float, float], params: IdentifyParams) -> list[np.ndarray]:
    """Possible T-openings from a lone end cap: a wall no longer than a wall's thickness
    (`jamb_cap_max`), joined to nothing (a partition's end seen only face on, its sides edge-on
    or hidden), whose normal towards the robot's side meets a building wall's face (at least
    `end_face_min_length`, about square to it) a door's width on, nothing across the gap. A
    person's foot or a chair's leg looks the same: only the map can prove it."""
    g = lone_cap_gaps(np.ascontiguousarray(walls, dtype=float), np.ascontiguousarray(connected, dtype=np.int64),
                      np.ascontiguousarray(objects, dtype=bool), np.ascontiguousarray(lengths, dtype=float),
                      float(robot[0]), float(robot[1]), float(params.jamb_cap_max), float(params.door_min_width),
                      float(params.door_max_width), float(params.end_face_min_length), float(params.door_angle))
    return list(g)
