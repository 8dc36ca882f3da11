"""Global maps: load, validate, convert and write the challenge's JSON maps and heightmaps.

    from pico_studio.json_map import load_map
    m = load_map("examples/maps/hospital_2019.json")   # or a .png/.pgm heightmap
    m.wall_segments                                    # (N, 4) array of x1, y1, x2, y2
"""

from __future__ import annotations

from pico_studio.json_map.json_io import load_json_map, map_from_dict, save_json_map
from pico_studio.json_map.model import GlobalMap

__all__ = ["GlobalMap", "load_json_map", "map_from_dict", "save_json_map"]
