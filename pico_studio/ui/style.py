"""Fixed, legible colours of every layer (on the page's white background) and the legend.

One place for them: the layers draw with these, the legend lists them, the browser test looks
for their pixels. Line colours are kept within what the page's tone curve can show (see
`colour.py`), so they appear as declared.
"""

from __future__ import annotations

RGB = tuple[int, int, int]

# global map
MAP_WALL: RGB = (40, 40, 40)
MAP_OBJECT: RGB = (150, 100, 50)
MAP_OBJECT_FRONT: RGB = (240, 135, 30)
MAP_DOOR: RGB = (0, 150, 150)
MAP_START: RGB = (60, 150, 225)
SIM_WORLD: RGB = (120, 90, 190)  # the simulator's doors (as they slide) and moving objects
# perception
LASER: RGB = (230, 30, 30)
CURRENT_MAP: RGB = (200, 0, 200)
LOCAL_WALL: RGB = (30, 90, 220)
ENDPOINT: dict[int, RGB] = {
    0: (150, 150, 150),  # floating
    1: (0, 170, 200),  # connected
    2: (255, 120, 0),  # convex
    3: (130, 40, 200),  # concave
}
ENDPOINT_NAMES = {0: "floating", 1: "connected", 2: "convex", 3: "concave"}
COMBINED_MATCHED: RGB = (0, 170, 0)
COMBINED_UNMATCHED: RGB = (220, 0, 80)
DOOR: RGB = (60, 190, 40)
POSSIBLE_DOOR: RGB = (220, 180, 40)
ROBOT_TRUE: RGB = (0, 0, 0)
ROBOT_ESTIMATE: RGB = (20, 90, 225)
TRAIL: RGB = (170, 170, 170)
PROXIMITY: RGB = (240, 95, 150)
PROXIMITY_FLAGGED: RGB = (245, 20, 20)
BEHAVIOUR_TARGET: RGB = (160, 0, 255)
BEHAVIOUR_PLAN: RGB = (0, 120, 60)
ENTRANCE: RGB = (50, 180, 190)
MEASURE: RGB = (230, 40, 220)
INSPECT: RGB = (230, 200, 80)

# line thickness in metres (world units: stays put when zooming)
THICK_MAP = 0.05
THICK_LAYER = 0.035
POINT_SIZE = 0.05


def swatch(rgb: RGB, text: str) -> str:
    r, g, b = rgb
    return (
        f'<span style="display:inline-block;width:0.9em;height:0.9em;margin-right:0.4em;'
        f'vertical-align:middle;background:rgb({r},{g},{b})"></span>{text}'
    )


LEGEND: list[tuple[str, list[tuple[RGB, str]]]] = [
    ("Global map", [(MAP_WALL, "walls"), (MAP_OBJECT, "cabinets / tables"), (MAP_OBJECT_FRONT, "their front"),
                    (MAP_DOOR, "doors"), (MAP_START, "start area")]),
    ("Simulated world", [(SIM_WORLD, "doors as they are now, moving objects")]),
    ("Laser", [(LASER, "laser points")]),
    ("Current map", [(CURRENT_MAP, "segments of this scan")]),
    ("Local map", [(LOCAL_WALL, "walls")] + [(ENDPOINT[k], f"{ENDPOINT_NAMES[k]} end point / corner") for k in range(4)]),
    ("Combined map", [(COMBINED_MATCHED, "matched wall"), (COMBINED_UNMATCHED, "unmatched wall")]),
    ("Doors", [(DOOR, "door"), (POSSIBLE_DOOR, "possible door")]),
    ("Robot", [(ROBOT_TRUE, "true pose (simulated)"), (ROBOT_ESTIMATE, "estimated pose")]),
    ("Trail", [(TRAIL, "path driven")]),
    ("Proximity", [(PROXIMITY, "bubble"), (PROXIMITY_FLAGGED, "flagged beams")]),
    ("Behaviour", [(BEHAVIOUR_TARGET, "target"), (BEHAVIOUR_PLAN, "plan")]),
    ("Entrance", [(ENTRANCE, "entrance estimate")]),
    ("Tools", [(MEASURE, "measure"), (INSPECT, "inspected feature")]),
]


def legend_html() -> str:
    rows = []
    for title, items in LEGEND:
        rows.append(f"<div><b>{title}</b>: " + " &nbsp; ".join(swatch(c, t) for c, t in items) + "</div>")
    return '<div style="font-size:0.8em;line-height:1.5">' + "".join(rows) + "</div>"
