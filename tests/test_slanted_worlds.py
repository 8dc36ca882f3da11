"""`slant:SEED`: a ward or a suite drawn askew — every doorway still an opening to the truth,
walls meeting at 76-84 degrees, the same world for the same seed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pico_studio.evaluation.worlds import make_world


def _angles(segments: np.ndarray) -> np.ndarray:
    """Each wall's direction, folded to [0, pi)."""
    d = segments[:, 2:] - segments[:, :2]
    return np.mod(np.arctan2(d[:, 1], d[:, 0]), math.pi)


@pytest.mark.parametrize("seed", range(6))
def test_a_slanted_world_keeps_every_opening_of_its_square_one(seed: int) -> None:
    slant = make_world(f"slant:{seed}")
    square = make_world(f"{'ward' if seed % 2 == 0 else 'suite'}:{seed}")
    assert len(slant.map.openings()) == len(square.map.openings()) > 0
    assert len(slant.map.wall_segments) == len(square.map.wall_segments)
    # two families of walls, 76-84 degrees apart (not 90): the shear tilts one of them
    a = _angles(slant.map.wall_segments)
    fam = np.unique(np.round(a, 2))  # (points are written to 0.1 mm)
    fam = fam[np.r_[True, np.diff(fam) > 0.02]]
    assert len(fam) == 2
    between = math.degrees(abs(fam[1] - fam[0]))
    between = min(between, 180 - between)
    assert 75.5 < between < 84.5


def test_a_slanted_world_is_the_same_for_the_same_seed() -> None:
    a, b = make_world("slant:3"), make_world("slant:3")
    assert np.array_equal(a.map.wall_segments, b.map.wall_segments)
    assert a.start == b.start
    assert not np.array_equal(a.map.wall_segments, make_world("slant:5").map.wall_segments)
