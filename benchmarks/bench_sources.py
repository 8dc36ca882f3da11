"""How fast recordings open and replay, against their peers in the same process.

* bag: `open_bag` (decode every topic, check every scan's beam layout, build the timeline)
  against the bare `rosbags` loop that only deserialises the same messages;
* CARMEN: `open_carmen` (gzip, field checks, ODOM/FLASER split) against bare parsing of the FLASER lines with `str.split` + `float`;
* replay loop: a full pass of `read_laser`/`advance` over the opened bag.

    .venv/bin/python benchmarks/bench_sources.py [--repeat N]

Prints medians over N runs and the ratios.
"""

from __future__ import annotations

import argparse
import gzip
import statistics
import time
from collections.abc import Callable
from pathlib import Path

from rosbags.rosbag1 import Reader
from rosbags.typesys import Stores, get_typestore

from pico_studio.sources import open_bag, open_carmen

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "recordings"
BAG = DATA / "pico_real_2019-05-07.bag"
CARMEN = DATA / "intel-corrected.log.gz"


def median_s(fn: Callable[[], object], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


_TS = get_typestore(Stores.ROS1_NOETIC)


def bare_rosbags() -> int:
    ts = _TS
    n = 0
    with Reader(BAG) as reader:
        for conn, _t, raw in reader.messages():
            ts.deserialize_ros1(raw, conn.msgtype)
            n += 1
    return n


def bare_carmen() -> int:
    n = 0
    with gzip.open(CARMEN, "rt") as f:
        for line in f:
            if line.startswith("FLASER"):
                [float(x) for x in line.split()[2:-2]]
                n += 1
    return n


def replay_pass() -> int:
    replay = open_bag(BAG)
    n = 0
    while replay.ok():
        n += replay.read_laser() is not None
        replay.advance(0.01)
    return n


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=7)
    repeat = ap.parse_args().repeat
    rows = [
        ("open_bag (243 scans x 1081 beams)", lambda: open_bag(BAG), "bare rosbags deserialise", bare_rosbags),
        ("open_carmen (910 scans, 14541 ODOM)", lambda: open_carmen(CARMEN), "bare FLASER split+float", bare_carmen),
        ("open_bag + full replay pass", replay_pass, "open_bag alone", lambda: open_bag(BAG)),
    ]
    print(f"median of {repeat} runs")
    for name, fn, peer_name, peer in rows:
        a, b = median_s(fn, repeat), median_s(peer, repeat)
        print(f"{name:40s} {a * 1e3:8.1f} ms   {peer_name:28s} {b * 1e3:8.1f} ms   ratio {a / b:5.2f}")


if __name__ == "__main__":
    main()
