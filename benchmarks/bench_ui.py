"""Web UI speed, with a real browser tab connected (Debian's chromium via Playwright).

1. Slider change -> updated layers sent: the server-side time from a parameter edit arriving
   (the GUI callback) to the re-processed frame's layers being flushed to the socket, for
   edits typed into the page while paused. Median over the edits, as wall time and as the
   callback thread's CPU time (what it costs when the machine is not shared).
2. Streaming at 20 Hz: the server process's CPU time / wall time while playing (1.0 = one
   core), and its CPU milliseconds per streamed frame (times 20 Hz = the share it needs at
   full rate), next to the same loop headless (studio tick + layer geometry, no viser).
3. The metrics the page reads every redraw, after a long run (10 minutes of frames scored
   at 4 Hz): the studio's running score sum next to the peer `RunScore(kept).summary()`,
   which sums every scored frame again (what the page did before).

4. A replay's jump (the one scrubber) on a 2,400-frame recording (a 120 s simulated run
   recorded to a bag): server-side time from the jump to its layers sent, to random frames
   after it was played through once (checkpoints every 10 frames), next to the peer that
   re-processes from the start of the file (no checkpoints).

    .venv/bin/python benchmarks/bench_ui.py [--edits 30] [--seconds 10] [--only-seek]
"""

from __future__ import annotations

import argparse
import socket
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from pico_studio.cli.serve_cmd import build_app  # noqa: E402
from pico_studio.config import Config  # noqa: E402
from pico_studio.json_map import load_json_map  # noqa: E402
from pico_studio.ui.runtime import Studio  # noqa: E402
from pico_studio.ui.scene_data import frame_prims  # noqa: E402
from pico_studio.ui.sources import DEFAULT_MAP, make_source_factory  # noqa: E402
from tests.ui_browser_helpers import CHROMIUM, CHROMIUM_ARGS, VIEWPORT, set_number  # noqa: E402


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def cpu_share(app, seconds: float) -> tuple[float, float]:  # noqa: ANN001
    """(CPU share of one core, CPU ms per streamed frame) of this process while it streams."""
    f0, c0, w0 = app.studio.frame_count, time.process_time(), time.monotonic()
    time.sleep(seconds)
    cpu, frames = time.process_time() - c0, max(app.studio.frame_count - f0, 1)
    return cpu / (time.monotonic() - w0), 1000.0 * cpu / frames


def headless_share(seconds: float) -> tuple[float, float]:
    """The same 20 Hz loop without viser: tick + layer geometry, paced like the page."""
    studio = Studio(Config(), load_json_map(DEFAULT_MAP), make_source_factory("sim", None, 1), map_name="h")
    c0, w0 = time.process_time(), time.monotonic()
    next_t, frames = w0, 0
    while time.monotonic() - w0 < seconds:
        studio.tick(0.05)
        frame_prims(studio, studio.shown())
        studio.metrics()
        frames += 1
        next_t += 0.05
        time.sleep(max(0.0, next_t - time.monotonic()))
    cpu = time.process_time() - c0
    return cpu / (time.monotonic() - w0), 1000.0 * cpu / frames


def long_run_metrics(scored: int = 2400, repeats: int = 50) -> tuple[float, float]:
    """(ms per `Studio.metrics()`, ms per peer: summing every kept `FrameScore` again) with
    `scored` frames."""
    from pico_studio.evaluation.frame_score import FrameScore
    from pico_studio.evaluation.run_score import RunScore

    studio = Studio(Config(), load_json_map(DEFAULT_MAP), make_source_factory("sim", None, 1), map_name="h")
    for _ in range(10):
        studio.tick(0.05)
    run = studio.scorer.run
    frame = run.last or FrameScore()
    kept = []
    for _ in range(scored):
        run.add(frame)
        kept.append(frame)

    def peer() -> dict:
        return RunScore(kept).summary()

    def median_ms(fn) -> float:  # noqa: ANN001
        times = []
        for _ in range(repeats):
            run.add(frame)  # a new scored frame each redraw, the worst case
            kept.append(frame)
            t0 = time.perf_counter()
            fn()
            times.append((time.perf_counter() - t0) * 1000.0)
        return statistics.median(times)

    return median_ms(studio.metrics), median_ms(peer)


def replay_seek(frames: int = 2400, jumps: int = 15, peer_jumps: int = 1) -> tuple[float, float, float, int]:
    """(median ms per jump, max ms, peer median ms, frames in the file)."""
    import random

    from pico_studio.ui.recording_panel import RunRecorder
    from pico_studio.ui.replay import ReplayDriver

    folder = Path(tempfile.mkdtemp())
    sim = Studio(Config(), load_json_map(DEFAULT_MAP), make_source_factory("sim", None, 1), map_name="h")
    recorder = RunRecorder(sim, folder)
    bag = recorder.start()
    while sim.frame_count < frames:
        sim.tick(0.05)
    recorder.stop()
    args = argparse.Namespace(
        map=None, sim_config=None, config=None, behaviour="stop", source=f"bag:{bag}", host="127.0.0.1",
        port=free_port(), seed=None, export_dir=str(folder), paused=True,
    )
    app = build_app(args, verbose=False)
    try:
        app.studio.playing = True
        while app.studio.playing:  # played through once: the checkpoints are there
            app.replay.play(0.05, float("inf"), budget_s=1.0)
        count = app.studio.source.frame_count
        rng = random.Random(1)
        ms = []
        for _ in range(jumps):
            t0 = time.perf_counter()
            app.seek(rng.randrange(count))
            app.server.flush()
            ms.append((time.perf_counter() - t0) * 1000.0)
        peer = ReplayDriver(app.studio, every=10**9)  # no checkpoints: from the start each time
        peer_ms = []
        for _ in range(peer_jumps):
            t0 = time.perf_counter()
            peer.seek(rng.randrange(count // 2, count))
            app.redraw()
            app.server.flush()
            peer_ms.append((time.perf_counter() - t0) * 1000.0)
    finally:
        app.stop()
    return statistics.median(ms), max(ms), statistics.median(peer_ms), count


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edits", type=int, default=30)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--only-seek", action="store_true", help="only the replay jump (no browser)")
    a = ap.parse_args()
    if a.only_seek:
        _print_seek()
        return 0
    from playwright.sync_api import sync_playwright

    args = argparse.Namespace(
        map=None, sim_config=None, config=None, behaviour="wander", source="sim", host="127.0.0.1",
        port=free_port(), seed=1, export_dir=tempfile.mkdtemp(), paused=False,
    )
    app = build_app(args, verbose=False)
    app.start()
    try:
        with sync_playwright() as p:
            ctx = p.chromium.launch_persistent_context(
                tempfile.mkdtemp(), executable_path=str(CHROMIUM), headless=True, args=CHROMIUM_ARGS, viewport=VIEWPORT
            )
            page = ctx.new_page()
            page.goto(app.url + "/?fixedDpr=1")
            page.get_by_text("hospital_2019.json").first.wait_for(timeout=30000)
            time.sleep(3.0)  # let the tab settle and the timeline fill a little

            share, frame_ms = cpu_share(app, a.seconds)
            hz = app.studio.metrics()["hz"]

            app.studio.playing = False
            page.get_by_role("tab", name="Config").click()
            page.get_by_text("scan", exact=True).locator("visible=true").first.click()
            app.update_ms.clear()
            app.update_cpu_ms.clear()
            for i in range(a.edits):
                set_number(page, "min_length", 0.2 if i % 2 == 0 else 0.1)
                deadline = time.monotonic() + 5.0
                while len(app.update_ms) < i + 1 and time.monotonic() < deadline:
                    time.sleep(0.01)
            ctx.close()
    finally:
        app.stop()
    peer, peer_frame_ms = headless_share(a.seconds)
    metrics_ms, summary_ms = long_run_metrics()
    ms, cpu_ms = app.update_ms, app.update_cpu_ms
    with open("/proc/loadavg") as f:
        load = f.read().split()[0]
    print(f"machine load average {load} (on {__import__('os').cpu_count()} cores)")
    print(f"slider change -> layers sent (server side, paused, {len(ms)} edits): "
          f"median {statistics.median(ms):.1f} ms wall (p90 {sorted(ms)[int(0.9 * (len(ms) - 1))]:.1f}), "
          f"{statistics.median(cpu_ms):.1f} ms CPU")
    print(f"streaming with a tab connected: server CPU {100 * share:.0f}% of one core at {hz:.1f} Hz; "
          f"{frame_ms:.1f} ms CPU per frame = {2 * frame_ms:.0f}% of one core at 20 Hz")
    print(f"peer, the same loop headless (no viser): {peer_frame_ms:.1f} ms CPU per frame; "
          f"page/headless ratio {frame_ms / peer_frame_ms:.2f}")
    print(f"after 10 minutes scored at 4 Hz: the page's metrics {metrics_ms:.2f} ms per redraw; "
          f"peer RunScore(kept).summary() {summary_ms:.2f} ms ({summary_ms / metrics_ms:.0f}x)")
    _print_seek()
    return 0


def _print_seek() -> None:
    med, worst, peer, count = replay_seek()
    with open("/proc/loadavg") as f:
        load = f.read().split()[0]
    print(f"replay jump on a {count}-frame recording (load {load}): median {med:.0f} ms to layers sent, "
          f"max {worst:.0f} ms; peer re-processing from the start {peer:.0f} ms ({peer / med:.0f}x)")


if __name__ == "__main__":
    raise SystemExit(main())
