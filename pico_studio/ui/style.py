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
COMBINED_UNSEEN: RGB = (160, 160, 225)  # dashed over a map wall the robot has not seen yet
DOOR: RGB = (60, 190, 40)
POSSIBLE_DOOR: RGB = (220, 180, 40)
POSSIBLE_DOOR_KIND: dict[str, RGB] = {  # core.perception.identify.POSSIBLE_DOOR_KINDS
    "convex_loose": POSSIBLE_DOOR,
    "loose_loose": (235, 120, 60),
    "loose_wall": (170, 130, 210),
}
POSSIBLE_DOOR_KIND_NAMES = {
    "convex_loose": "possible door: convex corner - loose end",
    "loose_loose": "possible door: loose end - loose end",
    "loose_wall": "possible door: loose end - wall",
}
SPIKE_CORNER: RGB = (140, 70, 0)
VECTOR_CORNER_INNER: RGB = (0, 160, 110)
VECTOR_CORNER_OUTER: RGB = (235, 50, 140)
ROBOT_TRUE: RGB = (0, 0, 0)
ROBOT_ESTIMATE: RGB = (20, 90, 225)
TRAIL: RGB = (170, 170, 170)
PROXIMITY: RGB = (240, 95, 150)
PROXIMITY_FLAGGED: RGB = (245, 20, 20)
BEHAVIOUR_TARGET: RGB = (160, 0, 255)
BEHAVIOUR_PLAN: RGB = (0, 120, 60)
ENTRANCE: RGB = (50, 180, 190)
HALLWAY: RGB = (0, 120, 120)  # the entrance estimate when it comes from a hallway's two walls
ROOM_SIDE: RGB = (150, 150, 150)  # the watched side beam
ROOM_JUMP: RGB = (200, 60, 10)  # ... when its range jumped: a side room's opening
MEASURE: RGB = (230, 40, 220)
INSPECT: RGB = (230, 200, 80)

# line thickness in metres (world units: stays put when zooming)
THICK_MAP = 0.05
THICK_LAYER = 0.035
POINT_SIZE = 0.05
DASH, DASH_GAP = 0.15, 0.1  # never-seen map walls: dash and gap, metres


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
    ("Combined map", [(COMBINED_MATCHED, "matched wall"), (COMBINED_UNMATCHED, "unmatched wall"),
                      (COMBINED_UNSEEN, "map wall never seen (dashed)")]),
    ("Doors (global frame when localised)", [(DOOR, "door")] + [(c, POSSIBLE_DOOR_KIND_NAMES[k]) for k, c in POSSIBLE_DOOR_KIND.items()]),
    ("Scan corners (seed 002)", [(SPIKE_CORNER, "spike corner"), (VECTOR_CORNER_INNER, "vector corner, inner"),
                                 (VECTOR_CORNER_OUTER, "vector corner, outer")]),
    ("Robot", [(ROBOT_TRUE, "true pose (simulated)"), (ROBOT_ESTIMATE, "estimated pose")]),
    ("Trail", [(TRAIL, "path driven")]),
    ("Proximity", [(PROXIMITY, "bubble"), (PROXIMITY_FLAGGED, "flagged beams")]),
    ("Behaviour", [(BEHAVIOUR_TARGET, "target"), (BEHAVIOUR_PLAN, "plan")]),
    ("Entrance", [(ENTRANCE, "entrance estimate"), (HALLWAY, "... in a hallway")]),
    ("Side room watch (seed 000)", [(ROOM_SIDE, "side beam"), (ROOM_JUMP, "side range jumped: a room")]),
    ("Tools", [(MEASURE, "measure"), (INSPECT, "inspected feature")]),
]


def legend_html() -> str:
    rows = []
    for title, items in LEGEND:
        rows.append(f"<div><b>{title}</b>: " + " &nbsp; ".join(swatch(c, t) for c, t in items) + "</div>")
    return '<div style="font-size:0.8em;line-height:1.5">' + "".join(rows) + "</div>"
