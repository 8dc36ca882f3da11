"""Converting maps both ways — JSON -> heightmap PNG/PGM + map_server YAML, heightmap -> JSON —
with a round-trip check of the geometry.

    from pico_studio.json_map.convert import convert
    result = convert("hospital_2019.json", "hospital_2019.png")   # also writes hospital_2019.yaml
    result.iou                                                     # >= 0.95 on the real maps

Round-trip check: the converted file is loaded again and rasterised in the frame of the
reference, and its occupied pixels are compared with the reference's:
- image -> JSON: the reference is the original image's occupied pixels (specks included),
  in the image's own frame;
- JSON -> image: the reference is the image just written (the JSON rasterised); the
  written image is vectorised again and rasterised in the same frame.

The figure is an intersection-over-union with a tolerance of `tolerance_px` (1 px): a
pixel of one side counts as matched when the other side has an occupied pixel within the
3 x 3 neighbourhood (dilation), so a half-pixel shift of an edge is not an error:
    matched_a = |A ∩ dilate(B)|,  matched_b = |B ∩ dilate(A)|
    tp = (matched_a + matched_b) / 2,  fn = |A| - matched_a,  fp = |B| - matched_b
    IoU = tp / (tp + fn + fp)           (1.0 when both are empty)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from pico_studio.config.map_params import MapParams
from pico_studio.errors import MapError
from pico_studio.json_map.grid import GridFrame
from pico_studio.json_map.heightmap import (
    IMAGE_SUFFIXES,
    YAML_SUFFIXES,
    HeightmapImage,
    classify,
    read_heightmap,
    vectorise,
)
from pico_studio.json_map.json_io import load_json_map, save_json_map
from pico_studio.json_map.model import GlobalMap
from pico_studio.json_map.raster import Raster, frame_for, rasterise

# map_server thresholds written with every image: grey 128 (a door) stays "unknown" to
# map_server, black is occupied, white free.
OCCUPIED_THRESH = 0.65
FREE_THRESH = 0.196


def tolerant_iou(a: np.ndarray, b: np.ndarray, tolerance_px: int = 1) -> float:
    """Intersection over union of two boolean masks, edges allowed to move `tolerance_px`."""
    a, b = a.astype(bool), b.astype(bool)
    if not a.any() and not b.any():
        return 1.0
    if tolerance_px > 0:
        kernel = np.ones((2 * tolerance_px + 1, 2 * tolerance_px + 1), np.uint8)
        da = cv2.dilate(a.astype(np.uint8), kernel).astype(bool)
        db = cv2.dilate(b.astype(np.uint8), kernel).astype(bool)
    else:
        da, db = a, b
    matched_a = int((a & db).sum())
    matched_b = int((b & da).sum())
    tp = (matched_a + matched_b) / 2
    fn = int(a.sum()) - matched_a
    fp = int(b.sum()) - matched_b
    return tp / (tp + fn + fp)


@dataclass
class RoundTrip:
    """How well a converted map reproduces the reference's pixels."""

    iou: float  # occupied pixels, after the tolerance
    iou_strict: float  # occupied pixels, no tolerance (for information)
    iou_doors: float | None  # door pixels; None when neither side has doors
    reference_px: int  # occupied pixels of the reference
    converted_px: int  # occupied pixels of the converted map, rasterised again


def round_trip(
    reference_occupied: np.ndarray,
    reference_doors: np.ndarray,
    converted: GlobalMap,
    frame: GridFrame,
    params: MapParams | None = None,
) -> RoundTrip:
    params = params or MapParams()
    r = rasterise(converted, frame, params=params.raster)
    doors = None
    if reference_doors.any() or r.doors.any():
        doors = tolerant_iou(reference_doors, r.doors)
    return RoundTrip(
        iou=tolerant_iou(reference_occupied, r.occupied),
        iou_strict=tolerant_iou(reference_occupied, r.occupied, tolerance_px=0),
        iou_doors=doors,
        reference_px=int(reference_occupied.sum()),
        converted_px=int(r.occupied.sum()),
    )


@dataclass
class ConvertResult:
    written: list[Path]  # the files written (the image and its YAML, or the JSON)
    map: GlobalMap  # the map as converted
    check: RoundTrip


def write_heightmap(raster: Raster, path: str | Path) -> tuple[Path, Path]:
    """Write the image (.png or .pgm) and a map_server YAML beside it (same stem, .yaml)."""
    p = Path(path)
    if p.suffix.lower() not in IMAGE_SUFFIXES:
        raise MapError(f"cannot write an image as {p.suffix!r}; use .png or .pgm", file=p)
    ok, data = cv2.imencode(p.suffix.lower(), raster.image)
    if not ok:  # pragma: no cover - OpenCV encodes every 8-bit grey image
        raise MapError("OpenCV could not encode the image", file=p)
    ox, oy = raster.origin
    yaml_path = p.with_suffix(".yaml")
    text = (
        f"image: {p.name}\n"
        f"resolution: {raster.resolution:.6f}\n"
        f"origin: [{ox:.6f}, {oy:.6f}, {raster.frame.yaw:.6f}]\n"
        f"negate: 0\n"
        f"occupied_thresh: {OCCUPIED_THRESH}\n"
        f"free_thresh: {FREE_THRESH}\n"
    )
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_bytes(data.tobytes())
        yaml_path.write_text(text, encoding="utf-8")
    except OSError as e:
        raise MapError(f"cannot write: {e.strerror or e}", file=p) from None
    return p, yaml_path


def as_heightmap(m: GlobalMap, params: MapParams | None = None) -> GlobalMap:
    """The map as the emc simulator's heightmap shows it: drawn into an image (`rasterise`,
    `params.raster`) and read back (`vectorise`, `params.heightmap`), as `convert` to a .png and
    back would, without files: walls become the outlines of dark blobs, a table against a wall
    part of the wall, cabinets and tables walls. Named after the map's source."""
    params = params or MapParams()
    raster = rasterise(m, resolution=params.raster.resolution, params=params.raster)
    name = Path(m.source).with_suffix(".png") if m.source is not None else Path("map.png")
    img = HeightmapImage(raster.image, raster.frame, name, None, OCCUPIED_THRESH, FREE_THRESH)
    out = vectorise(img, params.heightmap)
    out.opening_params = m.opening_params
    return out


def _is_image(p: Path) -> bool:
    return p.suffix.lower() in IMAGE_SUFFIXES + YAML_SUFFIXES


def convert(
    src: str | Path,
    dst: str | Path,
    *,
    resolution: float | None = None,
    params: MapParams | None = None,
) -> ConvertResult:
    """Convert `src` (.json, or a .png/.pgm/.yaml heightmap) to `dst` by its suffix.

    `dst` .json: the vector map; .png/.pgm: the image plus a map_server YAML beside it;
    .yaml: the image named after it (.png) plus the YAML. `resolution` is the pixel size
    of the image written, or of a source image that has no YAML.
    """
    params = params or MapParams()
    src, dst = Path(src), Path(dst)
    if src.resolve() == dst.resolve():
        raise MapError("the output would overwrite the input", file=dst)
    dst_suffix = dst.suffix.lower()
    if dst_suffix not in (".json", *IMAGE_SUFFIXES, *YAML_SUFFIXES):
        raise MapError(
            f"unknown output format {dst.suffix!r}: use .json, .png, .pgm or .yaml", file=dst
        )

    if _is_image(src):
        img = read_heightmap(src, params.heightmap, resolution if dst_suffix == ".json" else None)
        m = vectorise(img, params.heightmap)
        ref_occ, ref_doors = classify(img, params.heightmap)
        ref_frame = img.frame
    elif src.suffix.lower() == ".json":
        m = load_json_map(src)
        ref_occ = ref_doors = None
        ref_frame = None
    else:
        raise MapError(f"unknown map format {src.suffix!r}: use .json, .png, .pgm or .yaml", file=src)

    if dst_suffix == ".json":
        try:
            save_json_map(m, dst)
        except OSError as e:
            raise MapError(f"cannot write: {e.strerror or e}", file=dst) from None
        back = load_json_map(dst)
        if ref_frame is None:  # JSON -> JSON: compare both rasterised
            ref_frame = frame_for(m, resolution, params.raster)
            r = rasterise(m, ref_frame, params=params.raster)
            ref_occ, ref_doors = r.occupied, r.doors
        assert ref_occ is not None and ref_doors is not None
        return ConvertResult([dst], m, round_trip(ref_occ, ref_doors, back, ref_frame, params))

    image_path = dst.with_suffix(".png") if dst_suffix in YAML_SUFFIXES else dst
    raster = rasterise(m, resolution=resolution, params=params.raster)
    written = list(write_heightmap(raster, image_path))
    if dst_suffix in YAML_SUFFIXES and written[1] != dst:  # ".yml" asked for
        written[1] = written[1].replace(dst)
    back = vectorise(read_heightmap(written[1], params.heightmap), params.heightmap)
    check = round_trip(raster.occupied, raster.doors, back, raster.frame, params)
    return ConvertResult(written, back, check)
