"""The one way the page tells a user's edit from the server's own write.

viser calls a GUI handle's update callbacks for *every* change of its value, also when the
server assigns it (with `event.client is None`). The page writes values all the time (the
scrubber follows the frame, a rejected edit is put back, saved settings are restored), so
every input callback is registered through `on_user`: it runs for edits made in a browser
tab only, and a server-side `handle.value = x` is always quiet.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import viser

GuiEvent = viser.GuiEvent


def on_user(handle: Any, fn: Callable[[viser.GuiEvent], None]) -> None:
    """Call `fn(event)` when a user (not the server) changed `handle`'s value."""

    def callback(event: viser.GuiEvent) -> None:
        if event.client is None:  # the server wrote it: nothing to do
            return
        fn(event)

    handle.on_update(callback)
