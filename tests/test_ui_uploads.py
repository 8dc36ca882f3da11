"""Bad uploads and bad client messages against the real page (Debian's chromium via
Playwright): junk, huge, truncated, wrong-type files through the upload buttons, then a
valid map; GUI values, camera and pointer messages no page would send, through viser's
real message dispatch. The server stays up, the tab that sent it gets a notification, and
another tab is unaffected.
"""

from __future__ import annotations

import asyncio
import json
import math
import re
import struct
import zlib
from pathlib import Path

import pytest

from tests.ui_browser_helpers import (
    CHROMIUM,
    CHROMIUM_ARGS,
    VIEWPORT,
    open_folder,
    served_app,
    thread_stacks,
    wait_until,
)

pytestmark = pytest.mark.browser
sync_api = pytest.importorskip("playwright.sync_api")
if not CHROMIUM.exists():
    pytest.skip("Debian's chromium is not installed (./dev test installs it)", allow_module_level=True)

MAPS = Path(__file__).resolve().parents[1] / "examples" / "maps"
UPLOAD_CAP_MB = "1"


@pytest.fixture(scope="module")
def app(tmp_path_factory: pytest.TempPathFactory):
    mp = pytest.MonkeyPatch()
    mp.setenv("PICO_STUDIO_MAX_UPLOAD_MB", UPLOAD_CAP_MB)  # read at each upload: 1 MB, so "huge" is quick
    with served_app(tmp_path_factory, seed=3, paused=False) as app:
        yield app
    mp.undo()


@pytest.fixture(scope="module")
def browser(tmp_path_factory: pytest.TempPathFactory):
    with sync_api.sync_playwright() as p:
        ctx = p.chromium.launch_persistent_context(
            str(tmp_path_factory.mktemp("chromium-profile")), executable_path=str(CHROMIUM), headless=True,
            args=CHROMIUM_ARGS, viewport=VIEWPORT,
        )
        yield ctx
        ctx.close()


@pytest.fixture(scope="module")
def tabs(app, browser):
    """(the tab that uploads, a bystander tab)."""
    pages = []
    for _ in range(2):
        page = browser.new_page()
        page.goto(app.url + "/?fixedDpr=1")
        page.get_by_text("hospital_2019.json").first.wait_for(timeout=30000)
        pages.append(page)
    assert wait_until(lambda: len(app.server.get_clients()) == 2)
    return pages


def _png_header(width: int, height: int) -> bytes:
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(b"\0" * 100)) + chunk(b"IEND", b"")


def _upload(page, path: Path, button: str = "Upload map") -> None:  # noqa: ANN001 - playwright Page
    page.get_by_role("tab", name="Run").click()
    open_folder(page, "Map", button)
    with page.expect_file_chooser() as chooser:
        page.get_by_role("button", name=re.compile(button)).click()
    chooser.value.set_files(str(path))


def _still_serving(app, frames_before: int) -> bool:
    if wait_until(lambda: app.studio.frame_count > frames_before + 5):
        return True
    entries = "\n".join(f"{e.level} {e.stage}: {e.message}" for e in app.log.newest(20))
    pytest.fail(f"the loop stopped at frame {app.studio.frame_count} (playing: {app.studio.playing})\n"
                f"log:\n{entries}\n{thread_stacks()}")


HOSPITAL_JSON = (MAPS / "hospital_2019.json").read_text()
BAD_UPLOADS = [
    ("junk.json", bytes(range(256)) * 16, "not a text file"),
    ("huge.json", b" " * (2 << 20), "over the 1 MB upload limit"),
    ("truncated.json", HOSPITAL_JSON[: len(HOSPITAL_JSON) // 2].encode(), "not valid JSON"),
    ("notes.txt", b"hello", "upload one of .json, .png, .pgm"),
    ("map_as.png", HOSPITAL_JSON.encode(), "not a PNG/PGM image"),
    ("claims_20000.png", _png_header(20000, 20000), "over the 25 Mpx limit"),
    ("deep.json", b"[" * 50_000 + b"]" * 50_000, "nested deeper than 64 levels"),
    ("empty.json", b"", "not valid JSON"),
    ("far.json", json.dumps({"points": [{"x": 1e308, "y": 0}, {"x": 0, "y": 1}], "walls": [[0, 1]]}).encode(),
     "beyond the 10 km"),
]


@pytest.mark.parametrize(("name", "content", "message"), BAD_UPLOADS, ids=[b[0] for b in BAD_UPLOADS])
def test_bad_map_upload_is_refused_in_its_tab_only(app, tabs, tmp_path: Path, name: str, content: bytes,
                                                   message: str) -> None:
    uploader, bystander = tabs
    path = tmp_path / name
    path.write_bytes(content)
    frames = app.studio.frame_count
    _upload(uploader, path)
    uploader.get_by_text(re.compile(re.escape(message))).first.wait_for(timeout=20000)
    assert app.studio.map_name == "hospital_2019.json"
    assert _still_serving(app, frames)
    assert len(app.server.get_clients()) == 2
    assert bystander.get_by_text(re.compile(re.escape(message))).count() == 0


def test_bad_config_upload_is_refused(app, tabs, tmp_path: Path) -> None:
    uploader, _ = tabs
    before = app.studio.cfg
    for name, body, message in [
        ("dup.yaml", "sim:\n  seed: 1\n  seed: 2\n", "duplicate key 'seed'"),
        ("huge.yaml", "#" * (2 << 20), "over the 1 MB upload limit"),
        ("deep.yaml", "sim: " + "[" * 5000 + "]" * 5000 + "\n", "nested deeper than 64 levels"),
    ]:
        path = tmp_path / name
        path.write_text(body)
        uploader.get_by_role("tab", name="Config").click()
        with uploader.expect_file_chooser() as chooser:
            uploader.get_by_role("button", name=re.compile("Import config")).click()
        chooser.value.set_files(str(path))
        uploader.get_by_text(re.compile(re.escape(message))).first.wait_for(timeout=20000)
    assert app.studio.cfg == before


def _dispatch(app, client_id: int, message) -> None:  # noqa: ANN001 - a viser message
    """Hand a message to viser's real dispatch, as if the tab had sent it."""
    ws = app.server._websock_server
    future = asyncio.run_coroutine_threadsafe(ws._handle_incoming_message(client_id, message), ws._background_event_loop)
    future.result(timeout=10)


def _dispatch_camera(app, client, message) -> None:  # noqa: ANN001
    conn = client._websock_connection
    loop = app.server._websock_server._background_event_loop
    asyncio.run_coroutine_threadsafe(conn._handle_incoming_message(client.client_id, message), loop).result(timeout=10)


def test_values_no_page_would_send_are_refused(app, tabs) -> None:
    from viser import _messages

    uploader, bystander = tabs
    client = list(app.server.get_clients().values())[0]
    speed = app.run.speed  # the Run tab's speed dropdown
    number = next(h for h in app.server.gui._gui_input_handle_from_uuid.values()
                  if isinstance(h._impl.value, float) and not isinstance(h._impl.value, bool))
    before_number, before_speed = number.value, speed.value
    frames = app.studio.frame_count
    for uuid, updates in [
        (number._impl.uuid, {"value": "abc"}),  # was: "Task exception was never retrieved"
        (number._impl.uuid, {"value": float("nan")}),
        (number._impl.uuid, {"value": [1, 2]}),
        (number._impl.uuid, {"no_such_property": 1}),
        (speed._impl.uuid, {"value": "warp 9"}),
        (speed._impl.uuid, {"value": 3}),
    ]:
        _dispatch(app, client.client_id, _messages.GuiUpdateMessage(uuid, updates))
    assert number.value == before_number and speed.value == before_speed
    cam = client.camera
    for bad in [dict(position=(float("nan"), 0.0, 1.0)), dict(image_width=0), dict(fov=float("inf")),
                dict(image_height=10**9)]:
        fields = dict(wxyz=tuple(cam.wxyz), position=tuple(cam.position), fov=cam.fov, near=0.01, far=100.0,
                      image_height=600, image_width=800, look_at=tuple(cam.look_at),
                      up_direction=tuple(cam.up_direction))
        _dispatch_camera(app, client, _messages.ViewerCameraMessage(**{**fields, **bad}))
        assert all(math.isfinite(v) for v in (*cam.position, cam.fov)), cam.position
        assert 1 <= cam.image_width <= 16384 and 1 <= cam.image_height <= 16384
    _dispatch(app, client.client_id, _messages.ScenePointerMessage(
        "click", (float("nan"), 0.0, 1.0), (0.0, 0.0, -1.0), ((0.5, 0.5),), None))
    assert _still_serving(app, frames)
    assert len(app.server.get_clients()) == 2
    uploader.get_by_text(re.compile("must be a float")).first.wait_for(timeout=20000)
    assert bystander.get_by_text(re.compile("must be a float")).count() == 0


def test_a_valid_map_upload_still_works_after_all_that(app, tabs, tmp_path: Path) -> None:
    uploader, bystander = tabs
    good = tmp_path / "restaurant_2024.json"
    good.write_text((MAPS / "restaurant_2024.json").read_text())
    _upload(uploader, good)
    assert wait_until(lambda: app.studio.map_name == "restaurant_2024.json")
    bystander.get_by_text("restaurant_2024.json").first.wait_for(timeout=20000)  # the other tab follows
