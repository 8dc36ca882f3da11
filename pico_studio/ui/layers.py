"""The scene: one viser node per drawable, created once, then updated by assignment.

Nodes are named `/<layer>/<prim>` and shared by every tab (broadcast scope); a node is
visible when it has something to draw. Whether a *layer* shows is per tab: each tab gets its
own client-scoped frame `/<layer>` (`LayerToggles`), which shadows the shared parent of that
layer's nodes for that tab alone, and hiding it hides them (viser's visibility follows the
parent chain). Map-frame geometry goes out as float32 (viser's line segments are float32;
point clouds are asked for float32 rather than the default float16, which would be
centimetres off at 20 m).

Only what changed is sent: an assignment of equal geometry is dropped here (before viser
copies and compares it), so a static or paused scene costs next to nothing per frame.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import viser

from pico_studio.ui.colour import line_uniform, line_vertex
from pico_studio.ui.scene_data import LAYERS, PRIM_SPECS, Prim, PrimSpec

_DUMMY_SEG = np.zeros((1, 2, 3), dtype=np.float32)

_DUMMY_PT = np.zeros((1, 3), dtype=np.float32)

# viser's point clouds show about twice as wide as their `point_size` (measured on the
# page's screenshots: a 0.18 m point at 0.022 m/px shows ~17 px wide, not 8)
VISER_POINT_SCALE = 0.5

LAYER_OF = {spec.name: layer.key for layer in LAYERS for spec in layer.prims}

_Z_ORDER = [spec.name for layer in LAYERS for spec in layer.prims]


def _z_of(prim: str) -> float:
    """Height above the floor: the draw order of LAYERS, markers (points) above every line."""
    spec = PRIM_SPECS[prim]
    return 0.002 * _Z_ORDER.index(prim) + (0.05 if spec.kind == "points" else 0.0)


class SceneLayers:
    def __init__(self, server: viser.ViserServer):
        self.server = server
        self.handles: dict[str, Any] = {}
        self.has_data: dict[str, bool] = {}
        self.sizes: dict[str, int] = {}
        self._sent: dict[str, tuple[Any, ...]] = {}  # what each node shows now
        self.metres_per_px = 0.02  # of the view that last zoomed (points are world-sized in viser)
        for layer in LAYERS:
            for spec in layer.prims:
                self.handles[spec.name] = self._make(spec, layer.key)
                self.has_data[spec.name] = False
                self.sizes[spec.name] = 0

    def _make(self, spec: PrimSpec, layer: str) -> Any:
        name = f"/{layer}/{spec.name}"
        pos = (0.0, 0.0, _z_of(spec.name))
        scene = self.server.scene
        if spec.kind == "segments":
            # a node coloured per item is made with per-vertex colours: switching a line node
            # from one colour to per-vertex colours later leaves it white on the page
            colours: Any = (np.repeat(line_vertex(np.array([spec.color], np.uint8))[:, None, :], 2, axis=1)
                            if spec.per_item else line_uniform(spec.color))
            return scene.add_line_segments(
                name, _DUMMY_SEG, colours, thickness=spec.thickness, thickness_units="screen",
                position=pos, visible=False,
            )
        if spec.kind == "label":
            return scene.add_label(name, "", position=pos, visible=False, anchor="bottom-left", font_screen_scale=0.8)
        return scene.add_point_cloud(
            name, _DUMMY_PT, np.array([spec.color] if spec.per_item else spec.color, dtype=np.uint8),
            point_size=spec.point_size * self.metres_per_px * VISER_POINT_SCALE,
            point_shape="circle", precision="float32", point_shading="flat", position=pos, visible=False,
        )

    def set_pixel_size(self, metres_per_px: float) -> None:
        """Keep point markers at their size in screen pixels (viser sizes points in metres):
        called when a tab's view zooms; the tab that zoomed last sets it for all."""
        if not metres_per_px > 0 or abs(metres_per_px / self.metres_per_px - 1.0) < 0.1:
            return
        self.metres_per_px = metres_per_px
        with self.server.atomic():
            for name, h in self.handles.items():
                spec = PRIM_SPECS[name]
                if spec.kind == "points":
                    h.point_size = spec.point_size * metres_per_px * VISER_POINT_SCALE

    def update(self, prims: dict[str, Prim]) -> None:
        """Assign new geometry to the existing nodes (nothing is re-created)."""
        with self.server.atomic():
            for name, prim in prims.items():
                self._assign(name, prim)

    def _assign(self, name: str, prim: Prim) -> None:
        spec = PRIM_SPECS[name]
        h = self.handles[name]
        n = len(prim)
        self.sizes[name] = n
        self.has_data[name] = n > 0
        if n:
            data = np.asarray(prim.data, dtype=np.float32)
            colors = None if prim.colors is None else np.asarray(prim.colors, np.uint8)
            if spec.per_item and colors is None:  # keep the node per-vertex
                colors = np.tile(np.array(spec.color, np.uint8), (n, 1))
            elif not spec.per_item:
                colors = None  # one colour per node, as it was made
            sent = self._sent.get(name, (None, None))
            key = (data.tobytes() + prim.text.encode(), None if colors is None else colors.tobytes())
            # each part only when it changed (equal colour bytes are an equal count too)
            if colors is not None and key[1] != sent[1]:
                self._send_colors(spec, h, colors)
            if key[0] != sent[0]:
                self._send_geometry(spec, h, n, data, prim.text)
            self._sent[name] = key
        h.visible = n > 0

    @staticmethod
    def _send_colors(spec: PrimSpec, h: Any, colors: np.ndarray) -> None:
        # one colour per node stays a (3,) colour; only multi-coloured prims send
        # per-vertex colours (switching a node between the two is not reliable)
        if spec.kind == "segments":
            h.colors = np.ascontiguousarray(np.repeat(line_vertex(colors)[:, None, :], 2, axis=1))
        elif spec.kind == "points":
            h.colors = np.ascontiguousarray(colors)

    @staticmethod
    def _send_geometry(spec: PrimSpec, h: Any, n: int, data: np.ndarray, text: str) -> None:
        if spec.kind == "label":
            h.position = (float(data[0, 0]), float(data[0, 1]), h.position[2])
            h.text = text
        elif spec.kind == "segments":
            pts = np.zeros((n, 2, 3), dtype=np.float32)
            pts[:, :, :2] = data.reshape(n, 2, 2)
            h.points = pts
        else:
            pts = np.zeros((n, 3), dtype=np.float32)
            pts[:, :2] = data
            h.points = pts


class LayerToggles:
    """One tab's layer visibility: a client-scoped frame per layer, parent of that layer's
    shared nodes for this tab only."""

    def __init__(self, client: viser.ClientHandle):
        self.visible = {layer.key: layer.default_on for layer in LAYERS}
        self.frames = {
            layer.key: client.scene.add_frame(f"/{layer.key}", show_axes=False, visible=layer.default_on)
            for layer in LAYERS
        }

    def set(self, key: str, on: bool) -> None:
        self.visible[key] = on
        self.frames[key].visible = on
