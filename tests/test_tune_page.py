"""The page's Tune tab in a real browser: a study on the current map started from the page,
watched live, its best trial applied and exported; a bad glob is reported, the page stays up."""

from __future__ import annotations

from pathlib import Path

import pytest

from pico_studio.config import Config, loads_config, with_value
from tests import test_ui_browser as browser_tests
from tests.ui_browser_helpers import input_of, set_number, wait_until

pytestmark = pytest.mark.browser  # skipped with the browser tests when chromium or playwright is absent

PARAMS = "perception.merge.confirm_hits,perception.merge.min_length"
# one server (the default hospital, simulated, paused) and one browser, as the browser tests'
app, browser, page = browser_tests.app, browser_tests.browser, browser_tests.page


@pytest.fixture(scope="module")
def tune_page(page):  # noqa: ANN001 - the page of the browser tests, on the Tune tab
    page.get_by_role("tab", name="Tune").click()
    return page


def _set_text(page, label: str, text: str) -> None:  # noqa: ANN001
    box = input_of(page, label)
    box.fill(text)
    box.press("Enter")


def test_a_study_from_the_page_improves_a_bad_config_and_is_applied(app, tune_page, tmp_path: Path) -> None:
    page = tune_page
    bad = with_value(with_value(Config(), "perception.merge.confirm_hits", 40), "perception.merge.min_length", 1.5)
    app.apply_config(bad)  # a deliberately bad start: what the page has now is the start trial
    _set_text(page, "Parameters", PARAMS)
    set_number(page, "Trials", 8)
    set_number(page, "Poses", 2)
    assert wait_until(lambda: app.tune.trials.value == 8 and app.tune.globs.value == PARAMS, timeout=60), (
        app.tune.trials.value, app.tune.globs.value, app.tune.poses.value)
    page.get_by_role("button", name="Start study").click()
    assert wait_until(lambda: app.tune.live is not None and not app.tune.live.running
                      and "done" in app.tune.status.content, timeout=300)
    page.get_by_text("8/8 trials").first.wait_for(timeout=60000)  # the status as the tab shows it
    assert page.locator(".uplot canvas").locator("visible=true").count() >= 1  # the live plot
    x, values, best = app.tune.plot.data
    assert len(x) >= 2 and best[-1] == max(values) and best[-1] > values[0]  # improved on the start
    chosen = str(app.tune.choice.value)
    page.get_by_role("button", name="Apply to the config").click()
    n = int(chosen[1:])
    want = app.tune.live.config_of(n)
    assert wait_until(lambda: app.studio.cfg == want, timeout=60)
    assert app.studio.cfg.perception.merge.confirm_hits < 40 or app.studio.cfg.perception.merge.min_length < 1.5
    with page.expect_download(timeout=60000) as info:
        page.get_by_role("button", name="Export as YAML").click()
    path = tmp_path / "trial.yaml"
    info.value.save_as(path)
    assert loads_config(path.read_text()) == want


def test_a_bad_glob_is_reported_and_the_page_keeps_working(app, tune_page) -> None:
    page = tune_page
    _set_text(page, "Parameters", "perception.nope.*")
    assert wait_until(lambda: app.tune.globs.value == "perception.nope.*", timeout=60)
    page.get_by_role("button", name="Start study").click()
    page.get_by_text("perception.nope.*", exact=False).locator("visible=true").first.wait_for(timeout=60000)
    assert wait_until(lambda: any("perception.nope.*" in e.message for e in app.log.all()), timeout=60)
    assert page.get_by_role("button", name="Start study").is_enabled()
