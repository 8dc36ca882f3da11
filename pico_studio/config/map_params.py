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
    solid_loop_width: float = param(
        0.35, lo=0.0, hi=5.0, step=0.05, unit="m",
        help="A closed loop of JSON walls no wider than this (twice its area over its perimeter) is a solid "
        "wall drawn as its outline: filled when drawn into an image (0: never)",
    )
    margin: float = param(
        0.25, lo=0.0, hi=10.0, step=0.05, unit="m",
        help="Free border around the map's bounds in a written image",
    )


@dataclass(frozen=True)
class OpeningParams:
    """What a door opening is in a map (`json_map.openings`): the truth scores doors against
    these and the combined map confirms doors where they are."""

    door_min_width: float = param(0.5, lo=0.1, hi=5.0, step=0.05, unit="m", help="Narrowest gap between wall ends that counts as a door opening",
                                 at_most="door_max_width")
    door_max_width: float = param(1.5, lo=0.1, hi=5.0, step=0.05, unit="m", help="Widest gap between wall ends that counts as a door opening")
    max_wall_thickness: float = param(0.3, lo=0.01, hi=2.0, step=0.01, unit="m", help="A short segment closing a thick wall's end (an end cap) is at most this long")
    straight_tolerance: float = param(0.15, lo=0.0, hi=1.0, step=0.01, unit="rad", help="Walls meeting within this of a straight line form no corner (a passage mouth is between corners)")
    abut_tolerance: float = param(0.03, lo=0.0, hi=0.1, step=0.001, unit="m", help="A wall vertex this close to another wall abuts it (a T-junction): no free wall end there")
    mouth_probe: float = param(0.25, lo=0.05, hi=2.0, step=0.05, unit="m", help="How far either side of a candidate passage mouth the free width is measured")
    mouth_wall_length: float = param(0.5, lo=0.0, hi=5.0, step=0.05, unit="m", help="A passage's side walls run at least this long from its mouth (a plant pot beside a wall makes no passage)")
    mouth_margin: float = param(0.1, lo=0.0, hi=1.0, step=0.01, unit="m", help="A passage is at most this much wider than its mouth (and the area it opens into at least door_min_width wider)")
    mouth_depth: float = param(0.9, lo=0.0, hi=5.0, step=0.05, unit="m", help="A passage runs on free at least this far past its mouth (straight in from its middle): the niche between two tables or cabinets standing against a wall is shallower, no door (a table 0.8 m deep a few cm off the wall, fused with it on a heightmap, leaves a niche 0.81-0.85 m deep; 0: any)")


@dataclass(frozen=True)
class MapParams:
    heightmap: HeightmapParams = section(HeightmapParams, "Heightmap images: vectorising walls and doors")
    openings: OpeningParams = section(OpeningParams, "Door openings of a map: what the truth scores and the combined map confirms against")
    raster: RasterParams = section(RasterParams, "Drawing vector maps into occupancy/heightmap images")
