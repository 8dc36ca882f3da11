"""What the plugin layer costs per frame, and the example plugin segmenter against the built-in.

Scans: the perception benchmark's (hospital_2019, random free poses, the robot turning).
Printed, CPU ms per scan (medians over all scans and `--repeats` runs):
- the whole built-in perceptor through `perceive` (which now goes through
  `plugin_hooks.perceive_with_plugins`) against its stages called directly (`_perceive`, the
  peer): the hook's overhead when no plugin is selected;
- the same with the example door detector selected (`gap_doors`, Python loops);
- segmentation (segmenter + refit/merge/filter) with the example `chord_split` (plain numpy,
  one Python call per cluster) against the built-in split-and-merge (OpenCV) it mirrors.

    python benchmarks/bench_plugins.py [--poses 5] [--frames 10] [--repeats 3]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from bench_perception import record
from timing import load, median_ms

from pico_studio import plugins
from pico_studio.config import Config, with_value
from pico_studio.core.perception.perceptor import PerceptorState, _perceive, perceive
from pico_studio.core.perception.scan import process_scan
from pico_studio.core.perception.segment import segment_scan

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "plugins" / "my_stages.py"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--poses", type=int, default=5)
    ap.add_argument("--frames", type=int, default=10)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    plugins.load_plugin(str(EXAMPLE))
    cfg = Config()
    runs = record(args.poses, args.frames, 0)
    print(f"hospital_2019, {args.poses * args.frames} scans of 1000 beams; {load()}")

    # each frame from the state its run had before it, so every call does a real frame's work
    frames = []
    for seq in runs:
        state = PerceptorState.initial()
        for laser, odom in seq:
            frames.append((state, laser, odom))
            _, state = _perceive(state, laser, odom, cfg.perception)
    p = cfg.perception
    direct = median_ms(lambda f: _perceive(*f, p), frames, args.repeats)
    hooked = median_ms(lambda f: perceive(*f, p), frames, args.repeats)
    doors = with_value(cfg, "perception.identify.door_detector", "gap_doors").perception
    with_doors = median_ms(lambda f: perceive(*f, doors), frames, args.repeats)
    print("whole perceptor per scan (CPU time, median):")
    print(f"  stages called directly (peer)      {direct:8.3f} ms")
    print(f"  through perceive + plugin hook     {hooked:8.3f} ms  ({hooked / direct:5.2f}x)")
    print(f"  ... with the gap_doors plugin      {with_doors:8.3f} ms  ({with_doors / direct:5.2f}x)")

    scans = [process_scan(laser, p.scan, p.proximity)[0] for _, laser, _ in frames]
    mine = with_value(cfg, "perception.scan.segmenter", "chord_split").perception
    builtin = median_ms(lambda s: segment_scan(s, p), scans, args.repeats)
    plugin = median_ms(lambda s: segment_scan(s, mine), scans, args.repeats)
    print("segmenter + refit/merge/filter per scan:")
    print(f"  built-in split_merge (peer)        {builtin:8.3f} ms")
    print(f"  plugin chord_split (example)       {plugin:8.3f} ms  ({plugin / builtin:5.2f}x)")


if __name__ == "__main__":
    main()
