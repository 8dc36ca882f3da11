"""The scene: one viser node per drawable, created once, then updated by assignment.

Every layer (see `scene_data.LAYERS`) has a visibility toggle; a node is shown when its layer
is on and it has something to draw. Map-frame geometry goes out as float32 (viser's line
segments are float32; point clouds are asked for float32 rather than the default float16,
which would be centimetres off at 20 m).
"""

from __future__ import annotations

import numpy as np
import viser

from pico_studio.ui.colour import line_uniform, line_vertex
from pico_studio.ui.scene_data import LAYERS, PRIM_SPECS, Prim, PrimSpec

_DUMMY_SEG = np.zeros((1, 2, 3), dtype=np.float32)

_DUMMY_PT = np.zeros((1, 3), dtype=np.float32)


def _z_of(prim: str) -> float:
    order = [p for layer in LAYERS for p in (s.name for s in layer.prims)]
    return 0.001 * order.index(prim)


class SceneLayers:
    def __init__(self, server: viser.ViserServer):
        self.server = server
        self.visible = {layer.key: layer.default_on for layer in LAYERS}
        self.handles: dict[str, viser.LineSegmentsHandle | viser.PointCloudHandle] = {}
        self.has_data: dict[str, bool] = {}
        self.sizes: dict[str, int] = {}
        for layer in LAYERS:
            for spec in layer.prims:
                self.handles[spec.name] = self._make(spec, layer.key)
                self.has_data[spec.name] = False
                self.sizes[spec.name] = 0

    def _make(self, spec: PrimSpec, layer: str) -> viser.LineSegmentsHandle | viser.PointCloudHandle:
        name = f"/{layer}/{spec.name}"
        pos = (0.0, 0.0, _z_of(spec.name))
        if spec.kind == "segments":
            return self.server.scene.add_line_segments(
                name, _DUMMY_SEG, line_uniform(spec.color), thickness=spec.thickness, position=pos, visible=False
            )
        return self.server.scene.add_point_cloud(
            name, _DUMMY_PT, np.array(spec.color, dtype=np.uint8), point_size=spec.point_size,
            point_shape="circle", precision="float32", point_shading="flat", position=pos, visible=False,
        )

    def layer_of(self, prim: str) -> str:
        for layer in LAYERS:
            if any(s.name == prim for s in layer.prims):
                return layer.key
        raise KeyError(prim)

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
            if spec.kind == "segments":
                pts = np.zeros((n, 2, 3), dtype=np.float32)
                pts[:, :, :2] = np.asarray(prim.data, dtype=np.float32).reshape(n, 2, 2)
                # one colour per node stays a (3,) colour; only multi-coloured prims send
                # per-vertex colours (switching a node between the two is not reliable)
                if prim.colors is not None:
                    h.colors = np.ascontiguousarray(np.repeat(line_vertex(prim.colors)[:, None, :], 2, axis=1))
                h.points = pts  # type: ignore[union-attr]
            else:
                pts = np.zeros((n, 3), dtype=np.float32)
                pts[:, :2] = np.asarray(prim.data, dtype=np.float32)
                if prim.colors is not None:
                    h.colors = np.ascontiguousarray(np.asarray(prim.colors, np.uint8))
                h.points = pts  # type: ignore[union-attr]
        h.visible = self.visible[self.layer_of(name)] and n > 0

    def set_layer_visible(self, key: str, on: bool) -> None:
        self.visible[key] = on
        with self.server.atomic():
            for layer in LAYERS:
                if layer.key == key:
                    for spec in layer.prims:
                        self.handles[spec.name].visible = on and self.has_data[spec.name]
