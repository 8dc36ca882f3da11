"""How a JSON map's walls come out in a heightmap image: a solid wall drawn as its outline is
filled, lines meet in square corners and end square, and a generated world keeps its door
openings through `map convert` to a PNG and back."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from pico_studio.cli import main
from pico_studio.config.map_params import RasterParams
from pico_studio.evaluation.worlds import make_world
from pico_studio.json_map import load_map, rasterise
from pico_studio.json_map.json_io import map_from_dict, save_json_map
from pico_studio.json_map.raster import FREE, OCCUPIED, Raster, solid_loops, wall_bands


def _map(points: list[tuple[float, float]], walls: list[tuple[int, int]]):  # noqa: ANN202
    return map_from_dict(
        {"points": [{"x": x, "y": y} for x, y in points], "walls": [list(w) for w in walls]}
    )


def _at(r: Raster, xy: tuple[float, float]) -> int:
    u, v = np.floor(r.frame.to_pixel(np.array([xy], float))[0]).astype(int)
    return int(r.image[v, u])


def _loop(
    x0: float, y0: float, x1: float, y1: float, first: int
) -> tuple[list[tuple[float, float]], list[tuple[int, int]]]:
    pts = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    return pts, [(first + k, first + (k + 1) % 4) for k in range(4)]


def test_a_thin_closed_loop_is_a_solid_wall_a_rooms_ring_is_not() -> None:
    wall_pts, wall_walls = _loop(1.0, 1.0, 4.0, 1.2, 0)  # a wall 0.2 m thick drawn as its outline
    room_pts, room_walls = _loop(0.0, 0.0, 5.0, 4.0, 4)  # a room's four walls: a ring of lines
    m = _map(wall_pts + room_pts, wall_walls + room_walls)
    loops, rest = solid_loops(m, 0.35)
    assert len(loops) == 1 and sorted(loops[0].tolist()) == [0, 1, 2, 3]
    assert rest.tolist() == [4, 5, 6, 7]
    r = rasterise(m)
    assert (
        _at(r, (2.5, 1.1)) == OCCUPIED
    )  # inside the thick wall: solid, no free line between its faces
    assert _at(r, (2.5, 2.5)) == FREE  # the room is not filled
    assert _at(r, (0.0, 2.0)) == OCCUPIED  # its walls are drawn as lines
    # 0 turns the rule off: the wall's two faces are lines with free space between them
    assert _at(rasterise(m, params=RasterParams(solid_loop_width=0.0)), (2.5, 1.1)) == FREE


def test_walls_meet_in_square_corners_and_end_square() -> None:
    # an L of two walls sharing a point, each end free elsewhere
    m = _map([(1.0, 1.0), (3.0, 1.0), (3.0, 3.0)], [(0, 1), (1, 2)])
    half = 0.05
    bands = wall_bands(m.wall_segments, half)
    assert bands.shape == (2, 4, 2)
    # the first wall reaches half a width past the shared corner, not past its free end
    assert bands[0][:, 0].max() == pytest.approx(3.0 + half) and bands[0][
        :, 0
    ].min() == pytest.approx(1.0)
    r = rasterise(m, params=RasterParams(wall_thickness=5))  # 5 px = 0.125 m at 0.025 m/px
    assert _at(r, (3.05, 0.95)) == OCCUPIED  # the corner's outer square is filled: no notch
    assert _at(r, (0.97, 1.0)) == FREE  # cut square at the free end: no round cap bulging out


@pytest.mark.parametrize("spec", ["suite:4", "ward:3", "slant:5"])
def test_a_generated_world_keeps_its_openings_through_a_heightmap(
    spec: str, tmp_path: Path, capsys
) -> None:  # noqa: ANN001
    m = make_world(spec).map
    src = save_json_map(m, tmp_path / "w.json")
    assert main(["map", "convert", str(src), str(tmp_path / "w.png")]) == 0
    assert "IoU 1.0000" in capsys.readouterr().out
    mj, mp = np.asarray(m.openings()), np.asarray(load_map(tmp_path / "w.png").openings())
    assert len(mj) >= 2
    middles = (mp[:, :2] + mp[:, 2:]) / 2
    for o in mj:  # every opening of the vector map is one of the image's too
        assert np.min(np.hypot(*(middles - (o[:2] + o[2:]) / 2).T)) < 0.2, o
