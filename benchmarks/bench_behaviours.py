"""The behaviours' quality matrix (issue 7), measured in the simulator against its truth.

- escape room: the 20 generated escape rooms (pico_studio/evaluation/worlds.py, seeds 0-19) and
  `escape_room.png` (the simulator's start and 4 random starts inside the room, 0.5 m from
  the walls), uncertain odometry, 120 simulated s:
  escaped with 0 collisions in >= 19 of 20 is the bar;
- room finder: generated room-finder worlds: every room found, object counts right (the same
  sequence, rotated to the starting corner), 0 collisions;
- hospital tour: hospital_2019 (examples/sim_configs/hospital_2019_sim.json: a moving box in
  the corridor) and restaurant_2024 (its sim config's moving object), uncertain odometry,
  three targets in a given order, with the perceptor + localisation (`--dead-reckoning`: on
  odometry from the start pose only): all visited in order, 0 collisions.

    python benchmarks/bench_behaviours.py [--escape 20] [--rooms 20] [--hospital-seeds 2] [--json]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import statistics
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]

import numpy as np  # noqa: E402

from pico_studio.config.tree import Config  # noqa: E402
from pico_studio.core.behaviours.escape_room import EscapeRoom  # noqa: E402
from pico_studio.core.behaviours.hospital import HospitalTour  # noqa: E402
from pico_studio.core.behaviours.room_finder import RoomFinder  # noqa: E402
from pico_studio.core.geometry import point_segment_distance  # noqa: E402
from pico_studio.evaluation.runner import make_perceptor, run_behaviour  # noqa: E402
from pico_studio.evaluation.worlds import escape_world, room_finder_world  # noqa: E402
from pico_studio.json_map import load_json_map  # noqa: E402
from pico_studio.sim import Simulator  # noqa: E402
from pico_studio.sim.sim_config import SimConfigFile, load_sim_config  # noqa: E402

MAPS = ROOT / "pico_studio" / "data" / "maps"
HOSPITAL_RUNS = [
    ("hospital_2019", MAPS / "hospital_2019.json", ROOT / "examples" / "sim_configs" / "hospital_2019_sim.json", [0, 3, 1]),
    ("hospital_2019", MAPS / "hospital_2019.json", ROOT / "examples" / "sim_configs" / "hospital_2019_sim.json", [2, 1, 3]),
    ("restaurant_2024", MAPS / "restaurant_2024.json", MAPS / "restaurant_2024_sim.json", [1, 3, 4]),
    ("restaurant_2024", MAPS / "restaurant_2024.json", MAPS / "restaurant_2024_sim.json", [0, 2, 3]),
]
UNCERTAIN = SimConfigFile(uncertain_odom=True)


def escape_matrix(cfg: Config, n: int) -> list[dict[str, Any]]:
    rows = []
    for seed in range(n):
        w = escape_world(seed)
        sim = Simulator(w.map, cfg.sim, UNCERTAIN, seed=seed, initial_pose=w.start)
        r = run_behaviour(sim, EscapeRoom(cfg.behaviour), seconds=120.0)
        rows.append({"world": f"escape seed {seed}", **_pick(r, "escaped", "escape_seconds", "collisions", "state")})
    try:
        from pico_studio.json_map import load_map  # type: ignore[attr-defined]
    except ImportError:
        rows.append({"world": "escape_room.png", "skipped": "this build has no heightmap loader (json_map.load_map)"})
        return rows
    m = load_map(MAPS / "escape_room.png")
    for seed in range(5):
        start = inside_start(m, seed) if seed else None  # seed 0: the simulator's own start
        sim = Simulator(m, cfg.sim, UNCERTAIN, seed=seed, initial_pose=start)
        r = run_behaviour(sim, EscapeRoom(cfg.behaviour), seconds=120.0)
        rows.append({"world": f"escape_room.png seed {seed}", **_pick(r, "escaped", "escape_seconds", "collisions", "state")})
    return rows


def inside_start(m: Any, seed: int, clearance: float = 0.5) -> tuple[float, float, float]:
    """A random pose inside the room of an escape-room map, `clearance` from every wall:
    rays in the four axis directions must all meet a wall (the hallway's open end lets one
    direction out at most when standing in its line, so the room is where all four close)."""
    rng = np.random.default_rng(seed)
    walls = m.wall_segments
    x0, y0, x1, y1 = m.bounds
    for _ in range(10000):
        p = np.array([rng.uniform(x0, x1), rng.uniform(y0, y1)])
        if point_segment_distance(p[None, :], walls).min() < clearance:
            continue
        if all(_ray_hits(p, d, walls) for d in ((1, 0), (-1, 0), (0, 1), (0, -1))):
            return (float(p[0]), float(p[1]), float(rng.uniform(-np.pi, np.pi)))
    raise RuntimeError("no free place inside the room")


def _ray_hits(p: np.ndarray, d: tuple[int, int], walls: np.ndarray) -> bool:
    a, b = walls[:, :2], walls[:, 2:]
    e = b - a
    den = d[0] * e[:, 1] - d[1] * e[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((a[:, 0] - p[0]) * e[:, 1] - (a[:, 1] - p[1]) * e[:, 0]) / den
        u = ((a[:, 0] - p[0]) * d[1] - (a[:, 1] - p[1]) * d[0]) / den
    return bool(np.any((t > 0) & (u >= 0) & (u <= 1)))


def rooms_matrix(cfg: Config, n: int) -> list[dict[str, Any]]:
    rows = []
    for seed in range(n):
        w = room_finder_world(seed)
        sim = Simulator(w.map, cfg.sim, UNCERTAIN, seed=seed, initial_pose=w.start)
        r = run_behaviour(sim, RoomFinder(cfg.behaviour), seconds=300.0)
        expected = [room["objects"] for room in w.rooms]
        got = [room["objects"] for room in r["rooms"]]
        right = len(got) == len(expected) and any(got == expected[k:] + expected[:k] for k in range(len(expected)))
        rows.append({"world": f"rooms seed {seed}", "expected": expected, "found": got, "right": right,
                     **_pick(r, "collisions", "state", "sim_seconds")})
    return rows


def hospital_matrix(cfg: Config, seeds: int, localise: bool) -> list[dict[str, Any]]:
    rows = []
    for name, map_path, sim_cfg, order in HOSPITAL_RUNS:
        m = load_json_map(map_path)
        sc = dataclasses.replace(load_sim_config(sim_cfg), uncertain_odom=True)
        for seed in range(seeds):
            sim = Simulator(m, cfg.sim, sc, seed=seed)
            start = sim.truth.pose
            perceptor = make_perceptor(cfg, m, start, localise=True) if localise else None
            b = HospitalTour(cfg.behaviour, m, order, initial_pose=start)
            t0 = time.perf_counter()
            r = run_behaviour(sim, b, seconds=400.0, perceptor=perceptor)
            rows.append({"world": f"{name} {order} seed {seed}", "order": order,
                         "in_order": r["cabinets_visited"] == order, "wall_s": round(time.perf_counter() - t0, 1),
                         **_pick(r, "cabinets_visited", "collisions", "state", "sim_seconds", "notes")})
    return rows


def _pick(r: dict[str, Any], *keys: str) -> dict[str, Any]:
    return {k: r[k] for k in keys}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--escape", type=int, default=20, help="generated escape rooms (seeds 0..N-1)")
    ap.add_argument("--rooms", type=int, default=20, help="generated room-finder worlds")
    ap.add_argument("--hospital-seeds", type=int, default=2, help="simulator seeds per hospital run")
    ap.add_argument("--dead-reckoning", action="store_true", help="hospital on odometry only (no perceptor/localisation)")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    cfg = Config()
    out: dict[str, Any] = {}
    t0 = time.perf_counter()
    out["escape"] = escape_matrix(cfg, args.escape)
    out["rooms"] = rooms_matrix(cfg, args.rooms)
    out["hospital"] = hospital_matrix(cfg, args.hospital_seeds, not args.dead_reckoning)
    gen = [r for r in out["escape"] if r["world"].startswith("escape seed")]
    png = [r for r in out["escape"] if r["world"].startswith("escape_room.png") and "skipped" not in r]
    ok = lambda r: r["escaped"] and r["collisions"] == 0  # noqa: E731
    times = [r["escape_seconds"] for r in gen if r["escaped"]]
    out["summary"] = {
        "escape_generated": f"{sum(map(ok, gen))}/{len(gen)} escaped with 0 collisions"
                            + (f", escape time median {statistics.median(times):.1f} s, max {max(times):.1f} s" if times else ""),
        "escape_room_png": f"{sum(map(ok, png))}/{len(png)}" if png else "skipped (no heightmap loader)",
        "room_finder": f"{sum(r['right'] and r['collisions'] == 0 for r in out['rooms'])}/{len(out['rooms'])} "
                       f"worlds with every room found, counts right, 0 collisions "
                       f"({sum(len(r['expected']) for r in out['rooms'])} rooms)",
        "hospital": f"{sum(r['in_order'] and r['collisions'] == 0 for r in out['hospital'])}/{len(out['hospital'])} "
                    f"runs visited all three in order with 0 collisions"
                    + (" (dead reckoning)" if args.dead_reckoning else " (perceptor + localisation)"),
        "wall_seconds": round(time.perf_counter() - t0, 1),
    }
    if args.json:
        print(json.dumps(out))
        return 0
    for section in ("escape", "rooms", "hospital"):
        print(f"== {section}")
        for r in out[section]:
            print("  " + ", ".join(f"{k}={v}" for k, v in r.items()))
    print("== summary")
    for k, v in out["summary"].items():
        print(f"  {k}: {v}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
