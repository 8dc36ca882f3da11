"""Driving the page in Debian's chromium with Playwright: launch, find inputs, read pixels."""

from __future__ import annotations

import argparse
import math
import re
import socket
import sys
import threading
import time
import traceback
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import cv2
import numpy as np

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--no-sandbox", "--disable-background-networking", "--disable-gpu", "--no-first-run",
    "--disable-component-update", "--disable-sync",
]
VIEWPORT = {"width": 1200, "height": 800}
PANEL_LEFT = 790  # x where the control panel starts (control_width="large" at 1200 px)
NOTICE = (330, 160)  # the "software WebGL" notification covers this top-left box
LEGEND = (270, 170)  # the on-canvas legend's bottom-left box (style.LEGEND_BOX and its margin)


def thread_stacks() -> str:
    """Every thread's stack, for an assertion message when the page's loop stops."""
    names = {t.ident: t.name for t in threading.enumerate()}
    parts = []
    for ident, frame in sys._current_frames().items():
        parts.append(f"--- thread {names.get(ident, ident)}\n" + "".join(traceback.format_stack(frame)))
    return "\n".join(parts)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def screenshot(page) -> np.ndarray:  # noqa: ANN001 - playwright Page
    """The page as an (H, W, 3) RGB array."""
    png = page.screenshot()
    bgr = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
    return bgr[:, :, ::-1]


def world_to_pixel(client, x: float, y: float) -> tuple[int, int]:  # noqa: ANN001 - viser ClientHandle
    """Where a map point lands on the screen of a tab looking straight down."""
    cam = client.camera
    cx, cy, height = (float(v) for v in cam.position)
    w, h = cam.image_width, cam.image_height
    metres_per_px = 2.0 * height * math.tan(cam.fov / 2.0) / h
    return (round(w / 2 + (x - cx) / metres_per_px), round(h / 2 - (y - cy) / metres_per_px))


def colour_near(img: np.ndarray, px: tuple[int, int], rgb: tuple[int, int, int], radius: int = 3, tol: int = 14) -> bool:
    x, y = px
    patch = img[max(0, y - radius): y + radius + 1, max(0, x - radius): x + radius + 1].astype(int)
    return bool((np.abs(patch - np.array(rgb)).max(axis=-1) <= tol).any())


def count_colour(img: np.ndarray, rgb: tuple[int, int, int], tol: int = 14) -> int:
    view = img[:, :PANEL_LEFT].astype(int).copy()
    view[-LEGEND[1]:, : LEGEND[0]] = 255  # the legend's swatches are not the view's
    return int((np.abs(view - np.array(rgb)).max(axis=-1) <= tol).sum())


def visible_on_screen(px: tuple[int, int], size: tuple[int, int]) -> bool:
    x, y = px
    in_notice = x < NOTICE[0] and y < NOTICE[1]
    in_legend = x < LEGEND[0] and y > size[1] - LEGEND[1]
    return 5 <= x < PANEL_LEFT - 5 and 5 <= y < size[1] - 5 and not in_notice and not in_legend


def wait_until(check: Callable[[], bool], timeout: float = 20.0, every: float = 0.25) -> bool:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if check():
            return True
        time.sleep(every)
    return check()


def input_of(page, label: str):  # noqa: ANN001, ANN201 - playwright types
    """The text/number input in the row of the visible GUI element labelled `label`."""
    lab = page.locator("label", has_text=label).locator("visible=true").first
    row = lab.locator("xpath=ancestor::div[contains(@class,'mantine-Flex-root')][1]")
    return row.locator("input:not([type=hidden])").first


def set_number(page, label: str, value: float) -> None:  # noqa: ANN001
    box = input_of(page, label)
    box.fill(str(value))
    box.press("Enter")


def open_folder(page, title: str, inside: str, *, exact: bool = False) -> None:  # noqa: ANN001
    """Expand the visible GUI folder `title` unless the button or label `inside` shows already
    (`exact`: only that very text: a folder already open stays open — a click would close it,
    as the settings kept in local storage from an earlier test may have left it)."""
    if page.get_by_text(inside, exact=exact).locator("visible=true").count():
        return
    page.get_by_text(title, exact=True).locator("visible=true").first.click()
    page.get_by_text(inside, exact=exact).locator("visible=true").first.wait_for(timeout=20000)


@contextmanager
def served_app(tmp_path_factory: Any, **args: Any) -> Iterator[Any]:
    """`pico-studio serve` in this process on a free port, paused, exporting into a temporary
    folder (keyword arguments override serve's options), stopped afterwards."""
    from pico_studio.cli.serve_cmd import build_app

    options: dict[str, Any] = dict(
        map=None, sim_config=None, config=None, behaviour="wander", source="sim", host="127.0.0.1",
        port=free_port(), seed=None, export_dir=str(tmp_path_factory.mktemp("exports")), paused=True,
    )
    options.update(args)
    app = build_app(argparse.Namespace(**options), verbose=False)
    app.start()
    try:
        yield app
    finally:
        app.stop()


@contextmanager
def opened_page(app: Any, tmp_path_factory: Any, ready: str | re.Pattern[str]) -> Iterator[Any]:
    """Debian's chromium (its own profile, so local storage works) on the app's page, once
    `ready` is on it; closed afterwards."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        ctx = p.chromium.launch_persistent_context(
            str(tmp_path_factory.mktemp("chromium-profile")), executable_path=str(CHROMIUM), headless=True,
            args=CHROMIUM_ARGS, viewport=VIEWPORT,
        )
        try:
            page = ctx.new_page()
            page.goto(app.url + "/?fixedDpr=1")
            page.get_by_text(ready).first.wait_for(timeout=30000)
            yield page
        finally:
            ctx.close()
