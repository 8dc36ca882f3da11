"""What-if speed with a real browser tab connected (Debian's chromium via Playwright).

A simulated run of `--frames` scans (default 2,400: the timeline's 2 minutes at 20 Hz) is on
the page's timeline; then `--edits` parameter changes are typed into the Config tab:

1. change -> re-judged plots: wall time from the edit typed in the browser to the What-if
   tab's charts (polled in the browser, every 20 ms) showing the first part of the new
   re-judge (partial results, every second), and showing all of it; medians over the edits.
   The peer in the same process: the re-judge alone (`Judged.seconds`, the background
   worker's compute), so the ratio is what the page adds (queueing, sending the series, the
   browser's redraw).
2. the shown frame redrawn: the server-side time from the edit arriving to the re-processed
   frame's layers flushed to the socket (`ConfigTab.update_ms`), median, next to the same
   re-processing headless (`Studio.set_param`, no viser).

The page is measured judging in worker processes (`--workers 2`, the default: B's re-judge in
two processes beside the page's) and, as the peer in the same process, in a thread of the
page's process (`--workers 1`, as before).

3. `--headless`: the re-judge alone, no page: a 2,400-frame simulated run (hospital_2019,
   wander; `--localise`: localised on the map, as the page does) re-judged `--repeats` times
   with alternating configs, in this process (`rejudge(run, cfg)`) and in two warm worker
   processes (`ProcessRejudger`, the run sent once); wall time, CPU time of every process
   judging, and this process's own CPU while the workers judge.

Prints the machine's load (`os.getloadavg`) beside the figures: on a shared machine they
scale with it.

    .venv/bin/python benchmarks/bench_whatif.py [--frames 2400] [--edits 3] [--workers 2,1]
    .venv/bin/python benchmarks/bench_whatif.py --headless [--frames 2400] [--repeats 3] [--localise]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from pico_studio.cli.serve_cmd import build_app  # noqa: E402
from tests.ui_browser_helpers import CHROMIUM, CHROMIUM_ARGS, VIEWPORT, free_port, set_number  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]

CHECKSUM = """() => {
  const tp = (window.__viserTestpoints || {}).uplots || {};
  for (const k in tp) {
    const u = tp[k].chart;
    if (!u || (u.root.querySelector('.u-title') || {}).textContent !== 'Counts') continue;
    const i = u.series.findIndex(s => s.label === 'count.walls');
    if (i < 0) return null;
    let s = 0, n = 0;
    for (const v of u.data[i]) if (Number.isFinite(v)) { s += v; n++; }
    return [s, n];   // B's walls summed, and how many frames B has so far
  }
  return null;
}"""


def load() -> str:
    one, five, _ = os.getloadavg()
    return f"load {one:.1f} (1 min), {five:.1f} (5 min) on {os.cpu_count()} cores"


def headless(frames: int, repeats: int, localise: bool) -> None:
    """The re-judge alone: in this process, then in two warm worker processes."""
    from pico_studio.config import Config, with_value
    from pico_studio.evaluation.compare import sim_run
    from pico_studio.evaluation.rejudge import rejudge
    from pico_studio.evaluation.rejudge_worker import ProcessRejudger
    from pico_studio.jit import warm_up

    warm_up()
    cfg = Config()
    configs = [cfg, with_value(cfg, "perception.scan.min_length", 0.3)]
    run = sim_run(str(ROOT / "pico_studio" / "data" / "maps" / "hospital_2019.json"), cfg, seed=3,
                  seconds=frames * 0.05, localise=localise)
    what = f"{run.scans}-frame run ({'perceive + localise + score' if localise else 'perceive + score'})"
    print(f"re-judging a {what}; {load()}")
    wall, cpu = [], []
    for k in range(repeats):
        t = time.perf_counter()
        j = rejudge(run, configs[k % 2])
        wall.append(time.perf_counter() - t)
        cpu.append(j.cpu)
    t = time.perf_counter()
    worker = ProcessRejudger(run)
    first = worker.wait(worker.submit(configs[1]), timeout=600)
    start = time.perf_counter() - t
    w_wall, w_cpu, own, parts = [], [], [], []
    try:
        for k in range(repeats):
            t, c = time.perf_counter(), time.process_time()
            j = worker.wait(worker.submit(configs[k % 2]), timeout=600)
            assert j is not None
            w_wall.append(time.perf_counter() - t)
            own.append(time.process_time() - c)
            w_cpu.append(j.cpu)
            parts.append(j.cpu_parts)
    finally:
        worker.close()
    med = statistics.median
    print(f"  in this process:     median {med(wall):.2f} s wall, {med(cpu):.2f} s CPU "
          f"({1000 * med(wall) / run.scans:.2f} ms a frame wall)")
    print(f"  two worker processes: median {med(w_wall):.2f} s wall, {med(w_cpu):.2f} s CPU in both "
          f"({1000 * med(w_wall) / run.scans:.2f} ms a frame wall; perceiver {med(p[0] for p in parts):.2f} s CPU, "
          f"scorer {med(p[1] for p in parts):.2f} s); this process {1000 * med(own):.0f} ms CPU meanwhile; "
          f"the first (processes started, the run sent) {start:.2f} s{'' if first is not None else ' (timed out)'}")
    print(f"  ratio in-process / workers, wall: {med(wall) / med(w_wall):.2f} (target <= 2 s for 2,400 frames); {load()}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--frames", type=int, default=2400)
    ap.add_argument("--edits", type=int, default=3)
    ap.add_argument("--workers", default="2,1", help="the page's re-judge processes to measure, in turn (1: a thread)")
    ap.add_argument("--headless", action="store_true", help="the re-judge alone, no page, no browser")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--localise", action="store_true", help="--headless: localised on the map, as the page")
    args = ap.parse_args()
    if args.headless:
        headless(args.frames, args.repeats, args.localise)
        return 0
    from playwright.sync_api import sync_playwright

    ns = argparse.Namespace(map=None, sim_config=None, config=None, behaviour="wander", source="sim",
                            host="127.0.0.1", port=free_port(), seed=3, export_dir=tempfile.mkdtemp(), paused=True)
    app = build_app(ns, verbose=False)
    studio = app.studio
    t0 = time.perf_counter()
    for _ in range(args.frames):
        studio.tick(0.05)
    studio.playing = False
    print(f"drove {len(studio.timeline)} frames in {time.perf_counter() - t0:.1f} s; {load()}")
    app.start()
    figures: dict[int, tuple[float, float, float, float]] = {}
    redraw: list[float] = []
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=str(CHROMIUM), headless=True, args=CHROMIUM_ARGS)
            page = browser.new_page(viewport=VIEWPORT)
            page.goto(app.url + "/?fixedDpr=1")
            page.get_by_text("hospital_2019.json").first.wait_for(timeout=60000)
            for workers in [int(w) for w in args.workers.split(",")]:
                figures[workers] = edits(app, page, args.edits, workers, redraw)
            browser.close()
        # the peer of the redraw: the same re-processing without viser
        headless_ms = []
        for k in range(max(args.edits, 5)):
            t = time.perf_counter()
            studio.set_param("perception.scan.min_length", 0.3 if k % 2 == 0 else 0.1)
            headless_ms.append((time.perf_counter() - t) * 1000.0)
    finally:
        app.stop()
    for workers, (s, f, c, cpu) in figures.items():
        how = f"{workers} worker processes" if workers > 1 else "a thread of the page's process"
        print(f"re-judging in {how}: change -> re-judged plots of a {len(studio.timeline)}-frame run in the browser: "
              f"median {s:.2f} s (target <= 2 s), its first part after {f:.2f} s; re-judge alone {c:.2f} s "
              f"(ratio {s / c:.2f}); the page's process {cpu:.2f} s CPU from edit to plots")
    if 1 in figures and len(figures) > 1:
        best = min(w for w in figures if w > 1)
        print(f"  threads / worker processes, edit -> whole run plotted: {figures[1][0] / figures[best][0]:.2f}")
    r, h = statistics.median(redraw) if redraw else float("nan"), statistics.median(headless_ms)
    print(f"shown frame redrawn (edit -> layers flushed): median {r:.0f} ms (target <= 100 ms); "
          f"re-processing alone {h:.0f} ms (ratio {r / h:.2f})")
    print(load())
    return 0


def edits(app, page, count: int, workers: int, redraw: list[float]) -> tuple[float, float, float, float]:  # noqa: ANN001
    """(edit -> whole run plotted, edit -> first part plotted, the re-judge alone, the page
    process's CPU seconds from edit to plots): medians over `count` edits."""
    studio = app.studio
    app.whatif.set_workers(workers)
    page.get_by_role("tab", name="What-if").click()
    page.get_by_role("button", name="Re-judge now").click()
    time.sleep(0.5)
    app.whatif.wait(600)
    page.get_by_role("tab", name="Config").click()
    if not page.locator("label").filter(has_text="min_length").locator("visible=true").count():
        page.get_by_text("scan", exact=True).locator("visible=true").first.click()  # open its folder once
    compute, seen, first, cpu = [], [], [], []
    for k in range(count):
        page.get_by_role("tab", name="Config").click()
        before = page.evaluate(CHECKSUM)
        value = 0.1 if studio.cfg.perception.scan.min_length == 0.3 else 0.3  # a change, whatever came before
        n_ms = len(app.update_ms)
        t_edit, c_edit = time.perf_counter(), time.process_time()
        set_number(page, "min_length", value)
        while page.evaluate(CHECKSUM) in (before, None) and time.perf_counter() - t_edit < 600:
            time.sleep(0.02)
        first.append(time.perf_counter() - t_edit)
        frames = len(studio.timeline)
        while time.perf_counter() - t_edit < 900:
            now = page.evaluate(CHECKSUM)
            if now is not None and now != before and now[1] >= frames and app.whatif.settled():
                break
            time.sleep(0.02)
        seen.append(time.perf_counter() - t_edit)
        cpu.append(time.process_time() - c_edit)
        app.whatif.wait(60)
        judged = app.whatif.b.judged
        compute.append(judged.seconds if judged is not None else float("nan"))
        redraw.extend(app.update_ms[n_ms:])
        print(f"  workers {workers}, edit {k + 1}: first plots after {first[-1]:.2f} s, the whole run after "
              f"{seen[-1]:.2f} s (re-judge {compute[-1]:.2f} s, {len(judged.times) if judged else 0} frames); {load()}")
    med = statistics.median
    return med(seen), med(first), med(compute), med(cpu)


if __name__ == "__main__":
    raise SystemExit(main())
