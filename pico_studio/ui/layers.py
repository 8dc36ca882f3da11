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
            return scene.add_line_segments(
                name, _DUMMY_SEG, line_uniform(spec.color), thickness=spec.thickness, thickness_units="screen",
                position=pos, visible=False,
            )
        if spec.kind == "label":
            return scene.add_label(name, "", position=pos, visible=False, anchor="bottom-left", font_screen_scale=0.8)
        return scene.add_point_cloud(
            name, _DUMMY_PT, np.array(spec.color, dtype=np.uint8), point_size=spec.point_size,
            point_shape="circle", precision="float32", point_shading="flat", position=pos, visible=False,
        )

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
