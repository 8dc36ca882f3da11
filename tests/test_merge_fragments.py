"""Merge: a short wall lying along a longer one is a piece of it (`merge_kernels.lies_along`).
At a room's corner seen while turning, the local map kept a 0.11 m fragment of the side wall,
joined to the front wall, beside the side wall itself, whose end floated (escape:1100): the
corner was never one, the doorway beside it a bay. Seen from the fragment the long wall's far
end strays off its line, so the pieces' two-way test never merged them."""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config import load_config
from pico_studio.core.perception.merge_kernels import connect, merge_similar

PARAMS = load_config(None).perception.merge
SIDE = [3.58, -0.01, 3.60, 3.66]  # the room's side wall, its lower end floating
FRONT = [2.34, 0.01, 3.58, -0.01]  # the front wall up to the corner


def _merged(walls: list[list[float]]) -> np.ndarray:
    w = np.array(walls, dtype=float)
    n = len(w)
    out = merge_similar(w, np.array([10.0, 10.0, 3.0][:n]), np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64),
                        np.zeros((n, 2), dtype=bool), np.zeros((n, 2)), np.zeros((n, 2)), math.cos(PARAMS.angle),
                        float(PARAMS.distance), float(PARAMS.gap), float(PARAMS.max_weight))
    return out[0]


def test_a_corner_fragment_along_a_wall_is_part_of_it():
    # 0.11 m, 6 degrees off the side wall's direction: 0.36 m off its line at the side's far end
    fragment = [3.574, -0.01, 3.586, 0.10]
    walls = _merged([SIDE, FRONT, fragment])
    assert len(walls) == 2
    connected, _ = connect(walls, np.array([13.0, 10.0]), np.zeros((2, 2)), np.zeros((2, 2), dtype=bool),
                           float(PARAMS.connect_radius), math.sin(PARAMS.connect_min_angle),
                           float(PARAMS.confirm_hits), float(PARAMS.max_weight))
    assert (connected >= 0).sum() == 2  # the corner: the front wall's end and the side's


def test_a_piece_beside_a_wall_or_past_its_end_stays_apart():
    # a cabinet's front a step off the wall's line, and a stub in line past a doorway
    assert len(_merged([SIDE, FRONT, [3.70, 1.0, 3.70, 1.4]])) == 3
    assert len(_merged([SIDE, FRONT, [3.60, 4.5, 3.60, 4.7]])) == 3
