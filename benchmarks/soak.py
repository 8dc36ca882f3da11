"""Soak: does memory stay flat over long runs? RSS sampled while

1. **headless**: the simulator, the perceptor and the wander behaviour in one `Session`
   (the loop of `pico-studio run`), unpaced, for `--sim-minutes` of simulated time
   (default 60: a simulated hour);
2. **the page**: `pico-studio serve` (the viser app, playing at 20 Hz) with a connected
   chromium tab (Playwright), for `--page-minutes` of wall time (default 30). Both the
   server (this process, RSS) and the browser's processes (the sum of their PSS: shared
   pages split between them) are sampled.

For each: RSS at the start, after warm-up (a quarter of the run: the session keeps its last
2000 frames, 100 s at 20 Hz, so memory first rises by design), the peak and the end, and
the growth over the second half as MB per hour (a least-squares slope) — a leak shows as a
steady slope; a bounded cache as a step that then stays flat. The peer is the run's own
warm-up figure: end / warm-up RSS.

    .venv/bin/python benchmarks/soak.py                       # the full soak: ~1 h + 30 min
    .venv/bin/python benchmarks/soak.py --sim-minutes 10 --page-minutes 3   # a quick check
    .venv/bin/python benchmarks/soak.py --page-minutes 0      # headless only
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

from pico_studio.config import Config  # noqa: E402
from pico_studio.core.behaviours.wander import Wander  # noqa: E402
from pico_studio.core.perception import Perceptor  # noqa: E402
from pico_studio.session import Session  # noqa: E402
from pico_studio.sim import Simulator  # noqa: E402

MAP = Path(__file__).resolve().parents[1] / "examples" / "maps" / "hospital_2019.json"
PAGE_SIZE = os.sysconf("SC_PAGE_SIZE")


def rss_mb(pid: int | str = "self") -> float:
    """Resident set size of a process in MB (0 when it has gone)."""
    try:
        with open(f"/proc/{pid}/statm") as f:
            return int(f.read().split()[1]) * PAGE_SIZE / 2**20
    except (OSError, IndexError, ValueError):
        return 0.0


def pss_mb(pid: int) -> float:
    """Proportional set size in MB: shared pages split between the processes sharing them,
    so the browser's processes can be summed (their RSS counts shared libraries N times)."""
    try:
        with open(f"/proc/{pid}/smaps_rollup") as f:
            for line in f:
                if line.startswith("Pss:"):
                    return int(line.split()[1]) / 1024
    except OSError:
        pass
    return 0.0


def descendants(pid: int) -> list[int]:
    """Every process below `pid` (the browser's processes below this one)."""
    children: dict[int, list[int]] = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                ppid = int(f.read().rsplit(")", 1)[1].split()[1])
        except (OSError, IndexError, ValueError):
            continue
        children.setdefault(ppid, []).append(int(entry))
    out, stack = [], [pid]
    while stack:
        for c in children.get(stack.pop(), []):
            out.append(c)
            stack.append(c)
    return out


def slope_mb_per_hour(samples: list[tuple[float, float]]) -> float:
    """Least-squares slope of (seconds, MB) samples, in MB per hour."""
    if len(samples) < 3:
        return 0.0
    ts = [t for t, _ in samples]
    ms = [m for _, m in samples]
    tm, mm = statistics.fmean(ts), statistics.fmean(ms)
    den = sum((t - tm) ** 2 for t in ts)
    return 3600.0 * sum((t - tm) * (m - mm) for t, m in zip(ts, ms, strict=True)) / den if den else 0.0


def report(name: str, samples: list[tuple[float, float]], unit: str) -> None:
    warm = max(1, len(samples) // 4)
    second_half = samples[len(samples) // 2 :]
    start, warm_mb, end = samples[0][1], samples[warm][1], samples[-1][1]
    peak = max(m for _, m in samples)
    print(f"{name}: {len(samples)} samples over {samples[-1][0] / 60:.1f} {unit} minutes; RSS start {start:.0f} MB, "
          f"after warm-up {warm_mb:.0f} MB, peak {peak:.0f} MB, end {end:.0f} MB "
          f"(end / warm-up {end / warm_mb:.3f}); growth over the second half {slope_mb_per_hour(second_half):+.1f} MB per {unit} hour")
    step = max(1, len(samples) // 12)
    print("  RSS MB at " + ", ".join(f"{t / 60:.1f} min {m:.0f}" for t, m in samples[::step]))


def headless(minutes: float, every_s: float = 10.0) -> list[tuple[float, float]]:
    """RSS every `every_s` simulated seconds while the session runs `minutes` simulated."""
    cfg = Config()
    sim = Simulator.from_files(MAP, None, cfg.sim, seed=1)
    # the one behaviour protocol: the loop calls wander.step(world_model, laser, odometry, now, ok=)
    session = Session(sim, perceptor=Perceptor(cfg.perception), behaviour=Wander(cfg.ui.wander))
    samples = [(0.0, rss_mb())]
    t0 = time.perf_counter()
    while sim.now() < minutes * 60.0 - 1e-9:
        session.run(min(every_s, minutes * 60.0 - sim.now()), 0.05)
        samples.append((sim.now(), rss_mb()))
    wall = time.perf_counter() - t0
    print(f"headless: {minutes:g} simulated minutes in {wall:.0f} s wall ({sim.now() / wall:.1f}x real time), "
          f"{session.ticks} ticks, {sim.truth.collisions} collisions")
    return samples


def page(minutes: float, every_s: float = 10.0) -> tuple[list[tuple[float, float]], list[tuple[float, float]]]:
    """(server RSS, browser RSS) samples while a tab watches the page play for `minutes`."""
    from playwright.sync_api import sync_playwright

    from benchmarks.bench_ui import free_port
    from pico_studio.cli.serve_cmd import build_app
    from tests.ui_browser_helpers import CHROMIUM, CHROMIUM_ARGS, VIEWPORT

    args = argparse.Namespace(
        map=None, sim_config=None, config=None, behaviour="wander", source="sim", host="127.0.0.1",
        port=free_port(), seed=1, export_dir=tempfile.mkdtemp(), paused=False,
    )
    app = build_app(args, verbose=False)
    app.start()
    server: list[tuple[float, float]] = []
    browser: list[tuple[float, float]] = []
    try:
        with sync_playwright() as p:
            ctx = p.chromium.launch_persistent_context(
                tempfile.mkdtemp(), executable_path=str(CHROMIUM), headless=True, args=CHROMIUM_ARGS,
                viewport=VIEWPORT,
            )
            tab = ctx.new_page()
            tab.goto(app.url + "/?fixedDpr=1")
            tab.get_by_text("hospital_2019.json").first.wait_for(timeout=60000)
            f0, w0 = app.studio.frame_count, time.monotonic()
            while (t := time.monotonic() - w0) < minutes * 60.0:
                server.append((t, rss_mb()))
                browser.append((t, sum(pss_mb(c) for c in descendants(os.getpid()))))
                tab.wait_for_timeout(every_s * 1000)  # keeps the tab's event loop turning
            frames = app.studio.frame_count - f0
            print(f"page: {minutes:g} minutes with a tab connected, {frames} frames streamed "
                  f"({frames / (time.monotonic() - w0):.1f} Hz)")
            ctx.close()
    finally:
        app.stop()
    return server, browser


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sim-minutes", type=float, default=60.0, help="simulated minutes headless (0: skip)")
    ap.add_argument("--page-minutes", type=float, default=30.0, help="wall minutes of the page with a tab (0: skip)")
    ap.add_argument("--every", type=float, default=10.0, help="seconds between samples")
    a = ap.parse_args()
    with open("/proc/loadavg") as f:
        print(f"machine load average {f.read().split()[0]} (on {os.cpu_count()} cores)")
    if a.sim_minutes > 0:
        report("headless session", headless(a.sim_minutes, a.every), "simulated")
    if a.page_minutes > 0:
        server, browser = page(a.page_minutes, a.every)
        report("page server", server, "wall")
        report("page browser (PSS of all chromium processes)", browser, "wall")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
