"""An image's size read from its header, before anything is decoded, so a small file that
claims a huge image (a 439 kB PNG of 20000 x 20000 px: 400 Mpx, gigabytes once decoded)
is refused in microseconds instead of exhausting memory.

PNG: the IHDR chunk that must come first (width, height: big-endian uint32 at bytes 16..24).
PGM / PPM / PBM (netpbm `P1`..`P6`): magic, then width and height as decimal text,
separated by whitespace and `#` comments. Anything else is left to the decoder (which
refuses it as "not a PNG/PGM image"). The pixel cap is `user_files.FileLimits.image_pixels`.
"""

from __future__ import annotations

import math
import re
import struct
from pathlib import Path

from pico_studio.errors import MapError
from pico_studio.user_files import limits, read_bytes

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
_NETPBM = re.compile(rb"P([1-6])(?:\s|#[^\n]*\n)+(\d{1,12})(?:\s|#[^\n]*\n)+(\d{1,12})")


def image_size(head: bytes) -> tuple[int, int] | None:
    """(width, height) claimed by a PNG or netpbm header, None for another format.
    Raises ValueError for a header of a known format that is damaged."""
    if head.startswith(PNG_MAGIC):
        if len(head) < 24 or head[12:16] != b"IHDR":
            raise ValueError("PNG without its IHDR header chunk (truncated or damaged)")
        return struct.unpack(">II", head[16:24])
    if len(head) >= 2 and head[:1] == b"P" and head[1:2] in b"123456":
        m = _NETPBM.match(head)
        if m is None:
            raise ValueError("PGM header without a width and height (truncated or damaged)")
        return int(m.group(2)), int(m.group(3))
    return None


def check_image_size(width: int, height: int, *, what: str, file: str | Path | None) -> None:
    """MapError unless 1 <= width, height and width * height <= the pixel cap."""
    cap = limits().image_pixels
    if width < 1 or height < 1:
        raise MapError(f"{what} is {width} x {height} px: it has no pixels", file=file)
    if width * height > cap:
        raise MapError(
            f"{what} is {width} x {height} px = {width * height / 1e6:.0f} Mpx, over the "
            f"{cap / 1e6:.0f} Mpx limit (set PICO_STUDIO_MAX_IMAGE_PIXELS to raise it)",
            file=file,
        )


def check_raster_size(
    width_m: float, height_m: float, resolution: float, *, file: str | Path | None
) -> None:
    """MapError unless an image of `width_m` x `height_m` metres at `resolution` m/px is
    within the pixel cap; checked before any allocation (a 70 m map at 1e-6 m/px would be
    42 TiB)."""
    if isinstance(resolution, bool) or not (math.isfinite(resolution) and resolution > 0):
        raise MapError(f"must be a positive number of m/px, got {resolution!r}", file=file, field="resolution")
    w, h = width_m / resolution, height_m / resolution
    if not (math.isfinite(w) and math.isfinite(h)):
        raise MapError(f"{width_m:g} x {height_m:g} m at {resolution:g} m/px is not a usable image size", file=file)
    check_image_size(
        max(1, math.ceil(w)), max(1, math.ceil(h)), what=f"the map drawn at {resolution:g} m/px", file=file
    )


def read_image_bytes(path: Path, *, file: Path) -> bytes:
    """The bytes of an image file (a regular file within the map size cap) whose header
    claims a size within the pixel cap; MapError naming `file` (the YAML that names the
    image, or the image itself) otherwise."""
    try:
        data = read_bytes(path, MapError, "map")
    except MapError as e:
        raise MapError(f"cannot read image {path}: {e.message}", file=file) from None
    try:
        size = image_size(data[:4096])
    except ValueError as e:
        raise MapError(f"cannot read image {path}: {e}", file=file) from None
    if size is not None:
        what = "the image" if Path(path) == Path(file) else f"image {path}"
        check_image_size(size[0], size[1], what=what, file=file)
    return data
