"""A bag replay on the page, in a real browser (Debian's chromium via Playwright): times from
the start of the file, no driving controls, one scrubber over the whole file, and a scrubbed
frame whose local map is the one playing there builds."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from pico_studio.config import Config
from pico_studio.ui.replay import ReplayDriver
from pico_studio.ui.runtime import Studio
from pico_studio.ui.sources import make_source_factory
from tests.ui_browser_helpers import (
    CHROMIUM,
    opened_page,
    served_app,
    set_number,
    wait_until,
)

pytestmark = pytest.mark.browser
sync_api = pytest.importorskip("playwright.sync_api")
if not CHROMIUM.exists():
    pytest.skip("Debian's chromium is not installed (./dev test installs it)", allow_module_level=True)

BAG = Path(__file__).resolve().parent / "data" / "recordings" / "pico_real_2019-05-07.bag"


@pytest.fixture(scope="module")
def app(tmp_path_factory: pytest.TempPathFactory):
    with served_app(tmp_path_factory, source=f"bag:{BAG}") as app:
        yield app


@pytest.fixture(scope="module")
def page(app, tmp_path_factory: pytest.TempPathFactory):
    with opened_page(app, tmp_path_factory, re.compile("recording frame")) as page:
        yield page


def test_a_replay_shows_relative_time_and_no_driving_controls(app, page) -> None:
    page.get_by_role("button", name="Step one frame").click()
    assert wait_until(lambda: app.studio.source.frame_index >= 0)
    text = page.locator("body").inner_text()
    assert re.search(r"recording frame \d+ / 243 · \d+\.\d\d / 6\.80 s", text), text
    assert not re.search(r"\d{9,}\.\d", text)  # no epoch seconds
    assert "behaviour:" not in text
    for hidden in ("Teleop", "Open door"):
        assert not page.get_by_text(hidden).locator("visible=true").count(), hidden
    assert page.get_by_role("slider").locator("visible=true").count() == 1  # one scrubber
    assert "Recording position" not in text


def test_a_scrubbed_frame_has_the_local_map_playing_builds(app, page) -> None:
    k = 120
    reference = Studio(Config(), None, make_source_factory(f"bag:{BAG}", None), behaviour="stop", map_name="ref")
    driver = ReplayDriver(reference)
    while reference.source.frame_index < k:
        driver.step()
    walls = reference.timeline.latest.wm.local_map.walls
    assert len(walls) > 0

    set_number(page, "Timeline", k)
    assert wait_until(lambda: app.studio.source.frame_index == k and not app.studio.playing)
    page.get_by_text(re.compile(f"recording frame {k + 1} / 243")).first.wait_for(timeout=20000)
    shown = app.studio.shown().wm.local_map.walls
    np.testing.assert_allclose(shown, walls)
    assert page.get_by_role("button", name="Play").is_visible()  # paused, and the button says so
