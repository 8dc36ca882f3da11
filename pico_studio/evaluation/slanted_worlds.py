"""Slanted worlds (`world: slant:SEED`): a ward or a suite (`furnished_worlds`) drawn askew, so
its walls meet at 76-84 degrees, not 90.

Every generated family and every built-in map is drawn square; a rule that only holds for
walls at right angles (an end cap's normal taken for its wall's direction, a face "square
to" a wall) passes them all. The shear x' = x + k y (or y' = y + k x), |k| in [0.1, 0.25],
keeps every wall straight and every doorway open, tilts one family of walls by
atan(k) (6-14 degrees) and with them the caps, doorways and the people's paths; the tables
and beds become parallelograms, as a drawing askew would.

`slanted_world(seed)` returns `(map_doc, sim_doc)` like the furnished worlds: even seeds a
ward, odd seeds a suite, each of that seed.
"""

from __future__ import annotations

import copy

import numpy as np

from pico_studio.evaluation.furnished_worlds import suite_world, ward_world


def slanted_world(seed: int) -> tuple[dict, dict]:
    rng = np.random.default_rng(10_000 + seed)
    doc, sim = (ward_world if seed % 2 == 0 else suite_world)(seed)
    doc, sim = copy.deepcopy(doc), copy.deepcopy(sim)
    k = float(rng.uniform(0.1, 0.25) * rng.choice([-1.0, 1.0]))
    along_x = bool(rng.integers(2))

    def shear(x: float, y: float) -> tuple[float, float]:
        return (x + k * y, y) if along_x else (x, y + k * x)

    for p in doc["points"]:
        p["x"], p["y"] = (round(v, 4) for v in shear(float(p["x"]), float(p["y"])))
    for pose in [sim.get("initial_pose")] + [o.get(key) for o in sim.get("objects", [])
                                             for key in ("init_pose", "final_pose")]:
        if pose:
            pose[0], pose[1] = shear(float(pose[0]), float(pose[1]))
    return doc, sim


__all__ = ["slanted_world"]
