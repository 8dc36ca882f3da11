"""The web page in a real browser: Debian's chromium driven by Playwright (never downloaded).

One server (the default hospital example, simulated, started paused so the first screenshot
shows the map alone) and one browser for the module; the tests run in file order.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from pico_studio.config import loads_config, to_dict
from pico_studio.core.geometry import point_segment_distance
from pico_studio.ui import style
from pico_studio.ui.app import SETTINGS_KEY
from tests.ui_browser_helpers import (
    CHROMIUM,
    CHROMIUM_ARGS,
    VIEWPORT,
    colour_near,
    count_colour,
    input_of,
    open_folder,
    screenshot,
    served_app,
    set_number,
    visible_on_screen,
    wait_until,
    world_to_pixel,
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
def browser(tmp_path_factory: pytest.TempPathFactory):
    with sync_api.sync_playwright() as p:
        ctx = p.chromium.launch_persistent_context(
            str(tmp_path_factory.mktemp("chromium-profile")), executable_path=str(CHROMIUM), headless=True,
            args=CHROMIUM_ARGS, viewport=VIEWPORT, accept_downloads=True,
        )
        yield ctx
        ctx.close()


@pytest.fixture(scope="module")
def page(app, browser):
    page = browser.new_page()
    page.goto(app.url + "/?fixedDpr=1")
    page.get_by_text("hospital_2019.json").first.wait_for(timeout=30000)
    return page


def _client(app):
    clients = list(app.server.get_clients().values())
    assert clients, "no browser tab is connected"
    return clients[-1]


def _wall_hits(app, img: np.ndarray, colours=(style.MAP_WALL,), walls=None, client=None) -> tuple[int, int]:  # noqa: ANN001
    """How many on-screen wall midpoints (of `walls`, indices; default all) show one of
    `colours`, out of how many."""
    client = client or _client(app)
    segs = app.studio.global_map.wall_segments
    segs = segs if walls is None else segs[walls]
    mids = (segs[:, :2] + segs[:, 2:]) / 2
    px = [world_to_pixel(client, x, y) for x, y in mids]
    px = [p for p in px if visible_on_screen(p, (img.shape[1], img.shape[0]))]
    return sum(any(colour_near(img, p, c) for c in colours) for p in px), len(px)


def _camera_still(client) -> bool:  # noqa: ANN001
    before = tuple(client.camera.position)
    time.sleep(0.3)
    return tuple(client.camera.position) == pytest.approx(before, abs=1e-6)


def test_page_loads_and_connects(app, page) -> None:
    assert wait_until(lambda: len(app.server.get_clients()) >= 1)
    assert page.get_by_text("paused").first.is_visible()


def test_screenshot_shows_the_map_walls(app, page) -> None:
    def drawn() -> bool:
        hits, total = _wall_hits(app, screenshot(page))
        return total >= 10 and hits >= 0.9 * total

    assert wait_until(drawn), "the map's walls are not drawn in their colour where they are"


def test_toggling_a_layer_hides_it(app, page) -> None:
    page.get_by_role("tab", name="Layers").click()
    page.locator("label", has_text="Global map").click()
    assert wait_until(lambda: _wall_hits(app, screenshot(page))[0] == 0), "walls still drawn with the layer off"
    page.locator("label", has_text="Global map").click()
    assert wait_until(lambda: _wall_hits(app, screenshot(page))[0] > 0)


def _seen(app) -> np.ndarray:
    if app.studio.shown() is None:  # a test run alone (or on another xdist worker): one frame first
        with app.studio.lock:
            while app.studio.shown() is None:
                app.studio.tick(0.05)
        app.redraw()
    return np.asarray(app.studio.shown().wm.combined.map_wall_seen, dtype=bool)


COVERING = ("laser", "local_walls", "combined", "local_endpoints", "corners")


def _uncovered(app, walls: np.ndarray, covering: tuple[str, ...] = COVERING) -> np.ndarray:
    """Those of `walls` whose middle none of the `covering` prims is drawn over."""
    segs = app.studio.global_map.wall_segments[walls]
    mids = (segs[:, :2] + segs[:, 2:]) / 2
    near = np.zeros(len(walls), bool)
    for name in covering:
        data = app.prims[name].data
        if len(data):
            d = point_segment_distance(mids, data) if data.shape[1] == 4 else np.hypot(*(mids[:, None] - data[None]).T).T
            near |= d.min(axis=1) < 0.2
    return walls[~near]


def test_never_seen_walls_show_dashed_then_as_seen(app, page) -> None:
    """One frame in: the map's walls not seen yet carry the never-seen colour on their
    middles; after the robot has looked around, those it saw show as plain map walls."""
    page.get_by_role("tab", name="Run").click()
    page.get_by_role("button", name="Step one frame").click()
    assert wait_until(lambda: app.layers.sizes["combined_unseen"] > 0)  # drawn
    unseen = _uncovered(app, np.flatnonzero(~_seen(app)))

    def dashed() -> bool:
        hits, total = _wall_hits(app, screenshot(page), (style.COMBINED_UNSEEN,), unseen)
        return total >= 10 and hits >= 0.9 * total

    assert wait_until(dashed), "never-seen walls are not drawn in their colour"
    # drive on (server side, paused: as many frames as it takes, whatever the load)
    # a seen wall shows the map's colour, or the local / combined map's wall drawn on it
    markers = ("laser", "local_endpoints", "corners", "current", "trail", "possible_doors", "doors")

    def seen_now() -> np.ndarray:
        return _uncovered(app, np.intersect1d(unseen, np.flatnonzero(_seen(app))), markers)

    def seen_and_clear() -> int:
        return len(seen_now())

    for _ in range(60):
        if seen_and_clear() >= 4:
            break
        with app.studio.lock:
            for _ in range(20):
                app.studio.tick(0.05)
        app.redraw()
    assert seen_and_clear() >= 4
    now_seen = seen_now()

    def plain() -> bool:  # a seen wall: the map's colour, or the combined/local map's wall on it
        img = screenshot(page)
        hits, total = _wall_hits(app, img, (style.MAP_WALL, style.COMBINED_MATCHED, style.COMBINED_UNMATCHED, style.LOCAL_WALL), now_seen)
        dashes, _ = _wall_hits(app, img, (style.COMBINED_UNSEEN,), now_seen)
        return total >= 3 and hits >= 0.9 * total and dashes == 0

    if not wait_until(plain):
        img = screenshot(page)
        found = {name: _wall_hits(app, img, (c,), now_seen) for name, c in (
            ("map", style.MAP_WALL), ("matched", style.COMBINED_MATCHED), ("local", style.LOCAL_WALL),
            ("unseen", style.COMBINED_UNSEEN), ("unmatched", style.COMBINED_UNMATCHED), ("current", style.CURRENT_MAP))}
        pytest.fail(f"walls the robot saw are still drawn as never seen: {found}")


def _current_count(page) -> int:
    text = page.locator("body").inner_text()
    m = re.search(r"current map (\d+)", text)
    return int(m.group(1)) if m else -1


def test_slider_changes_drawing_and_metric(app, page) -> None:
    page.get_by_role("tab", name="Run").click()
    page.get_by_role("button", name="Play").click()
    assert wait_until(lambda: len(app.studio.timeline) >= 40)
    page.get_by_role("button", name="Pause").click()
    assert wait_until(lambda: _current_count(page) > 0)
    before_count = _current_count(page)
    page.get_by_role("tab", name="Layers").click()
    for covering in ("Laser points", "Proximity bubble"):  # drawn over the current map
        page.locator("label", has_text=covering).click()
    assert wait_until(lambda: count_colour(screenshot(page), style.CURRENT_MAP) > 50), "the current map is not drawn"
    before_px = count_colour(screenshot(page), style.CURRENT_MAP)

    page.get_by_role("tab", name="Config").click()
    open_folder(page, "scan", "min_length")
    set_number(page, "min_length", 5.0)
    assert wait_until(lambda: app.studio.cfg.perception.scan.min_length == 5.0)
    page.get_by_role("tab", name="Run").click()
    assert wait_until(lambda: _current_count(page) < before_count), "the metric did not change"
    assert wait_until(lambda: count_colour(screenshot(page), style.CURRENT_MAP) < before_px / 4), "the drawing did not change"
    page.get_by_role("tab", name="Layers").click()
    for covering in ("Laser points", "Proximity bubble"):
        page.locator("label", has_text=covering).click()


def test_timeline_scrubs_back_and_returns_to_live(app, page) -> None:
    page.get_by_role("tab", name="Run").click()
    set_number(page, "Timeline", 5)
    assert wait_until(lambda: app.studio.cursor == 5 and not app.studio.playing)
    page.get_by_text(re.compile(r"timeline frame \d+")).first.wait_for(timeout=20000)
    assert app.studio.shown().wm is not None  # re-processed with the current config
    page.get_by_role("button", name="Back to live").click()
    assert wait_until(lambda: app.studio.cursor is None and app.studio.playing)
    page.get_by_role("button", name="Pause").click()
    assert wait_until(lambda: not app.studio.playing)


def test_export_downloads_the_live_config(app, page, tmp_path: Path) -> None:
    app.config.edit("perception.scan.min_length", 0.55)  # what a user's edit does
    page.get_by_role("tab", name="Config").click()
    with page.expect_download(timeout=20000) as info:
        page.get_by_role("button", name="Export config (YAML)").click()
    path = tmp_path / "exported.yaml"
    info.value.save_as(path)
    text = path.read_text()
    assert to_dict(loads_config(text)) == to_dict(app.studio.cfg)
    assert loads_config(text).perception.scan.min_length == 0.55  # the tuned value went out
    check = subprocess.run(
        [sys.executable, "-m", "pico_studio", "config", "check", str(path)], capture_output=True, text=True
    )
    assert check.returncode == 0, check.stderr
    assert app.last_export is not None and app.last_export.read_text() == text
    assert page.get_by_text(str(app.last_export)).first.is_visible()


def test_broken_map_upload_shows_the_error_and_the_page_keeps_working(app, page, tmp_path: Path) -> None:
    tuned = 0.45
    app.config.edit("perception.scan.min_length", tuned)
    bad = tmp_path / "broken_map.json"
    bad.write_text(json.dumps({"points": [{"x": 0, "y": 0}], "walls": [[0, 7]]}))
    page.get_by_role("tab", name="Run").click()
    open_folder(page, "Map", "Upload map")
    with page.expect_file_chooser() as chooser:
        page.get_by_role("button", name=re.compile("Upload map")).click()
    chooser.value.set_files(str(bad))
    page.get_by_text(re.compile(r"broken_map\.json")).first.wait_for(timeout=20000)
    assert app.studio.map_name == "hospital_2019.json"
    assert app.studio.cfg.perception.scan.min_length == tuned  # nothing tuned is lost
    frames = len(app.studio.timeline)
    page.get_by_role("button", name="Step one frame").click()
    assert wait_until(lambda: len(app.studio.timeline) == frames + 1)


def test_an_invalid_value_is_reported_and_reverted(app, page) -> None:
    page.get_by_role("tab", name="Config").click()
    open_folder(page, "ui", "wander", exact=True)  # (a folder open already stays open)
    open_folder(page, "wander", "clear_distance", exact=True)
    before = app.studio.cfg.ui.wander.clear_distance
    set_number(page, "clear_distance", 0.2)  # below stop_distance: the declared ordering refuses it
    page.get_by_text(re.compile("must be at most clear_distance")).first.wait_for(timeout=20000)
    assert app.studio.cfg.ui.wander.clear_distance == before
    assert wait_until(lambda: float(input_of(page, "clear_distance").input_value()) == before)


def test_a_second_tab_sees_the_scene(app, page, browser) -> None:
    second = browser.new_page()
    try:
        _second_tab_checks(app, page, second)
    finally:  # later tests talk to the first tab only
        second.close()
        assert wait_until(lambda: len(app.server.get_clients()) == 1)


def _second_tab_checks(app, page, second) -> None:  # noqa: ANN001
    second.goto(app.url + "/?fixedDpr=1")
    second.get_by_text("hospital_2019.json").first.wait_for(timeout=30000)
    assert wait_until(lambda: len(app.server.get_clients()) >= 2)

    client2 = list(app.server.get_clients().values())[-1]
    colours = (style.MAP_WALL, style.COMBINED_UNSEEN)  # seen or never-seen walls

    def drawn() -> bool:
        hits, total = _wall_hits(app, screenshot(second), colours, client=client2)
        return total >= 10 and hits >= 0.5 * total

    assert wait_until(drawn)
    second.keyboard.press("w")
    assert wait_until(lambda: app.studio.behaviour_name == "teleop"), "the W key did not drive the robot"
    # hold the scene still, so the never-seen walls do not change while the tabs are compared
    if app.studio.playing:
        second.get_by_role("button", name="Pause").click()
        assert wait_until(lambda: not app.studio.playing)
    unseen = _uncovered(app, np.flatnonzero(~_seen(app)))
    # the layer toggles are per tab: hiding the combined map here leaves the first tab's alone
    second.get_by_role("tab", name="Layers").click()
    second.locator("label", has_text="Combined map").click()
    dashed = (style.COMBINED_UNSEEN,)
    assert wait_until(lambda: _wall_hits(app, screenshot(second), dashed, unseen, client2)[0] == 0)
    client1 = list(app.server.get_clients().values())[0]

    def first_tab_shows_them() -> bool:
        hits, total = _wall_hits(app, screenshot(page), dashed, unseen, client1)
        return total >= 5 and hits >= 0.9 * total

    assert wait_until(first_tab_shows_them)
    # so is Follow: the second tab's view centres on the robot, the first tab's stays put
    before = tuple(client1.camera.position)
    second.locator("label", has_text="Follow robot").click()
    robot = app.studio.robot_pose_in_map(app.studio.shown())
    assert wait_until(lambda: abs(client2.camera.position[1] - robot[1]) < 0.05), "the second tab does not follow"
    assert tuple(client1.camera.position) == pytest.approx(before)


def test_import_yaml_sets_the_sliders_and_a_bad_one_is_reported(app, page, tmp_path: Path) -> None:
    page.get_by_role("tab", name="Config").click()
    open_folder(page, "scan", "min_length")
    good = tmp_path / "tuned.yaml"
    good.write_text("perception:\n  scan:\n    min_length: 0.3\n")
    with page.expect_file_chooser() as chooser:
        page.get_by_role("button", name=re.compile("Import config")).click()
    chooser.value.set_files(str(good))
    assert wait_until(lambda: app.studio.cfg.perception.scan.min_length == 0.3)
    assert wait_until(lambda: input_of(page, "min_length").input_value() == "0.3")
    bad = tmp_path / "typo.yaml"
    bad.write_text("perception:\n  scan:\n    min_lenght: 0.3\n")
    with page.expect_file_chooser() as chooser:
        page.get_by_role("button", name=re.compile("Import config")).click()
    chooser.value.set_files(str(bad))
    page.get_by_text(re.compile("did you mean 'min_length'")).first.wait_for(timeout=20000)
    assert app.studio.cfg.perception.scan.min_length == 0.3  # the tuned config is kept


def test_click_on_a_wall_shows_its_numbers(app, page) -> None:
    page.get_by_role("tab", name="Tools").click()
    client = _client(app)
    img = screenshot(page)
    segs = app.studio.global_map.wall_segments
    lengths = np.hypot(segs[:, 2] - segs[:, 0], segs[:, 3] - segs[:, 1])
    for i in np.argsort(-lengths):
        mid = (segs[i, :2] + segs[i, 2:]) / 2
        px = world_to_pixel(client, *mid)
        if visible_on_screen(px, (img.shape[1], img.shape[0])):
            break
    page.mouse.click(*px)
    page.get_by_text(re.compile(r"wall.*length .* m.*from the click")).first.wait_for(timeout=20000)


def test_two_clicks_measure_a_distance(app, page) -> None:
    page.get_by_role("tab", name="Tools").click()
    input_of(page, "Click does").click()
    page.get_by_role("option", name="measure").click()
    assert wait_until(lambda: app.tools.mode(app.tabs[_client(app).client_id]) == "measure")
    client = _client(app)
    tab = app.tabs[client.client_id]
    assert wait_until(lambda: _camera_still(client)), "the view keeps moving"
    a, b = world_to_pixel(client, 1.0, 1.0), world_to_pixel(client, 3.0, 1.0)
    for _ in range(3):  # the first click after choosing in the dropdown may only close its list
        page.mouse.click(*a)
        if wait_until(lambda: tab.handles["tools"]["measure_from"] is not None, timeout=5.0):
            break
    assert tab.handles["tools"]["measure_from"] is not None, "the first click did not arrive"
    page.get_by_text(re.compile("click the second")).first.wait_for(timeout=20000)
    page.mouse.click(*b)
    text = page.get_by_text(re.compile(r"distance \d+\.\d+ m")).first
    text.wait_for(timeout=20000)
    metres = float(re.search(r"distance (\d+\.\d+) m", text.inner_text()).group(1))
    assert metres == pytest.approx(2.0, abs=0.05)  # one pixel is about 1 cm here


# (prim, its colour) drawn side by side on the floor; grouped as the pairs that used to clash
PALETTE_CHECKS = [
    ("doors", style.DOOR), ("combined", style.COMBINED_MATCHED),
    ("corners", style.ENDPOINT[2]), ("possible_doors", style.POSSIBLE_DOOR_KIND["convex_loose"]),
    ("combined_unseen", style.COMBINED_UNSEEN), ("sim_world", style.SIM_WORLD),
    ("local_endpoints", style.ENDPOINT[0]), ("room_side", style.ROOM_SIDE), ("trail", style.TRAIL),
    ("laser", style.LASER), ("flagged", style.PROXIMITY_FLAGGED), ("local_walls", style.LOCAL_WALL),
]


PER_ITEM = {"combined", "possible_doors", "local_endpoints", "corners", "room_side"}


def test_layers_show_distinct_colours_on_screen(app, page) -> None:
    """Each prim of the pairs that used to share a colour, drawn on an empty patch of floor:
    the pixels there show its own colour, and not its partner's."""
    from pico_studio.ui.scene_data import Prim

    page.get_by_role("tab", name="Run").click()
    if app.studio.playing:
        page.get_by_role("button", name="Pause").click()
    assert wait_until(lambda: not app.studio.playing)
    client = _client(app)
    assert wait_until(lambda: _camera_still(client))
    walls = app.studio.global_map.wall_segments
    x0, y0, x1, y1 = app.studio.global_map.bounds
    spots = []
    for y in np.arange(y0 + 0.6, y1 - 0.6, 0.5):  # free floor: 0.5 m from any wall
        for x in np.arange(x0 + 0.6, x1 - 1.2, 0.5):
            seg = np.array([[x, y, x + 0.6, y]])
            mid = np.array([[x + 0.3, y]])
            px = world_to_pixel(client, x + 0.3, y)
            if point_segment_distance(mid, walls).min() > 0.5 and visible_on_screen(px, (1200, 800)):
                spots.append((seg, px))
    assert len(spots) >= len(PALETTE_CHECKS)
    spots = spots[:: max(1, len(spots) // len(PALETTE_CHECKS))][: len(PALETTE_CHECKS)]
    empty = {name: Prim(p.kind, np.zeros((0, 4 if p.kind == "segments" else 2))) for name, p in app.prims.items()}
    drawn = dict(empty)
    for (name, colour), (seg, _px) in zip(PALETTE_CHECKS, spots, strict=True):
        kind = empty[name].kind
        data = seg if kind == "segments" else np.array([[seg[0, 0] + 0.3, seg[0, 1]]])
        per_item = name in PER_ITEM  # a node keeps the way it was made: one colour, or one per item
        drawn[name] = Prim(kind, data, np.array([colour], np.uint8) if per_item else None)
    with app._draw_lock:  # hold the loop's redraws off while the screen is read
        app.layers.update(drawn)
        try:
            def each_shows_its_colour() -> bool:
                img = screenshot(page)
                return all(colour_near(img, px, colour, radius=2) for (_n, colour), (_s, px) in zip(PALETTE_CHECKS, spots, strict=True))

            if not wait_until(each_shows_its_colour):
                img = screenshot(page)
                wrong = [(n, c, tuple(img[px[1], px[0]])) for (n, c), (_s, px) in zip(PALETTE_CHECKS, spots, strict=True)
                         if not colour_near(img, px, c, radius=2)]
                pytest.fail(f"layers not showing their colour (prim, declared, pixel): {wrong}")
            img = screenshot(page)
            pairs = [(0, 1), (2, 3), (4, 5), (6, 7), (6, 8), (7, 8), (9, 10)]
            for a, b in pairs:  # and not its old partner's
                assert not colour_near(img, spots[a][1], PALETTE_CHECKS[b][1], radius=1, tol=10), (PALETTE_CHECKS[a], PALETTE_CHECKS[b])
        finally:
            app.layers.update(app.prims)


def test_settings_survive_a_reload(app, page) -> None:
    page.get_by_role("tab", name="Layers").click()
    page.locator("label", has_text="Laser points").click()
    tab = app.tabs[_client(app).client_id]
    assert wait_until(lambda: tab.settings["layers"]["laser"] is False)
    page.locator("label", has_text="Legend on the view").click()
    assert wait_until(lambda: tab.settings["legend"] is False)

    def stored() -> bool:  # the browser has both before it reloads
        text = tab.client.local_storage.get_item(SETTINGS_KEY, timeout=10.0) or "{}"
        saved = json.loads(text)
        return saved.get("legend") is False and saved.get("layers", {}).get("laser") is False

    assert wait_until(stored), "the settings did not reach the browser's storage"
    page.reload()
    page.get_by_text("hospital_2019.json").first.wait_for(timeout=30000)
    assert wait_until(lambda: len(app.tabs) >= 1 and _client(app).client_id != tab.client_id)
    new = app.tabs[_client(app).client_id]
    assert wait_until(lambda: new.settings.get("restored")), "saved settings were not read back"
    assert new.settings["layers"]["laser"] is False and not new.toggles.visible["laser"]
    assert new.settings["legend"] is False
    page.get_by_role("tab", name="Layers").click()
    assert not page.get_by_role("checkbox", name="Laser points").is_checked()
    assert page.locator("#pico-legend").evaluate("d => d.style.display") == "none"
    page.locator("label", has_text="Laser points").click()  # back as it was, for the next tests
    page.locator("label", has_text="Legend on the view").click()
    assert wait_until(lambda: new.settings["layers"]["laser"] and new.settings["legend"])


def test_a_map_warning_shows_in_the_log_and_help_opens(app, page) -> None:
    from pico_studio.ui.sources import DEFAULT_MAP, example_maps

    page.get_by_role("tab", name="Run").click()
    open_folder(page, "Map", "Upload map")
    input_of(page, "Example").click()
    page.get_by_role("option", name="hospital_2019_with_nodes.json").click()
    try:
        assert wait_until(lambda: app.studio.map_name == "hospital_2019_with_nodes.json")
        assert wait_until(lambda: app.studio.playing and app.layers.sizes["robot_true"] > 0)  # plays at once, robot drawn
        page.get_by_role("tab", name="Log").click()
        page.get_by_text(re.compile(r"warning · t = .* · map: hospital_2019_with_nodes.json: .*duplicates")).first.wait_for(timeout=20000)
    finally:
        app.switch_map(DEFAULT_MAP, DEFAULT_MAP.name, None)
        assert "hospital_2019.json" in example_maps()
    page.keyboard.press("h")
    page.get_by_text("Layers and their colours").first.wait_for(timeout=20000)
    page.get_by_role("button", name="Close").click()
