"""Fixed, legible colours of every layer (on the page's white background) and the legend.

One place for them: the layers draw with these, the legend lists them, the browser test looks
for their pixels. Line colours are kept within what the page's tone curve can show (see
`colour.py`), so they appear as declared.
"""

from __future__ import annotations

RGB = tuple[int, int, int]

# Okabe & Ito's colour-blind-safe set (black, orange, sky blue, bluish green, yellow, blue,
# vermillion, reddish purple), stretched with darker / lighter shades of the same hues and
# greys; every layer's colour differs from every other's (tests/test_ui_style.py checks).
OI_BLACK, OI_ORANGE, OI_SKY, OI_GREEN = (0, 0, 0), (230, 159, 0), (86, 180, 233), (0, 158, 115)
OI_YELLOW, OI_BLUE, OI_VERMILLION, OI_PURPLE = (240, 228, 66), (0, 114, 178), (213, 94, 0), (204, 121, 167)

# global map
MAP_WALL: RGB = OI_BLACK
MAP_OBJECT: RGB = (125, 85, 45)  # brown
MAP_OBJECT_FRONT: RGB = (230, 159, 32)  # Okabe-Ito orange as the page can show it
MAP_DOOR: RGB = (0, 60, 100)  # dark blue
MAP_OPENING: RGB = (60, 130, 110)  # sea green: the map's door openings, what confirms a door
MAP_START: RGB = (135, 220, 225)  # pale sky blue
SIM_WORLD: RGB = (110, 60, 150)  # violet: the simulator's doors (as they slide) and moving objects
# perception
LASER: RGB = OI_PURPLE
CURRENT_MAP: RGB = (225, 0, 225)  # magenta
LOCAL_WALL: RGB = OI_BLUE
ENDPOINT: dict[int, RGB] = {
    0: (120, 120, 120),  # floating: mid grey
    1: OI_SKY,  # connected
    2: OI_VERMILLION,  # convex
    3: (0, 100, 40),  # concave: dark green
}
ENDPOINT_NAMES = {0: "floating", 1: "connected", 2: "convex", 3: "concave"}
COMBINED_MATCHED: RGB = OI_GREEN
COMBINED_UNMATCHED: RGB = (200, 0, 60)  # crimson
COMBINED_UNSEEN: RGB = (161, 164, 226)  # periwinkle dashes over a map wall not seen yet
DOOR: RGB = (165, 190, 36)  # lime (the tone curve cannot show Okabe-Ito's yellow on lines)
DOOR_REMEMBERED: RGB = (80, 130, 60)  # moss: a door remembered, not found in this scan
POSSIBLE_DOOR: RGB = (240, 140, 115)  # salmon
POSSIBLE_DOOR_KIND: dict[str, RGB] = {  # core.perception.identify.POSSIBLE_DOOR_KINDS
    "convex_loose": POSSIBLE_DOOR,
    "loose_loose": (170, 29, 3),  # dark vermillion
    "loose_wall": (236, 157, 226),  # pink
    "end_face": (60, 0, 120),  # deep indigo
    "bay": (100, 210, 80),  # leaf green: a door's shape, for the map to prove
    "jamb": (250, 40, 140),  # rose: one jamb, its other side out of view, for the map to prove
}
POSSIBLE_DOOR_KIND_NAMES = {
    "convex_loose": "possible door: convex corner - loose end",
    "loose_loose": "possible door: loose end - loose end",
    "loose_wall": "possible door: loose end - wall",
    "end_face": "possible door: wall end - wall face, not yet seen through over enough scans (or for the map)",
    "bay": "possible door: a door's shape between block corners (a bay, or a thin-walled room's mouth)",
    "jamb": "possible door: a building wall's end with nothing ahead (its other jamb out of view)",
}
SPIKE_CORNER: RGB = (90, 50, 0)  # dark brown
VECTOR_CORNER_INNER: RGB = (0, 200, 200)  # cyan
VECTOR_CORNER_OUTER: RGB = (170, 0, 110)  # wine
ROBOT_TRUE: RGB = (60, 60, 60)  # dark grey
ROBOT_ESTIMATE: RGB = (40, 40, 220)  # strong blue
TRAIL: RGB = (215, 215, 215)  # light grey
TRUE_PATH: RGB = (190, 150, 90)  # tan: a recording's true trajectory
PROXIMITY: RGB = (230, 200, 129)  # peach
PROXIMITY_FLAGGED: RGB = (250, 30, 38)  # red
BEHAVIOUR_TARGET: RGB = (140, 0, 240)  # purple
BEHAVIOUR_PLAN: RGB = (100, 160, 0)  # olive green
ENTRANCE: RGB = (60, 130, 170)  # steel blue
HALLWAY: RGB = (120, 200, 160)  # pale green
ROOM_SIDE: RGB = (148, 100, 227)  # lilac: the watched side beam
ROOM_JUMP: RGB = (150, 130, 0)  # ... when its range jumped: a side room's opening
DIFF_ADDED: RGB = (30, 180, 30)  # green: a wall, corner or door config B adds against A
DIFF_LOST: RGB = (210, 15, 15)  # red: ... one B loses
MEASURE: RGB = (249, 22, 139)
INSPECT: RGB = (230, 213, 82)
PLUGIN_OUTPUT: RGB = (0, 0, 130)  # navy: whatever a plugin handed the page (WorldModel.extras)
REFERENCE_MAP: RGB = (180, 230, 120)  # pale green: a replay's scans cast from its true poses

# line thickness in screen pixels (the same on screen at any zoom); drawn from the bottom up
# in LAYERS order, so the map's thick black walls show either side of the thinner local and
# combined walls drawn on them
THICK_MAP = 5.0
THICK_LAYER = 2.0
POINT_PX = 4.0  # markers' default size in screen pixels: small, so walls stay visible
DASH, DASH_GAP = 0.15, 0.1  # never-seen map walls: dash and gap, metres
LEGEND_BOX = (250, 150)  # the on-canvas legend's largest size (px), bottom left


def swatch(rgb: RGB, text: str) -> str:
    r, g, b = rgb
    return (
        f'<span style="display:inline-block;width:0.9em;height:0.9em;margin-right:0.4em;'
        f'vertical-align:middle;background:rgb({r},{g},{b})"></span>{text}'
    )


LEGEND: list[tuple[str, list[tuple[RGB, str]]]] = [
    ("Global map", [(MAP_WALL, "walls"), (MAP_OBJECT, "cabinets / tables"), (MAP_OBJECT_FRONT, "their front"),
                    (MAP_DOOR, "doors"), (MAP_OPENING, "door openings (what confirms a door; the truth's)"),
                    (MAP_START, "start area")]),
    ("Simulated world", [(SIM_WORLD, "doors as they are now, moving objects")]),
    ("Laser", [(LASER, "laser points")]),
    ("Current map", [(CURRENT_MAP, "segments of this scan")]),
    ("Local map", [(LOCAL_WALL, "walls")] + [(ENDPOINT[k], f"{ENDPOINT_NAMES[k]} end point / corner") for k in range(4)]),
    ("Combined map", [(COMBINED_MATCHED, "matched wall"), (COMBINED_UNMATCHED, "unmatched wall"),
                      (COMBINED_UNSEEN, "map wall never seen (dashed)")]),
    ("Doors (global frame when localised)", [(DOOR, "door"), (DOOR_REMEMBERED, "door remembered: found from places apart, not in this scan")] + [(c, POSSIBLE_DOOR_KIND_NAMES[k]) for k, c in POSSIBLE_DOOR_KIND.items()]),
    ("Scan corners (seed 002)", [(SPIKE_CORNER, "spike corner"), (VECTOR_CORNER_INNER, "vector corner, inner"),
                                 (VECTOR_CORNER_OUTER, "vector corner, outer")]),
    ("Robot", [(ROBOT_TRUE, "true pose (simulated, or a recording's corrected poses)"), (ROBOT_ESTIMATE, "estimated pose")]),
    ("Trail", [(TRAIL, "path driven"), (TRUE_PATH, "a recording's true trajectory")]),
    ("Proximity", [(PROXIMITY, "bubble"), (PROXIMITY_FLAGGED, "flagged beams")]),
    ("Behaviour", [(BEHAVIOUR_TARGET, "target"), (BEHAVIOUR_PLAN, "plan")]),
    ("Entrance", [(ENTRANCE, "entrance estimate"), (HALLWAY, "... in a hallway")]),
    ("Side room watch (seed 000)", [(ROOM_SIDE, "side beam"), (ROOM_JUMP, "side range jumped: a room")]),
    ("A/B diff", [(DIFF_ADDED, "B adds (vs A)"), (DIFF_LOST, "B loses")]),
    ("Tools", [(MEASURE, "measure"), (INSPECT, "inspected feature")]),
    ("Plugins", [(PLUGIN_OUTPUT, "a plugin's extra points / segments")]),
    ("Reference map (replay with true poses)", [(REFERENCE_MAP, "every scan cast from its true pose: the building as seen")]),
]


def legend_html() -> str:
    rows = []
    for title, items in LEGEND:
        rows.append(f"<div><b>{title}</b>: " + " &nbsp; ".join(swatch(c, t) for c, t in items) + "</div>")
    return '<div style="font-size:0.8em;line-height:1.5">' + "".join(rows) + "</div>"


def swatches(colours: list[RGB]) -> str:
    return "".join(swatch(c, "") for c in colours)


# colours drawn as points (point clouds are not tone-mapped: they show as declared)
POINT_COLOURS = {LASER, *ENDPOINT.values(), SPIKE_CORNER, VECTOR_CORNER_INNER, VECTOR_CORNER_OUTER, BEHAVIOUR_TARGET,
                 DIFF_ADDED, DIFF_LOST, PLUGIN_OUTPUT, REFERENCE_MAP}

# the layer key -> its colours as the Layers tab shows them beside the toggle
LAYER_COLOURS: dict[str, list[RGB]] = {
    "map": [MAP_WALL, MAP_OBJECT, MAP_OBJECT_FRONT, MAP_DOOR, MAP_OPENING, MAP_START],
    "sim_world": [SIM_WORLD],
    "trail": [TRAIL],
    "truth_path": [TRUE_PATH],
    "combined": [COMBINED_MATCHED, COMBINED_UNMATCHED, COMBINED_UNSEEN],
    "local": [LOCAL_WALL, *ENDPOINT.values()],
    "current": [CURRENT_MAP],
    "scan_corners": [SPIKE_CORNER, VECTOR_CORNER_INNER, VECTOR_CORNER_OUTER],
    "doors": [DOOR, DOOR_REMEMBERED, *POSSIBLE_DOOR_KIND.values()],
    "laser": [LASER],
    "proximity": [PROXIMITY, PROXIMITY_FLAGGED],
    "robot": [ROBOT_TRUE, ROBOT_ESTIMATE],
    "behaviour": [BEHAVIOUR_TARGET, BEHAVIOUR_PLAN],
    "entrance": [ENTRANCE, HALLWAY],
    "room": [ROOM_SIDE, ROOM_JUMP],
    "plugins": [PLUGIN_OUTPUT],
    "ab_diff": [DIFF_LOST, DIFF_ADDED],
    "reference_map": [REFERENCE_MAP],
}


def swatch_row(layer: str) -> str:
    """The colour swatches shown just above a layer's toggle."""
    return f'<div style="margin:4px 0 0 2px;line-height:1">{swatches(LAYER_COLOURS.get(layer, []))}</div>'


SHORT_LEGEND: list[tuple[RGB, str]] = [
    (MAP_WALL, "map wall"), (COMBINED_UNSEEN, "not seen yet"), (COMBINED_MATCHED, "matched wall"),
    (LOCAL_WALL, "local wall"), (LASER, "laser"), (DOOR, "door"), (ROBOT_ESTIMATE, "robot (estimate)"),
]


def short_legend_html(dark: bool = False) -> str:
    """The few colours a newcomer needs first (the help modal has them all)."""
    rows = "".join(f"<div>{swatch(c if not (dark and c == MAP_WALL) else (200, 200, 200), t)}</div>" for c, t in SHORT_LEGEND)
    return rows + "<div style='opacity:.7'>H: help, all colours</div>"
