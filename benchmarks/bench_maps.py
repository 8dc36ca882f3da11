"""How fast maps load, rasterise and convert, against the bare image decode in the same process.

* `load_map` of each real heightmap (read, classify, drop specks, trace and simplify the
  outlines, door rectangles) against `cv2.imread` of the same file (its peer: the least any
  loader must do);
* `load_map` of the real JSON maps (parse and validate);
* `rasterise` of each map at 0.025 m/px, and a full `convert` (write + read back + IoU).

    .venv/bin/python benchmarks/bench_maps.py [--repeat N]

Prints medians over N runs (ms) and the ratios.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import cv2

from pico_studio.json_map import convert, load_map, rasterise

MAPS = Path(__file__).resolve().parents[1] / "pico_studio" / "data" / "maps"
IMAGES = ["doors_heightmap_example.png", "escape_room.png", "hospital_2021.png", "restaurant_2024.png"]
JSONS = ["emc_example.json", "hospital_2019.json", "restaurant_2024.json"]


def median_ms(fn: Callable[[], object], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return 1000 * statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=20)
    n = ap.parse_args().repeat
    print(f"{'map':32s} {'load ms':>9s} {'imread ms':>10s} {'ratio':>7s} {'raster ms':>10s} {'convert ms':>11s}")
    with tempfile.TemporaryDirectory() as tmp:
        for name in IMAGES + JSONS:
            path = MAPS / name
            load = median_ms(lambda p=path: load_map(p), n)
            m = load_map(path)
            raster = median_ms(lambda m=m: rasterise(m), n)
            out = Path(tmp) / (path.stem + (".json" if path.suffix == ".png" else ".png"))
            conv = median_ms(lambda p=path, o=out: convert(p, o), max(3, n // 4))
            if path.suffix == ".png":
                peer = median_ms(lambda p=path: cv2.imread(str(p), cv2.IMREAD_UNCHANGED), n)
                print(f"{name:32s} {load:9.2f} {peer:10.2f} {load / peer:7.1f} {raster:10.2f} {conv:11.2f}")
            else:
                print(f"{name:32s} {load:9.2f} {'-':>10s} {'-':>7s} {raster:10.2f} {conv:11.2f}")


if __name__ == "__main__":
    main()
