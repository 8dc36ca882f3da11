"""Screenshots of the page (`pico-studio serve`) for docs/: the default view, the Layers tab
with its swatches, the help modal, the log, and a bag replay.

Runs the built-in hospital example (and the test bag for the replay) for a few seconds with
Debian's chromium connected, then saves what the tab shows.

    .venv/bin/python examples/screenshot_page.py [--seconds 12] [--out-dir docs]
"""

from __future__ import annotations

import argparse
import socket
import tempfile
import time
from pathlib import Path

from pico_studio.cli.serve_cmd import build_app

ARGS = ["--no-sandbox", "--disable-background-networking", "--disable-gpu", "--no-first-run",
        "--disable-component-update", "--disable-sync"]
BAG = Path(__file__).resolve().parents[1] / "tests" / "data" / "recordings" / "pico_real_2019-05-07.bag"


def _port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _app(source: str, seed: int):  # -> StudioApp
    args = argparse.Namespace(
        map=None, sim_config=None, config=None, behaviour="wander", source=source, host="127.0.0.1",
        port=_port(), seed=seed, export_dir=tempfile.mkdtemp(), paused=source != "sim",
    )
    return build_app(args, verbose=False)


def _close_notice(page) -> None:  # noqa: ANN001 - playwright Page
    """The "software WebGL" notice is about this headless browser, not the page."""
    notice = page.get_by_text("Software WebGL rendering detected")
    if notice.count():
        notice.locator("xpath=ancestor::div[contains(@class,'mantine-Notification-root')][1]").locator("button").first.click()
    time.sleep(0.5)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=12.0)
    ap.add_argument("--out-dir", default="docs")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    from playwright.sync_api import sync_playwright

    out = Path(a.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    with sync_playwright() as p:
        ctx = p.chromium.launch_persistent_context(
            tempfile.mkdtemp(), executable_path="/usr/bin/chromium", headless=True, args=ARGS,
            viewport={"width": 1400, "height": 900},
        )
        app = _app("sim", a.seed)
        app.start()
        try:
            page = ctx.new_page()
            page.goto(app.url + "/?fixedDpr=1")
            page.get_by_text("hospital_2019.json").first.wait_for(timeout=30000)
            time.sleep(a.seconds)
            _close_notice(page)
            page.screenshot(path=str(out / "ui_default.png"))
            page.get_by_role("tab", name="Layers").click()
            time.sleep(1.0)
            page.screenshot(path=str(out / "ui_layers.png"))
            page.keyboard.press("h")
            page.get_by_text("Layers and their colours").first.wait_for(timeout=20000)
            time.sleep(1.0)
            page.screenshot(path=str(out / "ui_help.png"))
            page.get_by_role("button", name="Close").click()
            page.close()
        finally:
            app.stop()
        app = _app(f"bag:{BAG}", a.seed)
        app.start()
        try:
            app.seek(150)
            page = ctx.new_page()
            page.goto(app.url + "/?fixedDpr=1")
            page.get_by_text("recording frame").first.wait_for(timeout=30000)
            time.sleep(3.0)
            _close_notice(page)
            page.screenshot(path=str(out / "ui_replay.png"))
            page.get_by_role("tab", name="Log").click()
            time.sleep(1.0)
            page.screenshot(path=str(out / "ui_log.png"))
        finally:
            app.stop()
        ctx.close()
    print(f"saved ui_default, ui_layers, ui_help, ui_replay, ui_log .png in {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
