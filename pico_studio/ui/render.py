"""The page's layers drawn top-down with OpenCV, without viser: `pico-studio render`.

    renderer = TopDown(bounds, width=900)
    image = renderer.draw(map_prims(m) | frame_prims(studio, frame))   # (H, W, 3) RGB

Same prims (`ui.scene_data`), same colours (`ui.style`), same draw order (`LAYERS`, bottom
up), line widths and marker sizes (screen pixels) as the page; points are discs (at
least 1 px). `render_run` steps a `Studio` through a time window and writes one image per
perceived frame to an MP4 (OpenCV's FFMPEG writer), a GIF (Pillow) or, for .png, the last one.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from pathlib import Path

import cv2
import numpy as np

from pico_studio.errors import UserError
from pico_studio.ui.clock import is_replay, start_time
from pico_studio.ui.replay import ReplayDriver
from pico_studio.ui.runtime import Studio
from pico_studio.ui.scene_data import LAYERS, PRIM_SPECS, Prim, frame_prims, map_prims
from pico_studio.ui.timeline import FrameRecord

FORMATS = (".mp4", ".gif", ".png")
MARGIN = 0.05  # of the view's size, each side


class TopDown:
    """Map-frame prims onto an image whose view covers `bounds` (x0, y0, x1, y1)."""

    def __init__(self, bounds: tuple[float, float, float, float], width: int = 900):
        x0, y0, x1, y1 = bounds
        span_x, span_y = max(x1 - x0, 1.0), max(y1 - y0, 1.0)
        pad = MARGIN * max(span_x, span_y)
        self.x0, self.y1 = x0 - pad, y1 + pad
        self.scale = (width - 1) / (span_x + 2 * pad)  # px per metre
        self.width = int(width) // 2 * 2  # even sizes: what H.264 encoders want
        self.height = int(math.ceil((span_y + 2 * pad) * self.scale)) // 2 * 2

    def to_px(self, xy: np.ndarray) -> np.ndarray:
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        return np.column_stack([(xy[:, 0] - self.x0) * self.scale, (self.y1 - xy[:, 1]) * self.scale])

    def draw(self, prims: dict[str, Prim], shown: set[str] | None = None, dark: bool = False) -> np.ndarray:
        """The prims in draw order; `shown` = the layer keys to draw (default: those on by default)."""
        img = np.full((self.height, self.width, 3), 30 if dark else 255, np.uint8)
        for layer in LAYERS:
            if (layer.key not in shown) if shown is not None else not layer.default_on:
                continue
            for spec in layer.prims:
                prim = prims.get(spec.name)
                if prim is not None and len(prim):
                    self._draw(img, spec.name, prim)
        return img

    def _draw(self, img: np.ndarray, name: str, prim: Prim) -> None:
        spec = PRIM_SPECS[name]
        colours = prim.colors if prim.colors is not None else np.tile(np.array(spec.color, np.uint8), (len(prim), 1))
        if spec.kind == "label":
            (x, y), = self.to_px(prim.data[:1]).astype(int)
            cv2.putText(img, prim.text, (x, y), cv2.FONT_HERSHEY_SIMPLEX, 0.45, tuple(int(c) for c in spec.color), 1, cv2.LINE_AA)
            return
        if spec.kind == "segments":
            a = self.to_px(prim.data[:, :2])
            b = self.to_px(prim.data[:, 2:4])
            width = max(1, int(round(spec.thickness)))
            for p, q, c in zip(a, b, colours, strict=True):
                cv2.line(img, _pt(p), _pt(q), _rgb(c), width, cv2.LINE_AA)
            return
        radius = max(1, int(round(spec.point_size / 2)))
        for p, c in zip(self.to_px(prim.data), colours, strict=True):
            cv2.circle(img, _pt(p), radius, _rgb(c), -1, cv2.LINE_AA)


def _pt(p: np.ndarray) -> tuple[int, int]:
    return (int(round(p[0])), int(round(p[1])))


def _rgb(c: np.ndarray) -> tuple[int, int, int]:
    return (int(c[0]), int(c[1]), int(c[2]))  # images are RGB here; BGR only when written


def frames_in(studio: Studio, t_from: float, t_to: float | None, dt: float) -> Iterator[FrameRecord]:
    """Step the studio and yield each perceived frame whose time, relative to the start, lies
    in [t_from, t_to]. A replay delivers every scan (`ReplayDriver`), from its first: the
    world model of the first frame shown is built up to it."""
    source = studio.source
    t0 = start_time(source)
    driver = ReplayDriver(studio) if is_replay(source) else None
    while source.ok():
        frame = driver.step() if driver is not None else studio.tick(dt)
        if frame is None:
            continue
        t = frame.time - t0
        if t_to is not None and t > t_to + 1e-9:
            break
        if t >= t_from - 1e-9:
            yield frame


def render_bounds(studio: Studio) -> tuple[float, float, float, float] | None:
    m = studio.global_map
    return tuple(m.bounds) if m is not None else None  # type: ignore[return-value]


def render_run(
    studio: Studio,
    out: Path,
    *,
    t_from: float = 0.0,
    t_to: float | None = None,
    width: int = 900,
    fps: float | None = None,
    progress: Callable[[float], None] | None = None,
) -> int:
    """Draw each perceived frame in the window into `out`; returns the number of frames written."""
    suffix = out.suffix.lower()
    if suffix not in FORMATS:
        raise UserError(f"write .mp4, .gif or .png, not {suffix or 'no suffix'}", field="--out")
    dt = 1.0 / studio.cfg.ui.rate_hz
    fps = fps or studio.cfg.ui.rate_hz
    bounds = render_bounds(studio)
    static = map_prims(studio.global_map)
    images: list[np.ndarray] = []
    renderer: TopDown | None = TopDown(bounds, width) if bounds is not None else None
    writer: cv2.VideoWriter | None = None
    count = 0
    last: np.ndarray | None = None
    t0 = start_time(studio.source)
    for frame in frames_in(studio, t_from, t_to, dt):
        prims = static | frame_prims(studio, frame)
        if renderer is None:  # no map: the first scan's surroundings, 12 m square
            x, y, _ = studio.robot_pose_in_map(frame)
            renderer = TopDown((x - 6.0, y - 6.0, x + 6.0, y + 6.0), width)
        img = renderer.draw(prims)
        _stamp(img, f"t = {frame.time - t0:6.2f} s")
        count += 1
        last = img
        if suffix == ".mp4":
            if writer is None:
                out.parent.mkdir(parents=True, exist_ok=True)
                writer = cv2.VideoWriter(str(out), cv2.VideoWriter.fourcc(*"mp4v"), fps, (img.shape[1], img.shape[0]))
                if not writer.isOpened():
                    raise UserError("OpenCV cannot write MP4 here", file=str(out))
            writer.write(cv2.cvtColor(img, cv2.COLOR_RGB2BGR))
        elif suffix == ".gif":
            images.append(img)
        if progress is not None:
            progress(frame.time - t0 - t_from)
    if writer is not None:
        writer.release()
    if count == 0 or last is None:
        raise UserError("no frame in that time window", field="--from/--to")
    out.parent.mkdir(parents=True, exist_ok=True)
    if suffix == ".png":
        cv2.imwrite(str(out), cv2.cvtColor(last, cv2.COLOR_RGB2BGR))
    elif suffix == ".gif":
        _write_gif(out, images, fps)
    return count


def _write_gif(out: Path, images: list[np.ndarray], fps: float) -> None:
    from PIL import Image  # Pillow: a declared dependency, only GIFs need it

    frames = [Image.fromarray(im).convert("P", palette=Image.Palette.ADAPTIVE, colors=64) for im in images]
    frames[0].save(out, save_all=True, append_images=frames[1:], duration=int(round(1000 / fps)), loop=0)


def _stamp(img: np.ndarray, text: str) -> None:
    cv2.putText(img, text, (8, 20), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (60, 60, 60), 1, cv2.LINE_AA)


__all__ = ["TopDown", "frames_in", "render_run"]
