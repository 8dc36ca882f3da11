"""Parameters of map loading: how heightmap images become vector walls and doors."""

from __future__ import annotations

from dataclasses import dataclass

from pico_studio.config.spec import param, section


@dataclass(frozen=True)
class HeightmapParams:
    resolution: float = param(
        0.025, lo=0.001, hi=1.0, step=0.001, unit="m/px",
        help="Pixel size of a heightmap image that has no map_server YAML",
    )
    simplify_tolerance: float = param(
        1.0, lo=0.0, hi=10.0, step=0.25, unit="px",
        help="Douglas-Peucker tolerance when turning wall contours into segments",
    )
    min_speck_area: int = param(
        10, lo=0, hi=1000, step=1, unit="px",
        help="Occupied blobs smaller than this are stray pixels: dropped and reported",
    )
    door_grey_low: int = param(
        50, lo=0, hi=255, step=1, unit="grey",
        help="Without a map_server YAML: grey values up to this are walls; above it (and below door_grey_high) door candidates",
        below="door_grey_high",
    )
    door_grey_high: int = param(
        205, lo=0, hi=255, step=1, unit="grey",
        help="Without a map_server YAML: grey values from this up are free; below it (and above door_grey_low) door candidates",
    )

    door_min_width: float = param(
        0.5, lo=0.05, hi=5.0, step=0.05, unit="m",
        help="A grey region is a door only when its long side is at least this long", at_most="door_max_width",
    )
    door_max_width: float = param(
        1.5, lo=0.05, hi=10.0, step=0.05, unit="m",
        help="A grey region is a door only when its long side is at most this long",
    )
    door_min_aspect: float = param(
        2.0, lo=1.0, hi=50.0, step=0.5,
        help="A grey region is a door only when its long side is this many times its short side",
    )
    door_min_fill: float = param(
        0.5, lo=0.0, hi=1.0, step=0.05,
        help="A grey region is a door only when it fills this fraction of its bounding rectangle",
    )
    edge_wall_grey: int = param(
        128, lo=0, hi=255, step=1, unit="grey",
        help="A grey pixel that is no door's is a wall (an anti-aliased wall edge) when darker than this, else free",
    )


@dataclass(frozen=True)
class RasterParams:
    resolution: float = param(
        0.025, lo=0.001, hi=1.0, step=0.001, unit="m/px",
        help="Pixel size of a heightmap image written from a vector map",
    )
    wall_thickness: int = param(
        3, lo=1, hi=50, step=1, unit="px",
        help="Line width of a (zero-thickness) JSON wall when it is drawn into an image",
    )
    margin: float = param(
        0.25, lo=0.0, hi=10.0, step=0.05, unit="m",
        help="Free border around the map's bounds in a written image",
    )


@dataclass(frozen=True)
class MapParams:
    heightmap: HeightmapParams = section(HeightmapParams, "Heightmap images: vectorising walls and doors")
    raster: RasterParams = section(RasterParams, "Drawing vector maps into occupancy/heightmap images")
