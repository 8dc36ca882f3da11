"""Where a tab's camera looks: straight down at the map, beside the control panel.

Pure maths on a viser `ClientHandle`'s camera; the page calls `fit` on connect and map
changes, and `look_at` to follow the robot.
"""

from __future__ import annotations

import math

import viser

CAMERA_MARGIN = 1.15  # the map fills ~85% of the view
PANEL_PX = 420  # the control panel (control_width="large") covers this much of the view's right side


def view_size(client: viser.ClientHandle) -> tuple[int, int]:
    """The tab's view in pixels; 1200 x 800 until it has said, or when what it said is not a
    size (its first camera message reaches viser before `ui.client_input` checks them)."""
    w, h = client.camera.image_width, client.camera.image_height
    ok = all(isinstance(v, int) and not isinstance(v, bool) and 1 <= v <= 16384 for v in (w, h))
    return (w, h) if ok else (1200, 800)


def look_at(client: viser.ClientHandle, fov: float, cx: float, cy: float, span_x: float, span_y: float) -> None:
    """Look straight down at (cx, cy) so that span_x x span_y fits beside the panel."""
    w, h = view_size(client)
    panel = PANEL_PX if w > 2 * PANEL_PX else 0
    view_h = max(span_y, span_x * h / (w - panel)) * CAMERA_MARGIN  # world metres, vertically
    cx += 0.5 * panel * view_h / h  # centre the map in the part the panel leaves free
    height = view_h / (2.0 * math.tan(fov / 2.0))
    with client.atomic():
        client.camera.fov = fov
        client.camera.up_direction = (0.0, 1.0, 0.0)
        client.camera.position = (cx, cy, height)
        client.camera.look_at = (cx, cy, 0.0)
        client.camera.far = height * 4.0


def fit(client: viser.ClientHandle, fov: float, bounds: tuple[float, float, float, float] | None) -> None:
    """The whole map (or a 10 m square round the origin when there is none) in view."""
    x0, y0, x1, y1 = bounds if bounds is not None else (-5.0, -5.0, 5.0, 5.0)
    look_at(client, fov, (x0 + x1) / 2, (y0 + y1) / 2, max(x1 - x0, 1.0), max(y1 - y0, 1.0))


def metres_per_pixel(client: viser.ClientHandle) -> float:
    """How many metres one screen pixel covers at the ground (looking straight down)."""
    height = float(client.camera.position[2])
    if not math.isfinite(height):
        height = 10.0
    _, h = view_size(client)
    return 2.0 * height * math.tan(client.camera.fov / 2.0) / h
