"""The three segmenters and the shared refit, compiled vs their own Python, on hospital_2019.

Scans: the perception benchmark's (the simulator at random free poses of hospital_2019,
1000 beams, the robot turning slowly). Per segmenter, CPU ms per scan (medians over all
scans and `--repeats` runs): the scan stage (filtering, resampling, clustering: one compiled
pass) and the segmenter with the refit/merge/filter on an already processed scan, each
compiled and uncompiled (`.py_func`, in the same process), and the whole "segmentation
alone" of the issue's table (scan stage, segmenter, refit) as scans per second.

    python benchmarks/bench_segmenters.py [--poses 10] [--frames 20] [--repeats 5]
"""

from __future__ import annotations

import argparse
from typing import Any

from bench_perception import record
from timing import compiled_vs_python, load, median_ms, ratio_line

from pico_studio.config import Config, with_value
from pico_studio.core.perception.scan import process_scan
from pico_studio.core.perception.segment import segment_scan

SEGMENTERS = ("split_merge", "angle", "ransac")


def measure(poses: int, frames: int, repeats: int, python_items: int = 20) -> dict[str, dict[str, float]]:
    """Per segmenter: compiled / python ms (segmenter + refit) and scans/s of segmentation
    alone; under "scan": compiled / python ms of the scan stage."""
    cfg = Config()
    lasers = [laser for seq in record(poses, frames, 0) for laser, _ in seq]
    p0 = cfg.perception
    scans = [process_scan(laser, p0.scan, p0.proximity)[0] for laser in lasers]
    fast, slow = compiled_vs_python(lambda laser: process_scan(laser, p0.scan, p0.proximity), lasers, repeats,
                                    python_items)
    out: dict[str, dict[str, float]] = {"scan": {"compiled_ms": fast, "python_ms": slow}}
    for name in SEGMENTERS:
        p = with_value(cfg, "perception.scan.segmenter", name).perception
        fast, slow = compiled_vs_python(lambda s, p=p: segment_scan(s, p), scans, repeats, python_items)

        def whole(laser: Any, p: Any = p) -> None:
            scan, _ = process_scan(laser, p.scan, p.proximity)
            segment_scan(scan, p)

        out[name] = {"compiled_ms": fast, "python_ms": slow, "scans_per_s": 1000 / median_ms(whole, lasers, repeats)}
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--poses", type=int, default=10)
    ap.add_argument("--frames", type=int, default=20)
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    print(f"hospital_2019, {args.poses * args.frames} scans of 1000 beams; {load()}")
    res = measure(args.poses, args.frames, args.repeats)
    scan = res.pop("scan")
    print("scan stage per scan (CPU time, median):")
    print(ratio_line("filter, resample, cluster", scan["compiled_ms"], scan["python_ms"]))
    print("segmenter + refit/merge/filter per scan (CPU time, median):")
    for name, r in res.items():
        print(ratio_line(name, r["compiled_ms"], r["python_ms"]))
    print("segmentation alone (filter, resample, cluster, segment, refit):")
    for name, r in res.items():
        print(f"  {name:34s} {r['scans_per_s']:9.0f} scans/s")


if __name__ == "__main__":
    main()
