"""Heightmap truth: grey regions are doors only when they look like doors and bridge two walls;
anti-aliased wall edges are walls. Pixels are read with map_server's thresholds under a YAML."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from pico_studio.config.map_params import HeightmapParams
from pico_studio.json_map import load_map
from pico_studio.json_map.heightmap import classify, read_heightmap
from pico_studio.json_map.openings import door_frame

RES = 0.025  # the default pixel size of an image without a YAML


def _line(img: np.ndarray, a: tuple[float, float], b: tuple[float, float], grey: int, thickness: int) -> None:
    # sub-pixel end points (shift 4): every wall edge is a row of anti-aliased grey pixels
    def p(x: float, y: float) -> tuple[int, int]:
        return (round(x * 16), round(y * 16))

    cv2.line(img, p(*a), p(*b), grey, thickness, cv2.LINE_AA, 4)


def _anti_aliased_room() -> np.ndarray:
    """A 5 x 4 m room (walls 4 px) with a diagonal inner wall and a 0.9 m doorway in the bottom
    wall, closed by a grey (128) door, all drawn anti-aliased."""
    img = np.full((200, 240), 255, np.uint8)
    x0, y0, x1, y1 = 20.3, 20.6, 220.4, 180.5
    for a, b in [((x0, y0), (x1, y0)), ((x1, y0), (x1, y1)), ((x0, y1), (x0, y0)),
                 ((x1, y1), (138.4, y1)), ((102.4, y1), (x0, y1))]:
        _line(img, a, b, 0, 4)
    _line(img, (137.0, y1), (104.0, y1), 128, 3)
    _line(img, (60.2, 60.7), (150.3, 120.9), 0, 3)
    return img


def test_an_anti_aliased_image_has_exactly_its_one_door(tmp_path: Path) -> None:
    img = _anti_aliased_room()
    assert len(np.unique(img)) > 50  # really anti-aliased: many grey levels on the edges
    cv2.imwrite(str(tmp_path / "room.png"), img)
    m = load_map(tmp_path / "room.png")
    assert len(m.door_polygons) == 1
    centre, _, size, thickness = door_frame(m.door_polygons[0])
    assert size == pytest.approx(36 * RES, abs=2 * RES)  # the doorway, not the walls' edges
    assert thickness < 0.25
    # where the door is: the middle of the gap, on the bottom wall
    (u, v), = read_heightmap(tmp_path / "room.png").frame.to_pixel(centre[None, :])
    assert u == pytest.approx(120.4, abs=1.5) and v == pytest.approx(181.0, abs=1.5)
    assert not any("grey" in w for w in m.warnings)


def test_anti_aliased_wall_edges_are_walls(tmp_path: Path) -> None:
    img = _anti_aliased_room()
    cv2.imwrite(str(tmp_path / "room.png"), img)
    hm = read_heightmap(tmp_path / "room.png")
    occupied, door = classify(hm, HeightmapParams())
    edge = (img > 50) & (img < 205) & ~door
    # every dark edge pixel is a wall, every light one free
    assert np.all(occupied[edge & (img < 128)]) and not np.any(occupied[edge & (img >= 128)])
    # the door region is a compact strip across the gap: nothing along the walls
    rows, cols = np.nonzero(door)
    assert cols.min() >= 100 and cols.max() <= 141 and rows.max() - rows.min() <= 8


@pytest.mark.parametrize(("what", "draw"), [
    ("a grey strip along a wall", lambda img: cv2.rectangle(img, (60, 24), (95, 27), 128, -1)),
    ("a grey bar in the open", lambda img: cv2.rectangle(img, (60, 90), (95, 93), 128, -1)),
    ("a grey square in a gap", lambda img: cv2.rectangle(img, (102, 100), (137, 135), 128, -1)),
])
def test_grey_that_does_not_look_like_a_door_is_no_door(tmp_path: Path, what: str, draw: object) -> None:
    img = np.full((200, 240), 255, np.uint8)
    cv2.rectangle(img, (20, 20), (220, 23), 0, -1)  # a top wall
    cv2.rectangle(img, (20, 100), (101, 135), 0, -1)  # two blocks with a 36 px gap between
    cv2.rectangle(img, (138, 100), (220, 135), 0, -1)
    draw(img)  # type: ignore[operator]
    cv2.imwrite(str(tmp_path / "m.png"), img)
    assert load_map(tmp_path / "m.png").door_polygons == [], what


def test_a_hard_edged_door_between_two_walls_is_a_door(tmp_path: Path) -> None:
    img = np.full((200, 240), 255, np.uint8)
    cv2.rectangle(img, (20, 100), (101, 103), 0, -1)
    cv2.rectangle(img, (138, 100), (220, 103), 0, -1)
    cv2.rectangle(img, (102, 100), (137, 103), 128, -1)  # 36 x 4 px: 0.9 x 0.1 m
    cv2.imwrite(str(tmp_path / "m.png"), img)
    doors = load_map(tmp_path / "m.png").door_polygons
    assert len(doors) == 1 and door_frame(doors[0])[2] == pytest.approx(0.9)


def test_a_yaml_reads_pixels_with_map_servers_thresholds(tmp_path: Path) -> None:
    img = np.full((40, 60), 255, np.uint8)
    img[5:8, :] = 80  # p = 0.69 > occupied_thresh 0.65: occupied (the emc rule, v <= 50, says door)
    img[20:23, 10:15] = 150  # p = 0.41: between the thresholds, a door candidate (too small: none)
    img[30:33, :] = 215  # p = 0.16 < free_thresh 0.196: free
    cv2.imwrite(str(tmp_path / "m.png"), img)
    (tmp_path / "m.yaml").write_text("image: m.png\nresolution: 0.05\norigin: [0, 0, 0]\n", encoding="utf-8")
    occupied, door = classify(read_heightmap(tmp_path / "m.yaml"), HeightmapParams())
    assert occupied[5:8].all() and not occupied[30:33].any() and not door.any()
    assert not occupied[20:23, 10:15].any()  # an undecided pixel lighter than edge_wall_grey is free
    (tmp_path / "m.yaml").write_text("image: m.png\nresolution: 0.05\nnegate: 1\n", encoding="utf-8")
    occupied, _ = classify(read_heightmap(tmp_path / "m.yaml"), HeightmapParams())
    assert occupied[0, 0] and not occupied[5, 0]  # negated: white is occupied, 80 -> 175 is not


def test_a_table_a_pixel_off_a_wall_meets_it_in_a_concave_corner(tmp_path: Path) -> None:
    """A table drawn one pixel (2.5 cm) off a wall: its outline's corner lies 3.1 cm from the
    wall's (the outlines are simplified), past `sim.truth.abut_tolerance` (3 cm), so the truth
    called the corner convex where the laser sees the table's front run into the wall. On a
    heightmap a vertex abuts within a pixel more (a table 3 cm off a wall is drawn 1 or 2
    pixels off it): concave."""
    from pico_studio.config import Config
    from pico_studio.sim import Simulator
    from pico_studio.sim.truth import abut_tolerance

    img = np.full((140, 180), 255, np.uint8)  # 4.5 x 3.5 m
    img[:, :4] = img[:, -4:] = img[:4, :] = img[-4:, :] = 0  # walls 4 px (0.1 m)
    img[80:112, 100:175] = 0  # a table 0.8 m deep, its right side a pixel off the right wall (col 176)
    cv2.imwrite(str(tmp_path / "m.png"), img)
    (tmp_path / "m.yaml").write_text("image: m.png\nresolution: 0.025\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
                                     "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    m = load_map(tmp_path / "m.yaml")
    assert abut_tolerance(m, 0.03) == pytest.approx(0.055)
    sim = Simulator(m, Config().sim, None, seed=1, initial_pose=(2.0, 2.9, -0.5))
    sim.advance(0.1)
    vc = sim.truth.visible_corners()
    near = np.hypot(*(vc.points - [4.375, 1.5]).T) < 0.1  # the table's top right corner
    assert near.sum() == 1 and not vc.convex[near][0]
    json_map = load_map(Path(__file__).resolve().parents[1] / "examples" / "maps" / "emc_example.json")
    assert abut_tolerance(json_map, 0.03) == 0.03  # a vector map's vertices are where they were drawn
