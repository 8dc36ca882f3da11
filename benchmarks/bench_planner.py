"""The hospital planner's A* on hospital_2019 and restaurant_2024: compiled vs its own Python.

The plans timed are the ones the hospital behaviour makes: from the map's start to the spot
in front of every cabinet / every side of every table (all candidate spots of
`HospitalTour`), between every pair of those spots, and as many plans again between random
free cells (seeded). Each plan is timed `--repeats`
times (CPU time, `time.process_time`); reported per map: median and worst ms of the
compiled A*, and the same for the uncompiled Python of the same function (`.py_func`, on a
subset: it is slow), with the ratio. `--same-as-main F` checks the paths against another
planner module file F (e.g. main's planner.py before the compiled loop): identical cells.

    python benchmarks/bench_planner.py [--repeats 5] [--python-plans 12] [--same-as-main FILE]
"""

from __future__ import annotations

import argparse
import importlib.util
import itertools
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from pico_studio.config import Config
from pico_studio.core.behaviours import planner
from pico_studio.core.behaviours.hospital import HospitalTour
from pico_studio.jit import py_func
from pico_studio.json_map import load_json_map

MAPS = Path(__file__).resolve().parents[1] / "pico_studio" / "data" / "maps"


def plans(name: str) -> tuple[planner.PlanGrid, list[tuple[tuple[float, float], tuple[float, float]]]]:
    cfg = Config()
    m = load_json_map(MAPS / f"{name}.json")
    tour = HospitalTour(cfg.behaviour, m, list(range(len(m.objects))))
    spots = [s[:2] for group in tour.spots for s in group]
    starts = [tuple(m.start_center)] if m.start_center is not None else []
    pairs = [(a, s) for a in starts for s in spots] + list(itertools.combinations(spots, 2))
    # and as many again between random free cells (seeded): long cross-map plans
    rng = np.random.default_rng(0)
    free = np.argwhere(~tour.grid.blocked)
    for _ in range(len(pairs)):
        a, b = free[rng.integers(len(free), size=2)]
        pairs.append((tour.grid.xy((int(a[0]), int(a[1]))), tour.grid.xy((int(b[0]), int(b[1])))))
    return tour.grid, pairs


def time_plans(fn, grid: planner.PlanGrid, pairs: list, repeats: int) -> list[float]:  # noqa: ANN001
    """Per plan, the median CPU ms over `repeats` runs of fn(blocked, penalty, sr, sc, gr, gc)."""
    blocked = np.ascontiguousarray(grid.blocked, dtype=np.bool_)
    penalty = np.ascontiguousarray(grid.penalty, dtype=np.float64)
    out = []
    for a, b in pairs:
        s, g = grid.cell(a), grid.cell(b)
        runs = []
        for _ in range(repeats):
            t0 = time.process_time()
            fn(blocked, penalty, s[0], s[1], g[0], g[1])
            runs.append((time.process_time() - t0) * 1000)
        out.append(statistics.median(runs))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--python-plans", type=int, default=12, help="plans timed uncompiled (slow)")
    ap.add_argument("--same-as-main", type=Path, help="a planner.py to compare paths with")
    args = ap.parse_args()
    print(f"load {os.getloadavg()[0]:.2f} (1-min average; 2 cores)")
    for name in ("hospital_2019", "restaurant_2024"):
        grid, pairs = plans(name)
        fast = time_plans(planner._astar, grid, pairs, args.repeats)
        sub = pairs[:: max(1, len(pairs) // args.python_plans)]
        slow = time_plans(py_func(planner._astar), grid, sub, 1)
        fast_sub = time_plans(planner._astar, grid, sub, args.repeats)
        print(f"{name}: {len(pairs)} plans on a {grid.blocked.shape[0]} x {grid.blocked.shape[1]} grid")
        print(f"  compiled   median {statistics.median(fast):7.2f} ms  worst {max(fast):7.2f} ms")
        print(f"  .py_func   median {statistics.median(slow):7.2f} ms  worst {max(slow):7.2f} ms "
              f"({len(sub)} plans; ratio {statistics.median(slow) / statistics.median(fast_sub):.0f}x on those)")
        if args.same_as_main:
            spec = importlib.util.spec_from_file_location("planner_ref", args.same_as_main)
            ref = importlib.util.module_from_spec(spec)
            sys.modules["planner_ref"] = ref
            spec.loader.exec_module(ref)  # type: ignore[union-attr]
            t_ref, same = [], 0
            for a, b in pairs:
                t0 = time.process_time()
                want = ref.astar(grid, a, b)
                t_ref.append((time.process_time() - t0) * 1000)
                got = planner.astar(grid, a, b)
                same += (want is None and got is None) or (want is not None and got is not None and np.array_equal(want, got))
            print(f"  reference  median {statistics.median(t_ref):7.2f} ms  worst {max(t_ref):7.2f} ms; "
                  f"same paths: {same}/{len(pairs)}")


if __name__ == "__main__":
    main()
