"""What every panel of the page shares: the `Page` context, one tab's `TabState`, the
snapshot `Shown` a redraw hands to the panels, and the `Panel` base class.

A panel (one per tab or section of the control panel, in `ui/panels/`) builds its widgets
in `__init__` (shared GUI, `server.gui`), its per-tab widgets in `connect(tab)`
(`tab.client.gui`, inside a folder it made), and follows the studio in `refresh(shown)`.
It owns its viser handles; `app.StudioApp` only creates the panels in order and calls them.
"""

from __future__ import annotations

import functools
import logging
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import viser

from pico_studio.errors import UserError
from pico_studio.ui.layers import LayerToggles
from pico_studio.ui.logbook import LogBook
from pico_studio.ui.runtime import Studio
from pico_studio.ui.scene_data import Prim
from pico_studio.ui.timeline import FrameRecord

log = logging.getLogger(__name__)


@dataclass
class TabState:
    """What belongs to one browser tab; rebuilt on every (re)connect. Panels keep their
    per-tab handles in `handles[panel name]` and per-tab values in `settings` (saved in the
    browser's local storage, restored on reload)."""

    client: viser.ClientHandle
    toggles: LayerToggles
    settings: dict[str, Any] = field(default_factory=dict)
    handles: dict[str, Any] = field(default_factory=dict)
    last_follow: tuple[float, float] | None = None  # where its camera was last centred

    @property
    def client_id(self) -> int:
        return self.client.client_id


@dataclass
class Shown:
    """One redraw's snapshot, taken under the studio's lock: what every panel shows."""

    frame: FrameRecord | None
    prims: dict[str, Prim]
    metrics: dict[str, Any]
    length: int  # frames the scrubber covers
    position: int  # where the scrubber is
    robot: tuple[float, float, float] | None
    playing: bool
    replay: bool  # a recording: the behaviour, teleop and door controls do nothing


class Page:
    """The context a panel gets: the server, the studio, the log, and the page's actions."""

    def __init__(self, server: viser.ViserServer, studio: Studio, logbook: LogBook):
        self.server = server
        self.studio = studio
        self.log = logbook
        self.tabs: dict[int, TabState] = {}
        self.redraw: Callable[[], None] = lambda: None  # set by the app
        self.map_changed: Callable[[], None] = lambda: None
        self.save_settings: Callable[[TabState], None] = lambda tab: None
        self.hooks: dict[str, Callable[..., Any]] = {}  # named actions panels offer each other

    def notify(self, client: viser.ClientHandle | None, title: str, body: str, color: str = "red") -> None:
        targets = [client] if client is not None else list(self.server.get_clients().values())
        for c in targets:
            try:
                c.add_notification(title, body, color=color, auto_close_seconds=10.0)  # type: ignore[arg-type]
            except Exception:  # a tab that just went away
                log.debug("notification to a closed tab dropped")

    def guard(self, what: str, fn: Callable[..., None]) -> Callable[..., None]:
        """Wrap a callback: a user error becomes a red notification, a log entry and a log
        line; anything else is logged with its traceback and reported too. The server stays up."""

        @functools.wraps(fn)
        def wrapper(event: Any = None, *args: Any) -> None:
            client = getattr(event, "client", None)
            try:
                fn(event, *args)
            except UserError as e:
                log.warning("%s: %s", what, e)
                self.log.add("error", what, str(e), self.studio)
                self.notify(client, f"{what}: error", str(e))
            except Exception as e:
                log.exception("%s failed", what)
                self.log.add("error", what, f"internal error: {type(e).__name__}: {e}", self.studio)
                self.notify(client, f"{what}: internal error", f"{type(e).__name__}: {e}")

        return wrapper

    def tab_of(self, event: Any) -> TabState | None:
        return self.tabs.get(getattr(event, "client_id", -1) if event is not None else -1)


class Panel:
    """A section of the control panel. Subclasses override what they need."""

    name = "panel"

    def __init__(self, page: Page):
        self.page = page

    def connect(self, tab: TabState) -> None:
        """Build this panel's per-tab widgets (client-scoped)."""

    def restore(self, tab: TabState, settings: dict[str, Any]) -> None:
        """Apply settings saved by this tab before a reload (values written quietly)."""

    def refresh(self, shown: Shown) -> None:
        """Follow the studio after a redraw."""


def empty_segments() -> np.ndarray:
    return np.zeros((1, 2, 3), np.float32)


def finite(x: float) -> bool:
    return not math.isnan(x) and not math.isinf(x)
