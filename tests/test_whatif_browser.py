"""The What-if tab and the tuner's config panel in a real browser (Debian's chromium, Playwright).

One server (the hospital example, simulated, paused) and one browser for the module; the
tests run in file order: a run is driven, then re-judged, pinned as A, changed into B.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from pico_studio.ui import style
from tests.ui_browser_helpers import (
    CHROMIUM,
    count_colour,
    input_of,
    opened_page,
    screenshot,
    served_app,
    set_number,
    wait_until,
)

pytestmark = pytest.mark.browser
sync_api = pytest.importorskip("playwright.sync_api")
if not CHROMIUM.exists():
    pytest.skip("Debian's chromium is not installed (./dev test installs it)", allow_module_level=True)


@pytest.fixture(scope="module")
def app(tmp_path_factory: pytest.TempPathFactory):
    with served_app(tmp_path_factory, seed=3) as app:
        yield app


@pytest.fixture(scope="module")
def page(app, tmp_path_factory: pytest.TempPathFactory):
    with opened_page(app, tmp_path_factory, "hospital_2019.json") as page:
        yield page


def _chart_mean(page, title: str, label: str) -> float | None:  # noqa: ANN001
    """The mean of series `label` of the chart titled `title`, as the browser holds it."""
    return page.evaluate(
        """([title, label]) => {
          const tp = (window.__viserTestpoints || {}).uplots || {};
          for (const k in tp) {
            const u = tp[k].chart;
            if (!u || (u.root.querySelector('.u-title') || {}).textContent !== title) continue;
            const i = u.series.findIndex(s => s.label === label);
            if (i < 0) return null;
            const v = Array.from(u.data[i]).filter(Number.isFinite);
            return v.length ? v.reduce((a, b) => a + b, 0) / v.length : null;
          }
          return null;
        }""", [title, label])


def _config_section(page, name: str) -> None:  # noqa: ANN001
    page.get_by_role("tab", name="Config").click()
    if not input_of(page, "min_length").count():
        page.get_by_text(name, exact=True).locator("visible=true").first.click()


def test_a_plot_of_the_whole_run_is_there_and_follows_a_slider_change(app, page) -> None:
    page.get_by_role("tab", name="Run").click()
    page.get_by_role("button", name="Play").click()
    assert wait_until(lambda: len(app.studio.timeline) >= 60, 60)
    page.get_by_role("button", name="Pause").click()
    page.get_by_role("tab", name="What-if").click()
    page.get_by_role("button", name="Re-judge now").click()
    assert app.whatif.wait(120)
    n = len(app.studio.timeline)
    page.get_by_text(re.compile(rf"{n} frames")).first.wait_for(timeout=30000)
    assert wait_until(lambda: (_chart_mean(page, "Counts", "count.walls") or 0) > 3, 30), "no counts plot"
    before = _chart_mean(page, "Counts", "count.walls")
    _config_section(page, "scan")
    set_number(page, "min_length", 1.5)
    assert wait_until(lambda: app.studio.cfg.perception.scan.min_length == 1.5)
    assert app.whatif.wait(120)
    page.get_by_role("tab", name="What-if").click()
    assert wait_until(lambda: (_chart_mean(page, "Counts", "count.walls") or before) < before / 2, 30), \
        "the plot did not follow the change"


def test_a_click_on_a_plot_jumps_the_timeline(app, page) -> None:
    page.get_by_role("tab", name="What-if").click()
    n = len(app.studio.timeline)

    def click_a_quarter_in() -> bool:  # a chart re-made by a newer result is hooked within 0.4 s
        over = page.locator(".u-over").first
        over.scroll_into_view_if_needed()
        box = over.bounding_box()
        assert box is not None
        page.mouse.click(box["x"] + box["width"] * 0.25, box["y"] + box["height"] / 2)
        return wait_until(lambda: app.studio.cursor is not None, timeout=2.0)

    assert wait_until(click_a_quarter_in, timeout=30.0, every=0.5)
    assert 0.1 * n < app.studio.cursor < 0.4 * n, app.studio.cursor


def test_pin_as_a_then_b_shows_the_table_and_the_diff_overlay(app, page) -> None:
    page.get_by_role("tab", name="Config").click()
    set_number(page, "min_length", 0.1)  # back to the defaults' detail: A
    assert wait_until(lambda: app.studio.cfg.perception.scan.min_length == 0.1)
    assert app.whatif.wait(120)
    page.get_by_role("tab", name="What-if").click()
    page.get_by_role("button", name="Pin as A").click()
    assert wait_until(lambda: app.whatif.a is not None), [e.line() for e in app.page.log.newest(5)]
    _config_section(page, "scan")
    set_number(page, "min_length", 1.5)  # B: only long walls
    assert wait_until(lambda: app.studio.cfg.perception.scan.min_length == 1.5)
    assert app.whatif.wait(120) and app.whatif.comparable
    page.get_by_role("tab", name="What-if").click()
    page.get_by_text("B − A").first.wait_for(timeout=30000)
    row = page.locator("tr", has_text="walls.recall").first.inner_text()
    assert re.search(r"-0\.\d+", row), row  # B loses wall recall against A
    shown = app.studio.shown()
    lost = app.whatif.overlay(shown.time, app.studio.robot_pose_in_map(shown))
    assert len(lost["walls_lost"]) + len(lost["corners_lost"]) > 0  # what the scene should draw
    assert wait_until(lambda: count_colour(screenshot(page), style.DIFF_LOST) > 100, 30), \
        f"no diff overlay drawn: {count_colour(screenshot(page), style.DIFF_LOST)} px; {len(lost['walls_lost'])} walls"
    # A's series beside B's in the plots
    assert wait_until(lambda: _chart_mean(page, "Counts", "A: count.walls") is not None, 30)


def test_a_partial_import_keeps_the_other_tuned_values(app, page, tmp_path: Path) -> None:
    _config_section(page, "scan")
    set_number(page, "min_length", 0.3)
    assert wait_until(lambda: app.studio.cfg.perception.scan.min_length == 0.3)
    part = tmp_path / "part.yaml"
    part.write_text("perception:\n  scan:\n    max_range: 7.5\n", encoding="utf-8")
    with page.expect_file_chooser() as chooser:
        page.get_by_role("button", name=re.compile("Import config")).click()
    chooser.value.set_files(str(part))
    assert wait_until(lambda: app.studio.cfg.perception.scan.max_range == 7.5)
    assert app.studio.cfg.perception.scan.min_length == 0.3  # the tuned value survives the import
    page.get_by_text(re.compile(r"1 value\(s\) changed: perception\.scan\.max_range")).first.wait_for(timeout=20000)
    assert wait_until(lambda: input_of(page, "min_length").input_value() == "0.3")


def test_search_undo_and_the_diff_view(app, page) -> None:
    page.get_by_role("tab", name="Config").click()
    box = input_of(page, "Search parameters")
    box.fill("connect radius")
    box.press("Enter")
    page.get_by_text("perception.merge.connect_radius", exact=True).first.wait_for(timeout=20000)
    set_number(page, "perception.merge.connect_radius", 0.4)
    assert wait_until(lambda: app.studio.cfg.perception.merge.connect_radius == 0.4)
    page.get_by_role("button", name="Undo").click()
    assert wait_until(lambda: app.studio.cfg.perception.merge.connect_radius != 0.4)
    page.get_by_role("button", name="Redo").click()
    assert wait_until(lambda: app.studio.cfg.perception.merge.connect_radius == 0.4)
    page.get_by_text("Changed parameters", exact=True).first.click()
    page.get_by_text(re.compile(r"\d+ differ from A")).first.wait_for(timeout=20000)
    # an out-of-range number is refused with the field and the range, and the value kept
    set_number(page, "perception.merge.connect_radius", 50)
    page.get_by_text(re.compile(r"perception\.merge\.connect_radius = 50.* refused")).first.wait_for(timeout=20000)
    assert app.studio.cfg.perception.merge.connect_radius == 0.4
