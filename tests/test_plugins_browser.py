"""A plugin on the page, in Debian's chromium: listed, its outputs drawn as a layer, and an
edit of its file reloaded from the page without restarting the server."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import numpy as np
import pytest
from plugin_helpers import unload_all, write_plugin

from pico_studio import plugins
from pico_studio.ui import style
from tests.ui_browser_helpers import (
    CHROMIUM,
    count_colour,
    free_port,
    open_folder,
    opened_page,
    screenshot,
    set_number,
    wait_until,
)

pytestmark = pytest.mark.browser
sync_api = pytest.importorskip("playwright.sync_api")
if not CHROMIUM.exists():
    pytest.skip("Debian's chromium is not installed (./dev test installs it)", allow_module_level=True)

PLUGIN = """
    from dataclasses import dataclass
    import numpy as np
    from pico_studio.core.io import Command
    from pico_studio.plugins import behaviour, emit, param, segmenter

    @dataclass(frozen=True)
    class MarkParams:
        size: float = param(0.4, lo=0.1, hi=2.0, unit="m", help="marker square side")

    @segmenter("marked", MarkParams, help="one piece per cluster, and a marker square")
    def marked(points, params):
        h = params.size / 2
        emit("marker", np.array([[x, y] for x in np.linspace(-h, h, COUNT) for y in (-h, h)]))
        return [(0, len(points) - 1)] if len(points) >= 2 else []

    @behaviour("stand_still")
    class StandStill:
        state = "standing"

        def step(self, world_model, laser, odometry, now, *, ok=True):
            return Command()
"""


@pytest.fixture(scope="module")
def plugin_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    unload_all()
    path = write_plugin(tmp_path_factory.mktemp("plugin"), "marked.py", PLUGIN.replace("COUNT", "3"))
    plugins.load_plugin(str(path))
    yield path
    unload_all()


@pytest.fixture(scope="module")
def app(plugin_file: Path, tmp_path_factory: pytest.TempPathFactory):
    from pico_studio.cli.serve_cmd import build_app

    cfg = tmp_path_factory.mktemp("cfg") / "use.yaml"
    cfg.write_text("perception:\n  scan:\n    segmenter: marked\n", encoding="utf-8")
    args = argparse.Namespace(
        map=None, sim_config=None, config=str(cfg), behaviour="stop", source="sim", host="127.0.0.1",
        port=free_port(), seed=3, export_dir=str(tmp_path_factory.mktemp("exports")), paused=True,
    )
    app = build_app(args, verbose=False)
    for _ in range(3):  # a few perceived frames to show (the page starts paused)
        app.studio.tick(0.05)
    app.start()
    app.redraw()
    yield app
    app.stop()


@pytest.fixture(scope="module")
def page(app, tmp_path_factory: pytest.TempPathFactory):
    with opened_page(app, tmp_path_factory, "hospital_2019.json") as page:
        yield page


def _visible(page, text: str) -> bool:  # noqa: ANN001
    return page.get_by_text(text).locator("visible=true").count() > 0


def test_the_page_lists_the_plugin_and_draws_its_outputs(app, page, plugin_file: Path) -> None:
    page.get_by_role("tab", name="Plugins").click()
    assert wait_until(lambda: _visible(page, "segmenter `marked`") or _visible(page, "segmenter marked")), \
        "the loaded plugin is not listed"
    assert "stand_still" in app.behaviour.dropdown.options  # the page's behaviour list has it
    assert wait_until(lambda: _visible(page, "marker: 6 points"))
    assert wait_until(lambda: count_colour(screenshot(page), style.PLUGIN_OUTPUT) > 0), "no plugin layer drawn"
    page.get_by_role("tab", name="Layers").click()
    page.locator("label", has_text="Plugin outputs").click()
    assert wait_until(lambda: count_colour(screenshot(page), style.PLUGIN_OUTPUT) == 0), "the toggle hides nothing"
    page.locator("label", has_text="Plugin outputs").click()
    assert wait_until(lambda: count_colour(screenshot(page), style.PLUGIN_OUTPUT) > 0)


def _marker_diagonal(app) -> float:  # noqa: ANN001
    pts = app.studio.shown().wm.extras["marker"]
    return float(np.max(np.hypot(*(pts[:, None, :] - pts[None, :, :]).transpose(2, 0, 1))))


def test_the_plugins_slider_reprocesses_the_frame_shown(app, page) -> None:
    assert _marker_diagonal(app) == pytest.approx(0.4 * np.sqrt(2))
    page.get_by_role("tab", name="Config").click()
    open_folder(page, "plugins", "marked")
    open_folder(page, "marked", "size")
    set_number(page, "size", 1.0)
    assert wait_until(lambda: abs(_marker_diagonal(app) - np.sqrt(2)) < 1e-6), "the slider did not reach the plugin"
    assert app.studio.cfg.perception.plugins.marked.size == 1.0


def test_an_edited_plugin_reloads_from_the_page(app, page, plugin_file: Path) -> None:
    page.get_by_role("tab", name="Plugins").click()
    mtime = plugin_file.stat().st_mtime_ns
    plugin_file.write_text(plugin_file.read_text().replace(", 3)", ", 9)"), encoding="utf-8")
    os.utime(plugin_file, ns=(mtime + 10**9, mtime + 10**9))  # a later save, whatever the clock
    assert plugins.changed()  # (the page says so at its next redraw; paused, there is none)
    page.get_by_role("button", name="Reload changed plugins").click()
    assert wait_until(lambda: _visible(page, "plugins reloaded"))
    assert wait_until(lambda: _visible(page, "marker: 18 points")), "the edit did not reach the frame shown"
    assert len(app.prims["plugin_points"]) == 18  # what the page's layer was sent
    assert not _visible(page, "changed on disk")
    assert app.studio.cfg.perception.plugins.marked.size == 1.0  # the slider's value survived the reload


def test_a_broken_edit_is_a_notification_and_the_old_version_keeps_running(app, page, plugin_file: Path) -> None:
    good = plugin_file.read_text()
    plugin_file.write_text(good + "\ndef broken(:\n", encoding="utf-8")
    line = len(good.splitlines()) + 2
    page.get_by_role("button", name="Reload changed plugins").click()
    assert wait_until(lambda: _visible(page, f"marked.py:{line}: SyntaxError")), "no notification naming file and line"
    app.studio.tick(0.05)
    app.redraw()
    assert wait_until(lambda: _visible(page, "marker: 18 points"))
