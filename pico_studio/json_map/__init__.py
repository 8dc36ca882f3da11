"""Global maps: load, validate, convert and write the challenge's JSON maps and heightmaps.

    from pico_studio.json_map import load_map
    m = load_map("examples/maps/hospital_2019.json")   # or a .png/.pgm heightmap, or its .yaml
    m.wall_segments                                    # (N, 4) array of x1, y1, x2, y2

    from pico_studio.json_map import rasterise, convert
    r = rasterise(m)                    # occupancy image + its frame (raster.py)
    convert("map.json", "map.png")      # + map.yaml; returns the round-trip IoU (convert.py)
"""

from __future__ import annotations

from pathlib import Path

from pico_studio.config.map_params import HeightmapParams, MapParams
from pico_studio.errors import MapError
from pico_studio.json_map.convert import ConvertResult, RoundTrip, convert, tolerant_iou
from pico_studio.json_map.grid import GridFrame
from pico_studio.json_map.heightmap import IMAGE_SUFFIXES, YAML_SUFFIXES, load_heightmap
from pico_studio.json_map.json_io import load_json_map, map_from_dict, save_json_map
from pico_studio.json_map.model import GlobalMap
from pico_studio.json_map.raster import Raster, rasterise

MAP_SUFFIXES = (".json", *IMAGE_SUFFIXES, *YAML_SUFFIXES)


def load_map(
    path: str | Path,
    params: HeightmapParams | MapParams | None = None,
    *,
    resolution: float | None = None,
) -> GlobalMap:
    """Any map by its suffix: .json (vector map), .png/.pgm (heightmap image; a same-stem
    map_server YAML beside it that names it is used), .yaml/.yml (map_server file).
    `params` (cfg.map or cfg.map.heightmap) tunes vectorising (and cfg.map.openings what the
    map's door openings are, `GlobalMap.openings`); `resolution` overrides the
    pixel size of an image without a YAML. Raises `MapError` naming the file (and field)."""
    openings = params.openings if isinstance(params, MapParams) else None
    if isinstance(params, MapParams):
        params = params.heightmap
    gmap = _load(Path(path), params, resolution)
    if openings is not None:
        gmap.opening_params = openings
    return gmap


def _load(p: Path, params: HeightmapParams | None, resolution: float | None) -> GlobalMap:
    suffix = p.suffix.lower()
    if suffix not in MAP_SUFFIXES:
        raise MapError(
            f"unknown map format {p.suffix or '(no suffix)'!r}: use .json, .png, .pgm or .yaml", file=p
        )
    if not p.exists():
        raise MapError("no such file", file=p)
    if suffix == ".json":
        return load_json_map(p)
    return load_heightmap(p, params, resolution)


__all__ = [
    "MAP_SUFFIXES",
    "ConvertResult",
    "GlobalMap",
    "GridFrame",
    "Raster",
    "RoundTrip",
    "convert",
    "load_heightmap",
    "load_json_map",
    "load_map",
    "map_from_dict",
    "rasterise",
    "save_json_map",
    "tolerant_iou",
]
