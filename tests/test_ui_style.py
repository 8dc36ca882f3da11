"""The page's palette: every layer's colour differs from every other's as the page shows it."""

from __future__ import annotations

import itertools

import numpy as np

from pico_studio.ui import style
from pico_studio.ui.colour import line_display
from pico_studio.ui.scene_data import LAYERS, PRIM_SPECS

MIN_DIFFERENCE = 40  # the largest channel difference between any two layers' colours, 0..255


def _shown(rgb: style.RGB) -> np.ndarray:
    return np.array(rgb if rgb in style.POINT_COLOURS else line_display(rgb), dtype=int)


def test_no_two_layers_share_a_colour() -> None:
    named = [(f"{layer}:{i}", c) for layer, cs in style.LAYER_COLOURS.items() for i, c in enumerate(cs)]
    close = [(a, b) for (a, ca), (b, cb) in itertools.combinations(named, 2)
             if np.abs(_shown(ca) - _shown(cb)).max() < MIN_DIFFERENCE]
    assert not close, close


def test_the_pairs_that_used_to_clash_differ() -> None:
    """Doors vs matched walls; convex corners, cabinet fronts and loose-end possible doors;
    never-seen walls, loose-wall possible doors and simulated doors; floating end points,
    the side beam and the trail; laser points and flagged beams."""
    kinds = style.POSSIBLE_DOOR_KIND
    groups = [
        (style.DOOR, style.COMBINED_MATCHED),
        (style.ENDPOINT[2], style.MAP_OBJECT_FRONT, kinds["convex_loose"], kinds["loose_loose"]),
        (style.COMBINED_UNSEEN, kinds["loose_wall"], style.SIM_WORLD),
        (kinds["end_face"], style.DOOR, style.BEHAVIOUR_TARGET, style.LASER, style.ROBOT_ESTIMATE, kinds["loose_wall"]),
        (style.ENDPOINT[0], style.ROOM_SIDE, style.TRAIL),
        (style.LASER, style.PROXIMITY_FLAGGED),
    ]
    for group in groups:
        for a, b in itertools.combinations(group, 2):
            assert np.abs(_shown(a) - _shown(b)).max() >= MIN_DIFFERENCE, (a, b)


def test_every_layer_has_swatches_and_map_walls_show_under_local_ones() -> None:
    assert set(style.LAYER_COLOURS) == {layer.key for layer in LAYERS}
    for layer in LAYERS:
        assert style.swatch_row(layer.key).count("background:rgb") == len(style.LAYER_COLOURS[layer.key])
    order = list(PRIM_SPECS)
    # global map at the bottom, robot on top; the map's walls wider than the local/combined ones on them
    assert order.index("map_walls") < order.index("combined") < order.index("local_walls") < order.index("robot_estimate")
    assert PRIM_SPECS["map_walls"].thickness > PRIM_SPECS["combined"].thickness > PRIM_SPECS["local_walls"].thickness
    assert all(spec.point_size <= 12 for spec in PRIM_SPECS.values() if spec.kind == "points")  # modest markers, px
