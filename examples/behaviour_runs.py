"""Draw the reference behaviours' runs: true trajectories over the maps -> docs/behaviours.png.

Four panels: the escape room of `escape_room.png`, a generated escape room (pico_studio/evaluation/worlds.py,
seed 4), a generated room-finder world (seed 6) with the counts found, and the hospital tour
0, 3, 1 on hospital_2019 (perceptor + localisation, a moving box in the corridor). Each
panel's title gives the outcome: escaped / rooms / visited, collisions, simulated time.

    python examples/behaviour_runs.py [--out docs/behaviours.png]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np

ROOT = Path(__file__).resolve().parents[1]

from pico_studio.config.tree import Config  # noqa: E402
from pico_studio.core.behaviours.registry import make_behaviour  # noqa: E402
from pico_studio.evaluation.runner import make_perceptor, run_behaviour  # noqa: E402
from pico_studio.evaluation.worlds import escape_world, room_finder_world  # noqa: E402
from pico_studio.json_map import GlobalMap, load_map  # noqa: E402
from pico_studio.json_map.draw import _TOP as TITLE_PX  # noqa: E402
from pico_studio.json_map.draw import draw_map  # noqa: E402
from pico_studio.json_map.grid import GridFrame  # noqa: E402
from pico_studio.sim import Simulator  # noqa: E402
from pico_studio.sim.sim_config import SimConfigFile, load_sim_config  # noqa: E402

MAPS = ROOT / "pico_studio" / "data" / "maps"
SIZE = 620


class Recorder:
    """Wraps a behaviour: records the true pose at every step."""

    def __init__(self, behaviour, sim):
        self.b, self.sim, self.xy = behaviour, sim, []

    def __getattr__(self, name):
        return getattr(self.b, name)

    def __setattr__(self, name, value):
        if name in ("b", "sim", "xy"):
            object.__setattr__(self, name, value)
        else:
            setattr(self.b, name, value)

    def step(self, wm, laser, odometry, now, *, ok=True):  # the behaviour protocol
        self.xy.append(self.sim.truth.pose[:2])
        return self.b.step(wm, laser, odometry, now, ok=ok)


def panel(m: GlobalMap, xy: list, title: str) -> np.ndarray:
    img = draw_map(m, max_size=SIZE, title=title)
    # the frame draw_map draws in (json_map/draw.py): 0.5 m margin, the longer side fitted
    pts = m.points[m.used_point_indices()]
    lo, hi = pts.min(axis=0) - 0.5, pts.max(axis=0) + 0.5
    px_per_m = max(10.0, min(200.0, (SIZE - TITLE_PX) / max(float(max(hi - lo)), 1e-6)))
    frame = GridFrame.map_server((img.shape[0] - TITLE_PX, img.shape[1]), 1.0 / px_per_m,
                                 (float(lo[0]), float(lo[1])))
    if len(xy) >= 2:
        uv = np.round(frame.to_pixel(np.array(xy)) - 0.5).astype(np.int32) + [0, TITLE_PX]
        cv2.polylines(img, [uv], False, (40, 160, 40), 2, cv2.LINE_AA)
        cv2.circle(img, tuple(int(v) for v in uv[0]), 6, (40, 160, 40), -1, cv2.LINE_AA)
        cv2.circle(img, tuple(int(v) for v in uv[-1]), 6, (0, 0, 200), 2, cv2.LINE_AA)
    return img


def run(m: GlobalMap, spec: str, sim: Simulator, seconds: float, cfg: Config, localise: bool = False):
    start = sim.truth.pose
    rec = Recorder(make_behaviour(spec, cfg.behaviour, m, start), sim)
    perceptor = make_perceptor(cfg, m, start, localise=True) if localise else None
    r = run_behaviour(sim, rec, seconds=seconds, perceptor=perceptor)
    return r, rec.xy


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "docs" / "behaviours.png"))
    args = ap.parse_args()
    cfg = Config()
    uncertain = SimConfigFile(uncertain_odom=True)
    panels = []

    m = load_map(MAPS / "escape_room.png")
    r, xy = run(m, "escape-room", Simulator(m, cfg.sim, uncertain, seed=0), 120, cfg)
    panels.append(panel(m, xy, f"escape_room.png: escaped {r['escaped']} in {r['escape_seconds']:.1f} s, "
                               f"collisions {r['collisions']}"))

    w = escape_world(4)
    r, xy = run(w.map, "escape-room", Simulator(w.map, cfg.sim, uncertain, seed=4, initial_pose=w.start), 120, cfg)
    panels.append(panel(w.map, xy, f"escape seed 4: escaped {r['escaped']} in {r['escape_seconds']:.1f} s, "
                                   f"collisions {r['collisions']}"))

    w = room_finder_world(6)
    r, xy = run(w.map, "room-finder", Simulator(w.map, cfg.sim, uncertain, seed=6, initial_pose=w.start), 300, cfg)
    panels.append(panel(w.map, xy, f"room finder seed 6: objects {[x['objects'] for x in r['rooms']]} "
                                   f"(true {[x['objects'] for x in w.rooms]}), collisions {r['collisions']}"))

    m = load_map(MAPS / "hospital_2019.json")
    sc = load_sim_config(ROOT / "examples" / "sim_configs" / "hospital_2019_sim.json")
    r, xy = run(m, "hospital:0,3,1", Simulator(m, cfg.sim, sc, seed=0), 400, cfg, localise=True)
    panels.append(panel(m, xy, f"hospital 0,3,1: visited {r['cabinets_visited']} in {r['sim_seconds']:.0f} s, "
                               f"collisions {r['collisions']}"))

    h = max(p.shape[0] for p in panels)
    padded = [cv2.copyMakeBorder(p, 0, h - p.shape[0], 0, 10, cv2.BORDER_CONSTANT, value=(255, 255, 255)) for p in panels]
    top = np.hstack(padded[:2])
    bottom = np.hstack(padded[2:])
    wmax = max(top.shape[1], bottom.shape[1])
    top = cv2.copyMakeBorder(top, 0, 0, 0, wmax - top.shape[1], cv2.BORDER_CONSTANT, value=(255, 255, 255))
    bottom = cv2.copyMakeBorder(bottom, 0, 0, 0, wmax - bottom.shape[1], cv2.BORDER_CONSTANT, value=(255, 255, 255))
    cv2.imwrite(args.out, np.vstack([top, bottom]))
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
