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

Prints the machine's load (`os.getloadavg`) beside the figures: on a shared machine they
scale with it.

    .venv/bin/python benchmarks/bench_whatif.py [--frames 2400] [--edits 3]
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


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--frames", type=int, default=2400)
    ap.add_argument("--edits", type=int, default=3)
    args = ap.parse_args()
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
    compute, seen, first, redraw = [], [], [], []
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=str(CHROMIUM), headless=True, args=CHROMIUM_ARGS)
            page = browser.new_page(viewport=VIEWPORT)
            page.goto(app.url + "/?fixedDpr=1")
            page.get_by_text("hospital_2019.json").first.wait_for(timeout=60000)
            page.get_by_role("tab", name="What-if").click()
            page.get_by_role("button", name="Re-judge now").click()
            app.whatif.wait(600)
            page.get_by_role("tab", name="Config").click()
            page.get_by_text("scan", exact=True).locator("visible=true").first.click()
            for k in range(args.edits):
                page.get_by_role("tab", name="Config").click()
                before = page.evaluate(CHECKSUM)
                value = 0.3 if k % 2 == 0 else 0.1
                n_ms = len(app.update_ms)
                t_edit = time.perf_counter()
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
                app.whatif.wait(60)
                judged = app.whatif.b.judged
                compute.append(judged.seconds if judged is not None else float("nan"))
                redraw.extend(app.update_ms[n_ms:])
                print(f"  edit {k + 1}: first plots after {first[-1]:.2f} s, the whole run after {seen[-1]:.2f} s "
                      f"(re-judge {compute[-1]:.2f} s, {len(judged.times) if judged else 0} frames)")
            browser.close()
        # the peer of the redraw: the same re-processing without viser
        headless = []
        for k in range(max(args.edits, 5)):
            t = time.perf_counter()
            studio.set_param("perception.scan.min_length", 0.3 if k % 2 == 0 else 0.1)
            headless.append((time.perf_counter() - t) * 1000.0)
    finally:
        app.stop()
    s, c, f = statistics.median(seen), statistics.median(compute), statistics.median(first)
    r, h = statistics.median(redraw) if redraw else float("nan"), statistics.median(headless)
    print(f"change -> re-judged plots of a {len(studio.timeline)}-frame run in the browser: median {s:.2f} s "
          f"(target <= 2 s), its first part after {f:.2f} s; re-judge alone {c:.2f} s (ratio {s / c:.2f})")
    print(f"shown frame redrawn (edit -> layers flushed): median {r:.0f} ms (target <= 100 ms); "
          f"re-processing alone {h:.0f} ms (ratio {r / h:.2f})")
    print(load())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
