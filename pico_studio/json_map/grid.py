"""Where an image's pixels lie in the world: `GridFrame`, a pixel <-> metre affine map.

Pixel coordinates here are *continuous*: (u, v) = (column, row), with (0, 0) the top-left
corner of the top-left pixel, so pixel (c, r) covers [c, c+1] x [r, r+1] and its centre is
(c + 0.5, r + 0.5). A frame is the 2 x 3 matrix A with  [x, y] = A @ [u, v, 1].

Two conventions occur in the PICO world (evidence in `heightmap.py`'s docstring):

- `GridFrame.map_server(shape, resolution, origin)`: ROS map_server — x to the right,
  y up the image, `origin` = world (x, y) of the image's bottom-left corner.
  x = ox + u * res,  y = oy + (H - v) * res.
- `GridFrame.emc_centred(shape, resolution)`: the emc simulator loading a bare image
  (2015-2021): the image centre is the world origin, x points *up* the image and y to
  the *left*.  x = (H/2 - v) * res,  y = (W/2 - u) * res.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

FrameKind = Literal["map_server", "emc_centred"]


@dataclass(frozen=True)
class GridFrame:
    """An image of `shape` (rows, cols) placed in the world by an affine pixel->metre map."""

    shape: tuple[int, int]  # (rows H, cols W)
    resolution: float  # metres per pixel
    matrix: np.ndarray  # (2, 3): [x, y] = matrix @ [u, v, 1]
    kind: FrameKind = "map_server"

    @staticmethod
    def map_server(
        shape: tuple[int, int],
        resolution: float,
        origin: tuple[float, float] = (0.0, 0.0),
        yaw: float = 0.0,
    ) -> GridFrame:
        """`origin` (x, y) and `yaw` as in the map_server YAML: the pose of the image's
        bottom-left corner; the image is rotated by yaw about it."""
        h = shape[0]
        c, s = np.cos(yaw), np.sin(yaw)
        rot = np.array([[c, -s], [s, c]])
        # unrotated: x = u res, y = (H - v) res, relative to the bottom-left corner
        lin = rot @ np.array([[resolution, 0.0], [0.0, -resolution]])
        off = rot @ np.array([0.0, h * resolution]) + np.array(origin, dtype=float)
        m = np.hstack([lin, off[:, None]])
        return GridFrame((int(shape[0]), int(shape[1])), float(resolution), m, "map_server")

    @staticmethod
    def emc_centred(shape: tuple[int, int], resolution: float) -> GridFrame:
        h, w = shape
        m = np.array(
            [[0.0, -resolution, h / 2 * resolution], [-resolution, 0.0, w / 2 * resolution]]
        )
        return GridFrame((int(h), int(w)), float(resolution), m, "emc_centred")

    @staticmethod
    def covering(
        bounds: tuple[float, float, float, float], resolution: float, margin: float
    ) -> GridFrame:
        """A map_server frame whose image covers `bounds` (xmin, ymin, xmax, ymax) plus a margin.

        The origin is snapped to the pixel grid; when the map lies in x, y >= 0 (as the
        challenge maps do) it is (0, 0), which is where the current emc simulator puts the
        image's bottom-left corner whatever the YAML says.
        """
        x0, y0, x1, y1 = bounds
        if x0 >= 0 and y0 >= 0:
            ox, oy = 0.0, 0.0
        else:
            ox = np.floor((x0 - margin) / resolution) * resolution
            oy = np.floor((y0 - margin) / resolution) * resolution
        w = int(np.ceil((x1 + margin - ox) / resolution - 1e-9))
        h = int(np.ceil((y1 + margin - oy) / resolution - 1e-9))
        return GridFrame.map_server((max(h, 1), max(w, 1)), resolution, (float(ox), float(oy)))

    # ----- conversions ---------------------------------------------------------------------
    def to_world(self, uv: np.ndarray) -> np.ndarray:
        """Continuous pixel coordinates (N, 2) as (u, v) -> world (N, 2) metres."""
        uv = np.asarray(uv, dtype=float).reshape(-1, 2)
        return uv @ self.matrix[:, :2].T + self.matrix[:, 2]

    def to_pixel(self, xy: np.ndarray) -> np.ndarray:
        """World (N, 2) metres -> continuous pixel coordinates (N, 2) as (u, v)."""
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        inv = np.linalg.inv(self.matrix[:, :2])
        return (xy - self.matrix[:, 2]) @ inv.T

    def pixel_centre(self, col: float, row: float) -> tuple[float, float]:
        x, y = self.to_world(np.array([[col + 0.5, row + 0.5]]))[0]
        return (float(x), float(y))

    @property
    def origin(self) -> tuple[float, float]:
        """World (x, y) of the image's bottom-left corner (the map_server YAML `origin`)."""
        x, y = self.to_world(np.array([[0.0, float(self.shape[0])]]))[0]
        return (float(x), float(y))

    @property
    def world_bounds(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) of the whole image in the world."""
        h, w = self.shape
        c = self.to_world(np.array([[0, 0], [w, 0], [0, h], [w, h]], dtype=float))
        lo, hi = c.min(axis=0), c.max(axis=0)
        return (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))

    def to_dict(self) -> dict[str, object]:
        return {
            "frame": self.kind,
            "resolution": self.resolution,
            "shape": [self.shape[0], self.shape[1]],
            "origin": [round(v, 9) for v in self.origin],
            "yaw": round(self.yaw, 9),
        }

    @property
    def yaw(self) -> float:
        """Rotation of the image's x axis (columns) in the world, radians."""
        return float(np.arctan2(self.matrix[1, 0], self.matrix[0, 0]))

    @staticmethod
    def from_dict(d: dict[str, object]) -> GridFrame | None:
        """The frame recorded by `to_dict`, or None when `d` does not hold a usable one."""
        try:
            kind = d["frame"]
            res = float(d["resolution"])  # type: ignore[arg-type]
            h, w = (int(v) for v in d["shape"])  # type: ignore[union-attr]
            if kind == "emc_centred":
                return GridFrame.emc_centred((h, w), res)
            ox, oy = (float(v) for v in d["origin"])  # type: ignore[union-attr]
            yaw = float(d.get("yaw", 0.0))  # type: ignore[arg-type]
            return GridFrame.map_server((h, w), res, (ox, oy), yaw)
        except (KeyError, TypeError, ValueError):
            return None
