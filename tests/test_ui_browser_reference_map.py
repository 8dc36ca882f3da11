"""The Intel corrected log on the page, in a real browser (Debian's chromium via Playwright):
its reference map (every scan cast from its true pose) is drawn in its colour and can be
toggled off, and the Run tab shows the local map's agreement with it."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from pico_studio.ui import style
from tests.ui_browser_helpers import (
    CHROMIUM,
    count_colour,
    opened_page,
    screenshot,
    served_app,
    wait_until,
)

pytestmark = pytest.mark.browser
sync_api = pytest.importorskip("playwright.sync_api")
if not CHROMIUM.exists():
    pytest.skip("Debian's chromium is not installed (./dev test installs it)", allow_module_level=True)

INTEL = Path(__file__).resolve().parent / "data" / "recordings" / "intel-corrected.log.gz"


@pytest.fixture(scope="module")
def app(tmp_path_factory: pytest.TempPathFactory):
    with served_app(tmp_path_factory, behaviour="stop", source=f"carmen:{INTEL}") as app:
        yield app


@pytest.fixture(scope="module")
def page(app, tmp_path_factory: pytest.TempPathFactory):
    with opened_page(app, tmp_path_factory, re.compile("recording frame")) as page:
        yield page


def test_the_reference_map_is_drawn_and_the_agreement_shown(app, page) -> None:
    assert app.studio.reference is not None and app.studio.reference.ready(timeout=120)
    for _ in range(3):  # a few frames, so there is a local map to judge
        page.get_by_role("button", name="Step one frame").click()
    assert wait_until(lambda: app.studio.source.frame_index >= 2)
    assert wait_until(lambda: count_colour(screenshot(page), style.REFERENCE_MAP) > 300, timeout=30), \
        "the reference map is not drawn"
    assert wait_until(lambda: "Reference map agreement" in page.locator("body").inner_text(), timeout=30)
    text = page.locator("body").inner_text()
    assert re.search(r"this frame \d\.\d\d · run so far \d\.\d\d \(\d+ frames\)", text), text

    page.get_by_role("tab", name="Layers").click()
    page.locator("label", has_text="Reference map (true poses)").click()
    assert wait_until(lambda: count_colour(screenshot(page), style.REFERENCE_MAP) < 20), "the toggle does not hide it"
    page.locator("label", has_text="Reference map (true poses)").click()
    assert wait_until(lambda: count_colour(screenshot(page), style.REFERENCE_MAP) > 300)
