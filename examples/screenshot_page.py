"""Take a screenshot of the default page (`pico-studio serve`) as docs/ui_default.png.

Runs the built-in hospital example for a few seconds with Debian's chromium connected, then
saves what the tab shows.

    .venv/bin/python examples/screenshot_page.py [--seconds 12] [--out docs/ui_default.png]
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


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=12.0)
    ap.add_argument("--out", default="docs/ui_default.png")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    from playwright.sync_api import sync_playwright

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    args = argparse.Namespace(
        map=None, sim_config=None, config=None, behaviour="wander", source="sim", host="127.0.0.1",
        port=port, seed=a.seed, export_dir=tempfile.mkdtemp(), paused=False,
    )
    app = build_app(args, verbose=False)
    app.start()
    try:
        with sync_playwright() as p:
            ctx = p.chromium.launch_persistent_context(
                tempfile.mkdtemp(), executable_path="/usr/bin/chromium", headless=True, args=ARGS,
                viewport={"width": 1400, "height": 900},
            )
            page = ctx.new_page()
            page.goto(app.url + "/?fixedDpr=1")
            page.get_by_text("hospital_2019.json").first.wait_for(timeout=30000)
            # the "software WebGL" notice is about this headless browser, not the page
            time.sleep(a.seconds)
            notice = page.get_by_text("Software WebGL rendering detected")
            if notice.count():
                notice.locator("xpath=ancestor::div[contains(@class,'mantine-Notification-root')][1]").locator("button").first.click()
            time.sleep(0.5)
            Path(a.out).parent.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=a.out)
            ctx.close()
    finally:
        app.stop()
    print(f"saved {a.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
