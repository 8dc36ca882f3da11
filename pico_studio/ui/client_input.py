"""Checks on what a browser tab sends, before viser acts on it.

viser trusts its client: a GUI update is cast with `type(current)(sent)` inside an asyncio
task (`float("abc")` ends as "Task exception was never retrieved", the tab left wrong), a
camera or pointer message may carry NaN, infinity or a zero-sized view that the page's
camera maths then divide by, and an upload is buffered whole, whatever size it declares.
`guard_server` wraps the server's message dispatch and `guard_connection` each tab's, so

* a GUI value that cannot take its widget's type, or a non-finite number, is refused with
  a notification to that tab (the widget keeps its value);
* a camera message with a non-finite number or an image size outside 1..16384 px, and a
  pointer (click) message with a non-finite ray or screen position, are dropped (the
  previous camera stays);
* an upload that declares more than `user_files.FileLimits.upload_bytes`, or whose parts
  add up to more than it declared, is refused before it is buffered, with a notification;
* anything a handler still raises is logged and notified instead of killing its task.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Coroutine
from typing import Any

import viser
from viser import _messages

from pico_studio.user_files import limits

log = logging.getLogger(__name__)

Notify = Callable[[int, str, str], None]  # (client id, title, body)
MAX_VIEW_PX = 16384


def _finite(values: Any) -> bool:
    """True when every number in a (nested) tuple/list is a finite int or float."""
    if values is None:
        return True
    if isinstance(values, (bool, str)):  # text is not a number to check (a text field's value)
        return True
    if isinstance(values, (int, float)):
        return math.isfinite(values)
    if isinstance(values, (tuple, list)):
        return all(_finite(v) for v in values)
    return False


def camera_problem(m: Any) -> str | None:
    """Why a `ViewerCameraMessage` cannot be used, or None."""
    for name in ("wxyz", "position", "fov", "near", "far", "look_at", "up_direction"):
        if not _finite(getattr(m, name, None)):
            return f"camera {name} is not finite"
    for name in ("image_width", "image_height"):
        v = getattr(m, name, None)
        if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= MAX_VIEW_PX:
            return f"camera {name} {v!r} is outside 1..{MAX_VIEW_PX} px"
    if not 0.0 < m.fov < math.pi:
        return f"camera fov {m.fov!r} is outside (0, pi)"
    return None


def pointer_problem(m: Any) -> str | None:
    """Why a `ScenePointerMessage` cannot be used, or None."""
    for name in ("ray_origin", "ray_direction", "screen_pos"):
        if not _finite(getattr(m, name, None)):
            return f"pointer {name} is not finite"
    return None


def gui_problem(server: viser.ViserServer, m: Any) -> str | None:
    """Why a `GuiUpdateMessage` cannot be applied to its widget, or None."""
    handle = server.gui._gui_input_handle_from_uuid.get(m.uuid)
    if handle is None:
        return None  # a widget that is gone: viser ignores it
    state = handle._impl
    if not isinstance(m.updates, dict):
        return "a GUI update that is not a mapping"
    for prop, value in m.updates.items():
        if not isinstance(prop, str) or not hasattr(state, prop):
            return f"unknown property {str(prop)[:40]!r}"
        if prop != "value":
            continue
        current = state.value
        try:  # the cast viser will do
            if isinstance(current, tuple):
                if not isinstance(value, (list, tuple)) or (current and len(value) != len(current)):
                    return f"{_label(state)}: needs {len(current)} values, got {_short(value)}"
                cast: Any = tuple(type(current[0])(v) for v in value) if current else tuple(value)
            elif isinstance(current, (int, float)) and not isinstance(current, bool):
                if isinstance(value, bool) or not isinstance(value, (int, float, str)):
                    return f"{_label(state)}: must be a number, got {_short(value)}"
                cast = type(current)(value)
            elif isinstance(current, str):
                if not isinstance(value, str):
                    return f"{_label(state)}: must be text, got {_short(value)}"
                cast = value
            elif isinstance(current, bool):
                if not isinstance(value, bool):
                    return f"{_label(state)}: must be true or false, got {_short(value)}"
                cast = value
            else:
                continue
        except (TypeError, ValueError, OverflowError):
            return f"{_label(state)}: must be a {type(current).__name__}, got {_short(value)}"
        text = isinstance(cast, str) or (isinstance(cast, tuple) and all(isinstance(v, str) for v in cast))
        if not text and not _finite(cast):  # text (a dropdown's choice, a text field) has no number to check
            return f"{_label(state)}: must be a finite number, got {_short(value)}"
        options = getattr(getattr(state, "props", None), "options", None)
        if isinstance(options, (tuple, list)) and options and isinstance(cast, str) and cast not in options:
            return f"{_label(state)}: {_short(value)} is not one of the choices"
    return None


def _label(state: Any) -> str:
    return str(getattr(getattr(state, "props", None), "label", None) or "value")


def _short(value: Any) -> str:
    from pico_studio.errors import short

    return short(value)


class _Uploads:
    """Declared and received bytes of the uploads in flight, to refuse oversized ones."""

    def __init__(self) -> None:
        self.declared: dict[str, int] = {}
        self.received: dict[str, int] = {}

    def start_problem(self, m: Any) -> str | None:
        cap = limits().upload_bytes
        size = m.size_bytes
        if isinstance(size, bool) or not isinstance(size, int) or size < 0:
            return f"upload {m.filename!r} declares no valid size"
        if size > cap:
            return f"{str(m.filename)[:80]} is {size / 2**20:.1f} MB, over the {cap / 2**20:.0f} MB upload limit"
        self.declared[m.transfer_uuid] = size
        self.received[m.transfer_uuid] = 0
        return None

    def part_problem(self, m: Any) -> str | None:
        if m.transfer_uuid not in self.declared:
            return None  # refused at its start, or a download: viser ignores it
        self.received[m.transfer_uuid] += len(m.content) if isinstance(m.content, (bytes, bytearray)) else 0
        if self.received[m.transfer_uuid] > self.declared[m.transfer_uuid]:
            self.declared.pop(m.transfer_uuid)
            self.received.pop(m.transfer_uuid)
            return "upload refused: its parts are larger than the size it declared"
        return None


def _end_transfer(server: viser.ViserServer, client_id: int, m: Any) -> None:
    """Tell the tab a refused upload is over (an ack for all of it), so that its upload
    button comes back instead of waiting for ever; the parts it still sends are ignored."""
    client = server.get_clients().get(client_id)
    size = m.size_bytes if isinstance(m.size_bytes, int) and m.size_bytes >= 0 else 0
    if client is not None:
        client._websock_connection.queue_message(
            _messages.FileTransferPartAck(
                source_component_uuid=m.source_component_uuid, transfer_uuid=m.transfer_uuid,
                transferred_bytes=size, total_bytes=size,
            )
        )


Dispatch = Callable[[int, Any], Coroutine[Any, Any, None]]


def _wrap(
    original: Dispatch, check: Callable[[int, Any], str | None], notify: Notify, quiet: set[type]
) -> Dispatch:
    async def dispatch(client_id: int, message: Any) -> None:
        try:
            problem = check(client_id, message)
        except Exception:  # a check that fails refuses the message
            log.exception("checking a %s failed", type(message).__name__)
            problem = "a message the page cannot check"
        if problem is not None:
            log.warning("tab %s: %s refused: %s", client_id, type(message).__name__, problem)
            if type(message) not in quiet:
                notify(client_id, "refused", problem)
            return
        try:
            await original(client_id, message)
        except Exception as e:  # viser's own handlers: never a dead task, always a message
            log.exception("handling a %s from tab %s failed", type(message).__name__, client_id)
            notify(client_id, "internal error", f"{type(e).__name__}: {e}")

    return dispatch


def guard_server(server: viser.ViserServer, notify: Notify) -> None:
    """Check GUI updates, pointer events and uploads before viser's handlers see them."""
    uploads = _Uploads()

    def check(client_id: int, m: Any) -> str | None:
        if isinstance(m, _messages.GuiUpdateMessage):
            return gui_problem(server, m)
        if isinstance(m, _messages.ScenePointerMessage):
            return pointer_problem(m)
        if isinstance(m, _messages.FileTransferStartUpload):
            problem = uploads.start_problem(m)
            if problem is not None:
                _end_transfer(server, client_id, m)
            return problem
        if isinstance(m, _messages.FileTransferPart):
            return uploads.part_problem(m)
        return None

    ws = server._websock_server
    ws._handle_incoming_message = _wrap(  # type: ignore[method-assign]
        ws._handle_incoming_message, check, notify, quiet={_messages.ScenePointerMessage}
    )


def guard_connection(client: viser.ClientHandle, notify: Notify) -> None:
    """Check a tab's camera messages (handled on its own connection) before viser's."""

    def check(client_id: int, m: Any) -> str | None:
        return camera_problem(m) if isinstance(m, _messages.ViewerCameraMessage) else None

    conn = client._websock_connection
    conn._handle_incoming_message = _wrap(  # type: ignore[method-assign]
        conn._handle_incoming_message, check, notify, quiet={_messages.ViewerCameraMessage}
    )
