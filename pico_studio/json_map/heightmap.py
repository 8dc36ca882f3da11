"""Heightmap images (what the emc simulator loads) -> the vector `GlobalMap`.

An image is grey (PNG/PGM; grey+alpha and RGB are converted): 255 = free, dark = wall,
grey in between = a door candidate; a candidate region is a sliding door only when it looks
like one (see `classify`). A map_server YAML beside it (`image`, `resolution`, `origin`,
`negate`, `occupied_thresh`, `free_thresh`) sets its size and place; without one the pixel
size is `cfg.map.heightmap.resolution` (0.025 m).

Reading:
- alpha: a (nearly) transparent pixel (alpha < 128) reads as free — it is "nothing drawn",
  as map_server treats it (unknown); the real files are all opaque, a note lists any.
- grey+alpha / RGB(A) are converted to grey as OpenCV's IMREAD_GRAYSCALE does (what the
  simulator reads); 16-bit PGMs are scaled to 8 bit.
- occupied / free: with a YAML, map_server's rule on p = (255 - v) / 255 (after `negate`):
  p > occupied_thresh occupied, p < free_thresh free (defaults 0.65 / 0.196, as
  map_server's); without one the emc simulator's convention: v <= door_grey_low occupied,
  v >= door_grey_high free. In between (map_server's "unknown") are door candidates.
- doors: a candidate region is a door when, cut off the walls' anti-aliased edges, it has a
  door's size and shape and bridges two walls (`door_looks_like_a_door`); every other
  candidate pixel is an anti-aliased wall edge: a wall when darker than `edge_wall_grey`
  (half covered), else free. So a PGM with ~100 grey levels on its wall edges gets its
  walls, not door rectangles lying along them. Door pixels are never walls. The real maps
  (hard-edged) read exactly as with the plain grey band.

Where the image lies in the world (see `grid.GridFrame`):
- **with a map_server YAML**: ROS map_server's convention — x right, y up the image,
  `origin` = world pose of the bottom-left corner. Checked on the real files:
  `restaurant_2024.png` + `.yaml` (origin 0, 0) overlays `restaurant_2024.json` (its walls
  lie on the image's wall edges, its door on the grey region; tests/test_heightmap.py).
  The current emc simulator (master since 2023, map via map_server, `pixel2world` in
  src/heightmap.cpp) also puts the image's bottom-left corner at (0, 0) (within a pixel)
  with x right, y up — but ignores a non-zero YAML origin;
  `convert` therefore writes origin (0, 0) whenever the map lies in x, y >= 0.
- **without a YAML**: the emc simulator that loaded bare images (2015 .. 2021, e.g. branch
  `finalchallenge2021`, `createHeightMapShape`): `origin_x = -(cols * res / 2)`,
  `origin_y = -(rows * res / 2)`, a vertex at pixel (px, py) goes to
  `wx = (rows - py - 1) * res + origin_y`, `wy = -(px * res + origin_x)`: the **image
  centre is the world origin, world x points up the image and y to the left**. Checked:
  the moving objects of `hospital_2021_sim.json` sweep (box footprint, 50 steps) through
  free space of `hospital_2021.png` in this frame (5 of 4500 samples touch a wall edge),
  and through walls or off the image in the alternatives (centre with x right: 827 of
  4500 in walls; a corner origin: entirely off the image). The simulator's own pixel
  offsets moved by a pixel between versions (2023: "fix origin relative to rviz map");
  here the centre is exact: pixel (c, r)'s centre is ((H/2 - r - .5) res, (W/2 - c - .5) res).

Vectorising (all in pixels, then through the frame to metres):
1. classify pixels into occupied and door masks (`classify`);
2. occupied 8-connected blobs smaller than `min_speck_area` px are dropped and reported
   (a warning with their pixel and world position) — e.g. the stray pixel of escape_room;
3. the remaining blobs' outlines (outer boundaries and holes, `cv2.findContours` on the
   mask upsampled x2 so a one-pixel wall still has an inside) are simplified with
   `cv2.approxPolyDP(tolerance = simplify_tolerance px)` into closed polygons; every
   polygon edge is a wall. The map records `"heightmap": {..., "walls": "outlines"}` so a
   rasteriser fills these loops (even-odd) instead of drawing thin lines;
4. each door region becomes the minimum-area rectangle around its pixels (a door polygon);
   its grey value is kept in `"heightmap": {"door_grey": [...]}` (the emc simulator slides a
   door with grey < 128 the opposite way).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from pico_studio.config.map_params import HeightmapParams
from pico_studio.errors import MapError
from pico_studio.json_map.grid import GridFrame
from pico_studio.json_map.image_header import read_image_bytes
from pico_studio.json_map.model import MAX_COORDINATE_M, GlobalMap
from pico_studio.user_files import parse_yaml, read_text

IMAGE_SUFFIXES = (".png", ".pgm")
YAML_SUFFIXES = (".yaml", ".yml")
MAX_LISTED_SPECKS = 20  # a noisy scan can have thousands: list these, count the rest
UPSAMPLE = 2  # outline tracing on a x2 mask: a one-pixel-wide wall keeps a non-zero width


@dataclass
class HeightmapImage:
    """A heightmap read from disk: grey pixels, where they lie, and how to classify them."""

    grey: np.ndarray  # (H, W) uint8, negate already applied, transparent pixels = 255
    frame: GridFrame
    path: Path  # the image file
    yaml_path: Path | None = None
    occupied_thresh: float | None = None  # from the YAML; None: the emc convention (door_grey_low/high)
    free_thresh: float | None = None  # from the YAML
    notes: list[str] = field(default_factory=list)


# ----- reading ----------------------------------------------------------------------------
def read_heightmap(
    path: str | Path, params: HeightmapParams | None = None, resolution: float | None = None
) -> HeightmapImage:
    """Read an image (.png/.pgm) or a map_server YAML (.yaml) and place it in the world.

    An image with a same-stem YAML beside it whose `image` names it is read through that
    YAML. `resolution` overrides the default pixel size of an image without a YAML.
    """
    params = params or HeightmapParams()
    p = Path(path)
    if p.suffix.lower() in YAML_SUFFIXES:
        return _read_via_yaml(p)
    for suffix in YAML_SUFFIXES:
        sibling = p.with_suffix(suffix)
        if sibling.is_file() and _yaml_names_image(sibling, p):
            return _read_via_yaml(sibling)
    grey, notes = _read_grey(p, file=p)
    res = resolution if resolution is not None else params.resolution
    if not (math.isfinite(res) and res > 0):
        raise MapError(f"resolution must be a positive number of m/px, got {res!r}", file=p)
    return HeightmapImage(grey, GridFrame.emc_centred(grey.shape, res), p, notes=notes)


def _yaml_names_image(yaml_path: Path, image: Path) -> bool:
    try:
        data = parse_yaml(read_text(yaml_path, MapError, "a map_server YAML"), MapError, yaml_path)
    except MapError:
        return False
    if not isinstance(data, dict) or not isinstance(data.get("image"), str):
        return False
    return (yaml_path.parent / data["image"]).resolve() == image.resolve()


def read_map_server_yaml(path: Path) -> dict[str, Any]:
    """The validated fields of a map_server YAML: image (Path), resolution, origin, negate,
    occupied_thresh, free_thresh. Errors name the field."""
    data = parse_yaml(read_text(path, MapError, "a map_server YAML"), MapError, path)
    if not isinstance(data, dict):
        raise MapError("must be a mapping with image, resolution, origin, ...", file=path)

    def number(key: str, default: float | None, lo: float, hi: float, lo_open: bool = False) -> float:
        if key not in data:
            if default is None:
                raise MapError("missing key", file=path, field=key)
            return default
        v = data[key]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise MapError(f"must be a finite number, got {v!r}", file=path, field=key)
        if v < lo or v > hi or (lo_open and v == lo):
            bracket = "(" if lo_open else "["
            raise MapError(f"{v:g} is out of range {bracket}{lo:g}, {hi:g}]", file=path, field=key)
        return float(v)

    image = data.get("image")
    if image is None:
        raise MapError("missing key", file=path, field="image")
    if not isinstance(image, str) or not image:
        raise MapError(f"must be a file name, got {image!r}", file=path, field="image")
    image_path = path.parent / image
    if not image_path.is_file():
        raise MapError(f"image file {image_path} does not exist", file=path, field="image")
    resolution = number("resolution", None, 0.0, 100.0, lo_open=True)
    origin = data.get("origin", [0.0, 0.0, 0.0])
    if (
        not isinstance(origin, list)
        or len(origin) not in (2, 3)
        or any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) for v in origin)
    ):
        raise MapError(f"must be [x, y, yaw] (finite numbers), got {origin!r}", file=path, field="origin")
    if any(abs(v) > MAX_COORDINATE_M for v in origin[:2]):  # as a JSON map's coordinates
        raise MapError(f"x, y must lie within {MAX_COORDINATE_M:g} m of zero (a typo?), got {origin[:2]!r}",
                       file=path, field="origin")
    negate = data.get("negate", 0)
    if negate not in (0, 1) or (isinstance(negate, float)):
        raise MapError(f"must be 0 or 1, got {negate!r}", file=path, field="negate")
    occupied = number("occupied_thresh", 0.65, 0.0, 1.0)
    free = number("free_thresh", 0.196, 0.0, 1.0)
    if free >= occupied:
        raise MapError(
            f"{free:g} must be below occupied_thresh ({occupied:g})", file=path, field="free_thresh"
        )
    return {
        "image": image_path,
        "resolution": resolution,
        "origin": [float(v) for v in origin] + ([0.0] if len(origin) == 2 else []),
        "negate": bool(negate),
        "occupied_thresh": occupied,
        "free_thresh": free,
    }


def _read_via_yaml(yaml_path: Path) -> HeightmapImage:
    meta = read_map_server_yaml(yaml_path)
    grey, notes = _read_grey(meta["image"], file=yaml_path)
    if meta["negate"]:
        grey = 255 - grey
    ox, oy, yaw = meta["origin"]
    frame = GridFrame.map_server(grey.shape, meta["resolution"], (ox, oy), yaw=yaw)
    return HeightmapImage(grey, frame, meta["image"], yaml_path, meta["occupied_thresh"], meta["free_thresh"], notes)


def _read_grey(path: Path, *, file: Path) -> tuple[np.ndarray, list[str]]:
    """8-bit grey pixels of an image file, transparent pixels as free (255)."""
    raw = np.frombuffer(read_image_bytes(path, file=file), dtype=np.uint8)  # size checked from the header
    img = cv2.imdecode(raw, cv2.IMREAD_UNCHANGED) if raw.size else None
    if img is None:
        raise MapError(f"cannot read image {path}: not a PNG/PGM image, or corrupt", file=file)
    notes: list[str] = []
    if img.dtype == np.uint16:
        img = (img >> 8).astype(np.uint8)
    elif img.dtype != np.uint8:
        raise MapError(f"unsupported pixel type {img.dtype} in {path}", file=file)
    if img.ndim == 2:
        grey = img
    elif img.shape[2] == 2:  # grey + alpha (OpenCV rarely yields this, but PGM-like decoders may)
        grey = np.where(img[..., 1] < 128, 255, img[..., 0]).astype(np.uint8)
    else:
        grey = cv2.cvtColor(img[..., :3], cv2.COLOR_BGR2GRAY)
        if img.shape[2] == 4:
            transparent = img[..., 3] < 128
            if transparent.any():
                notes.append(f"{int(transparent.sum())} transparent pixels read as free")
                grey = np.where(transparent, 255, grey).astype(np.uint8)
    if grey.size == 0:
        raise MapError(f"image {path} has no pixels", file=file)
    return np.ascontiguousarray(grey), notes


# ----- classifying and vectorising ----------------------------------------------------------
def classify(img: HeightmapImage, params: HeightmapParams) -> tuple[np.ndarray, np.ndarray]:
    """(occupied, door) boolean masks of the image's pixels (see the module doc, "Reading").

    1. bands: with a YAML, map_server's: p = (255 - v) / 255 > occupied_thresh occupied,
       p < free_thresh free; without one the emc convention: v <= door_grey_low occupied,
       v >= door_grey_high free. What lies between is a door candidate (map_server's
       "unknown");
    2. door cores: candidates not touching (8-neighbour) an occupied pixel — an
       anti-aliased wall edge is a band of such touching pixels, so this cuts it off the
       doors it would otherwise join; each 4-connected core grows back by one pixel into the
       candidates (restoring a door's ends where it meets the walls);
    3. a grown core is a door when it looks like one (`door_looks_like_a_door`);
    4. every other candidate is an (anti-aliased) wall edge: occupied when darker than
       `edge_wall_grey`, free otherwise."""
    g = img.grey
    if img.occupied_thresh is not None:
        p = (255.0 - g) / 255.0
        occupied = p > img.occupied_thresh
        free = p < (img.free_thresh if img.free_thresh is not None else 0.196)
    else:
        occupied = g <= params.door_grey_low
        free = g >= params.door_grey_high
    candidate = ~occupied & ~free
    if not candidate.any():
        return occupied, candidate
    cross = cv2.getStructuringElement(cv2.MORPH_CROSS, (3, 3))
    touching = cv2.dilate(occupied.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    near_wall = cv2.dilate(occupied.astype(np.uint8), np.ones((5, 5), np.uint8)).astype(bool)
    n, labels = cv2.connectedComponents((candidate & ~touching).astype(np.uint8), connectivity=4)
    door = np.zeros_like(candidate)
    for k in range(1, n):
        core = labels == k
        region = cv2.dilate(core.astype(np.uint8), cross).astype(bool) & candidate
        if door_looks_like_a_door(region, near_wall, img.frame.resolution, params):
            door |= region
    edge = candidate & ~door
    occupied = occupied | (edge & (g < params.edge_wall_grey))
    return occupied & ~door, door


def door_looks_like_a_door(
    region: np.ndarray, near_wall: np.ndarray, resolution: float, params: HeightmapParams
) -> bool:
    """A grey region is a door when its minimum-area rectangle's long side is within
    [door_min_width, door_max_width], at least `door_min_aspect` times its short side, the
    region fills at least `door_min_fill` of it, and it bridges two walls: both ends (the
    outer 2 px along the long side) lie within 2 px of a wall (`near_wall`), while at most a
    fifth of the pixels between them do (an edge or strip along a wall is near it all along)."""
    rows, cols = np.nonzero(region)
    if len(rows) < max(params.min_speck_area, 1):
        return False
    corners = np.concatenate([np.stack([cols + du, rows + dv], axis=1) for du in (0, 1) for dv in (0, 1)])
    (_, _), (w, h), deg = cv2.minAreaRect(corners.astype(np.float32))
    long_px, short_px = max(w, h), max(min(w, h), 1.0)
    if not (params.door_min_width <= long_px * resolution <= params.door_max_width):
        return False
    if long_px / short_px < params.door_min_aspect or len(rows) / (long_px * short_px) < params.door_min_fill:
        return False
    a = math.radians(deg if w >= h else deg + 90.0)
    along = cols * math.cos(a) + rows * math.sin(a)
    near = near_wall[rows, cols]
    first, last = along <= along.min() + 2.0, along >= along.max() - 2.0
    between = ~first & ~last
    return bool(near[first].any() and near[last].any() and (not between.any() or near[between].mean() <= 0.2))


def drop_specks(
    mask: np.ndarray, min_area: int, connectivity: int
) -> tuple[np.ndarray, list[tuple[int, float, float]]]:
    """The mask without connected blobs smaller than `min_area` px, and the dropped ones as
    (area, centre column, centre row)."""
    n, labels, stats, centroids = cv2.connectedComponentsWithStats(
        mask.astype(np.uint8), connectivity=connectivity
    )
    small = np.flatnonzero(stats[1:, cv2.CC_STAT_AREA] < min_area) + 1
    if len(small) == 0:
        return mask, []
    keep = mask & ~np.isin(labels, small)
    dropped = [
        (int(stats[k, cv2.CC_STAT_AREA]), float(centroids[k, 0]), float(centroids[k, 1])) for k in small
    ]
    return keep, dropped


def outline_loops(mask: np.ndarray, tolerance_px: float) -> list[np.ndarray]:
    """Closed outlines (outer boundaries and holes) of the mask's blobs, simplified by
    Douglas-Peucker, as (K, 2) continuous pixel coordinates (u, v), K >= 3."""
    k = UPSAMPLE
    up = cv2.resize(mask.astype(np.uint8), None, fx=k, fy=k, interpolation=cv2.INTER_NEAREST)
    up = cv2.copyMakeBorder(up, 1, 1, 1, 1, cv2.BORDER_CONSTANT, value=0)
    contours, _ = cv2.findContours(up, cv2.RETR_CCOMP, cv2.CHAIN_APPROX_NONE)
    loops: list[np.ndarray] = []
    for c in contours:
        poly = cv2.approxPolyDP(c, tolerance_px * k, True)
        if len(poly) < 3:  # a thin sliver collapsed to a line: keep its bounding rectangle
            poly = cv2.boxPoints(cv2.minAreaRect(c)).reshape(-1, 1, 2)
        pts = poly[:, 0, :].astype(float)
        # drop repeated vertices; an upsampled boundary pixel's centre is 1/(2k) px inside the edge
        keep = np.any(pts != np.roll(pts, 1, axis=0), axis=1)
        pts = pts[keep]
        if len(pts) >= 3:
            loops.append((pts - 1 + 0.5) / k)
    return loops


def door_rectangles(
    door_mask: np.ndarray, min_area: int, grey: np.ndarray | None = None
) -> tuple[list[np.ndarray], list[tuple[int, float, float]], list[int]]:
    """One rectangle (4, 2) in continuous pixel coordinates per 4-connected door region, the
    grey specks dropped as too small, and each kept region's median grey value."""
    n, labels, stats, centroids = cv2.connectedComponentsWithStats(door_mask.astype(np.uint8), connectivity=4)
    rects: list[np.ndarray] = []
    greys: list[int] = []
    dropped: list[tuple[int, float, float]] = []
    for k in range(1, n):
        area = int(stats[k, cv2.CC_STAT_AREA])
        if area < min_area:
            dropped.append((area, float(centroids[k, 0]), float(centroids[k, 1])))
            continue
        x, y, w, h = (int(v) for v in stats[k, :4])
        rows, cols = np.nonzero(labels[y : y + h, x : x + w] == k)
        rows, cols = rows + y, cols + x
        if grey is not None:
            greys.append(int(np.median(grey[rows, cols])))
        corners = np.concatenate(
            [np.stack([cols + du, rows + dv], axis=1) for du in (0, 1) for dv in (0, 1)]
        ).astype(np.float32)
        rects.append(cv2.boxPoints(cv2.minAreaRect(corners)).astype(float))
    return rects, dropped, greys


def vectorise(img: HeightmapImage, params: HeightmapParams | None = None) -> GlobalMap:
    """The image as a `GlobalMap`: blob outlines as walls, grey regions as door polygons."""
    params = params or HeightmapParams()
    occupied, door = classify(img, params)
    occupied, specks = drop_specks(occupied, params.min_speck_area, connectivity=8)
    loops = outline_loops(occupied, params.simplify_tolerance)
    if not loops:
        what = "only specks smaller than min_speck_area" if specks else "no dark (occupied) pixels"
        raise MapError(f"no walls: the image has {what}", file=img.yaml_path or img.path)
    doors_px, grey_specks, door_greys = door_rectangles(door, params.min_speck_area, img.grey)

    points: list[np.ndarray] = []
    walls: list[np.ndarray] = []
    doors: list[np.ndarray] = []
    n = 0
    for loop in loops:
        idx = np.arange(n, n + len(loop))
        walls.append(np.stack([idx, np.roll(idx, -1)], axis=1))
        points.append(img.frame.to_world(loop))
        n += len(loop)
    for rect in doors_px:
        idx = np.arange(n, n + 4)
        doors.append(np.stack([idx, np.roll(idx, -1)], axis=1).astype(np.int64))
        points.append(img.frame.to_world(rect))
        n += 4

    warnings = list(img.notes)
    for kind, found in (("speck", specks), ("grey (door) speck", grey_specks)):
        for area, cx, cy in found[:MAX_LISTED_SPECKS]:
            x, y = img.frame.to_world(np.array([[cx + 0.5, cy + 0.5]]))[0]
            warnings.append(
                f"dropped a {kind} of {area} px at pixel (col {cx:.0f}, row {cy:.0f}) = ({x:.3f}, {y:.3f}) m"
            )
        if len(found) > MAX_LISTED_SPECKS:
            rest = found[MAX_LISTED_SPECKS:]
            warnings.append(
                f"dropped {len(rest)} more {kind}s ({sum(a for a, _, _ in rest)} px in all)"
            )
    info: dict[str, Any] = {
        "image": img.path.name,
        **({"yaml": img.yaml_path.name} if img.yaml_path else {}),
        **img.frame.to_dict(),
        "walls": "outlines",
    }
    if door_greys:
        # the emc simulator slides a door whose grey is below 128 the other way
        info["door_grey"] = door_greys
    return GlobalMap(
        points=np.vstack(points),
        walls=np.vstack(walls).astype(np.int64),
        doors=doors,
        extra={"heightmap": info},
        key_order=["points", "walls", "doors", "heightmap"],
        source=img.yaml_path or img.path,
        warnings=warnings,
    )


def load_heightmap(
    path: str | Path, params: HeightmapParams | None = None, resolution: float | None = None
) -> GlobalMap:
    """Read and vectorise a heightmap image or map_server YAML."""
    return vectorise(read_heightmap(path, params, resolution), params)
