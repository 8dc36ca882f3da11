"""Heightmap images: every real image loads, where it lies in the world, broken inputs fail clearly."""

from __future__ import annotations

import json
import math
from pathlib import Path

import cv2
import numpy as np
import pytest

from pico_studio.config.map_params import HeightmapParams
from pico_studio.errors import MapError
from pico_studio.json_map import GridFrame, load_map
from pico_studio.json_map.convert import tolerant_iou
from pico_studio.json_map.heightmap import classify, read_heightmap, vectorise
from pico_studio.json_map.raster import rasterise

REAL_IMAGES = {  # file: doors
    "doors_heightmap_example.png": 4,
    "escape_room.png": 0,
    "hospital_2021.png": 0,
    "restaurant_2024.png": 1,
    "restaurant_2024.yaml": 1,
}


@pytest.mark.parametrize("name", sorted(REAL_IMAGES))
def test_every_real_image_loads(maps_dir: Path, name: str) -> None:
    m = load_map(maps_dir / name)
    assert len(m.walls) >= 4
    assert np.isfinite(m.points).all()
    assert len(m.doors) == REAL_IMAGES[name]
    assert m.extra["heightmap"]["walls"] == "outlines"
    # every wall is a real segment
    seg = m.wall_segments
    assert (np.hypot(seg[:, 2] - seg[:, 0], seg[:, 3] - seg[:, 1]) > 1e-6).all()


@pytest.mark.parametrize("name", ["doors_heightmap_example.png", "escape_room.png", "hospital_2021.png", "restaurant_2024.png"])
def test_unsimplified_outlines_reproduce_the_image_exactly(maps_dir: Path, name: str) -> None:
    # with no simplification the outlines, filled, give back exactly the occupied pixels:
    # the pixel <-> metre convention is consistent both ways
    params = HeightmapParams(simplify_tolerance=0.0, min_speck_area=0)
    img = read_heightmap(maps_dir / name, params)
    occupied, _ = classify(img, params)
    r = rasterise(vectorise(img, params), img.frame)
    assert tolerant_iou(occupied, r.occupied, tolerance_px=0) == 1.0


def test_hospital_2021_free_form_shapes_become_many_walls(maps_dir: Path) -> None:
    m = load_map(maps_dir / "hospital_2021.png")
    assert len(m.walls) > 300  # plants and the round table are free-form outlines
    assert m.extra["heightmap"]["shape"] == [569, 576]
    x0, y0, x1, y1 = m.bounds
    assert -7.2 < x0 < -6.9 and 6.9 < x1 < 7.2 and -7.2 < y0 < -6.9 and 6.9 < y1 < 7.2


def test_escape_room_stray_pixel_is_dropped_and_reported(maps_dir: Path) -> None:
    m = load_map(maps_dir / "escape_room.png")
    specks = [w for w in m.warnings if "speck" in w]
    assert len(specks) == 1
    assert "6 px" in specks[0] and "col 255, row 558" in specks[0]
    # nothing is left near the speck: all walls belong to the room around the image centre
    x0, y0, x1, y1 = m.bounds
    assert x0 > -4 and x1 < 1 and y0 > -3.2 and y1 < 3.1
    kept = load_map(maps_dir / "escape_room.png", HeightmapParams(min_speck_area=0))
    assert len(kept.walls) > len(m.walls) and not any("speck" in w for w in kept.warnings)


def _box_samples(pose_a, pose_b, length, width):  # noqa: ANN001, ANN202 - test helper
    out = []
    for t in np.linspace(0, 1, 50):
        x = pose_a[0] + t * (pose_b[0] - pose_a[0])
        y = pose_a[1] + t * (pose_b[1] - pose_a[1])
        for dx in np.linspace(-length / 2, length / 2, 9):
            for dy in np.linspace(-width / 2, width / 2, 5):
                out.append((x + dx, y + dy))
    return np.array(out)


def _free_fraction(occupied: np.ndarray, frame: GridFrame, xy: np.ndarray) -> float:
    uv = np.floor(frame.to_pixel(xy)).astype(int)
    h, w = occupied.shape
    inside = (uv[:, 0] >= 0) & (uv[:, 0] < w) & (uv[:, 1] >= 0) & (uv[:, 1] < h)
    free = np.zeros(len(xy), bool)
    free[inside] = ~occupied[uv[inside, 1], uv[inside, 0]]
    return float(free.mean())


def test_image_without_yaml_is_centred_with_x_up_like_the_emc_simulator(maps_dir: Path) -> None:
    # the moving objects of the 2021 simulator config must sweep through free space
    sim = json.loads((maps_dir / "hospital_2021_sim.json").read_text())
    img = read_heightmap(maps_dir / "hospital_2021.png")
    assert img.frame.kind == "emc_centred"
    occupied, _ = classify(img, HeightmapParams())
    samples = np.vstack(
        [_box_samples(o["init_pose"], o["final_pose"], o["length"], o["width"]) for o in sim["objects"]]
    )
    assert _free_fraction(occupied, img.frame, samples) > 0.99
    # the alternatives put them in walls or off the image
    h, w = occupied.shape
    centred_x_right = GridFrame.map_server((h, w), 0.025, (-w * 0.025 / 2, -h * 0.025 / 2))
    corner = GridFrame.map_server((h, w), 0.025, (0.0, 0.0))
    assert _free_fraction(occupied, centred_x_right, samples) < 0.9
    assert _free_fraction(occupied, corner, samples) < 0.5


def test_restaurant_png_with_yaml_overlays_the_restaurant_json(maps_dir: Path) -> None:
    img = read_heightmap(maps_dir / "restaurant_2024.png")
    assert img.yaml_path is not None and img.yaml_path.name == "restaurant_2024.yaml"
    occupied, door = classify(img, HeightmapParams())
    js = load_map(maps_dir / "restaurant_2024.json")

    def near_walls(frame: GridFrame) -> float:
        segs = js.wall_segments
        t = np.linspace(0, 1, 40)[:, None, None]
        pts = (segs[None, :, :2] * (1 - t) + segs[None, :, 2:] * t).reshape(-1, 2)
        dist = cv2.distanceTransform((~occupied).astype(np.uint8), cv2.DIST_L2, 5)
        uv = np.floor(frame.to_pixel(pts)).astype(int)
        h, w = occupied.shape
        ok = (uv[:, 0] >= 0) & (uv[:, 0] < w) & (uv[:, 1] >= 0) & (uv[:, 1] < h)
        near = np.zeros(len(pts), bool)
        near[ok] = dist[uv[ok, 1], uv[ok, 0]] <= 2.0
        return float(near.mean())

    assert near_walls(img.frame) > 0.97  # JSON walls lie on the image's wall edges
    assert near_walls(GridFrame.emc_centred(occupied.shape, 0.025)) < 0.7
    # the JSON's door is the image's grey region
    r = rasterise(js, img.frame)
    assert tolerant_iou(door, r.doors) > 0.75
    png_door = load_map(maps_dir / "restaurant_2024.png").door_polygons[0].mean(axis=0)
    np.testing.assert_allclose(png_door, js.door_polygons[0].mean(axis=0), atol=0.05)


def test_door_regions_become_rectangles(maps_dir: Path) -> None:
    m = load_map(maps_dir / "doors_heightmap_example.png")
    assert sorted(m.extra["heightmap"]["door_grey"]) == [90, 90, 180, 180]
    for poly in m.door_polygons:
        assert poly.shape == (4, 2)
        sides = np.linalg.norm(np.roll(poly, -1, axis=0) - poly, axis=1)
        assert max(sides) > 0.3  # a door is about a metre wide, not a speck
    # the slanted door (84 grey pixels, 13 x 28 bounding box) stays one door
    def slanted(p: np.ndarray) -> bool:
        d = np.roll(p, -1, axis=0) - p
        return bool((np.abs(d) > 0.02).all())

    tilted = [p for p in m.door_polygons if slanted(p)]
    assert len(tilted) == 1
    length = max(np.linalg.norm(np.roll(tilted[0], -1, axis=0) - tilted[0], axis=1))
    assert length == pytest.approx(math.hypot(13, 28) * 0.025, rel=0.15)


# ----- frames -------------------------------------------------------------------------------
def test_grid_frames_round_trip_and_place_corners() -> None:
    ms = GridFrame.map_server((10, 20), 0.5, (1.0, 2.0))
    assert ms.origin == (1.0, 2.0)
    assert ms.pixel_centre(0, 9) == (1.25, 2.25)  # bottom-left pixel
    assert ms.world_bounds == (1.0, 2.0, 11.0, 7.0)
    emc = GridFrame.emc_centred((10, 20), 0.5)
    assert emc.pixel_centre(9, 4) == (0.25, 0.25)  # just above-left of the image centre
    assert emc.to_world(np.array([[20.0, 0.0]]))[0].tolist() == [2.5, -5.0]  # top-right corner
    rot = GridFrame.map_server((10, 20), 0.5, (1.0, 2.0), yaw=0.3)
    for f in (ms, emc, rot):
        uv = np.array([[0.0, 0.0], [3.5, 7.25], [20.0, 10.0]])
        np.testing.assert_allclose(f.to_pixel(f.to_world(uv)), uv, atol=1e-12)
        assert GridFrame.from_dict(f.to_dict()) is not None
        np.testing.assert_allclose(GridFrame.from_dict(f.to_dict()).matrix, f.matrix, atol=1e-8)


# ----- image formats and YAML fields ---------------------------------------------------------
def _room(h: int = 60, w: int = 80) -> np.ndarray:
    img = np.full((h, w), 255, np.uint8)
    cv2.rectangle(img, (5, 5), (w - 6, h - 6), 0, 3)
    return img


def _write(path: Path, img: np.ndarray) -> Path:
    ok, data = cv2.imencode(path.suffix, img)
    assert ok
    path.write_bytes(data.tobytes())
    return path


def _yaml(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def test_many_specks_are_counted_not_all_listed(tmp_path: Path) -> None:
    img = _room()
    img[20:50:3, 20:70:3] = 0  # 10 x 17 single-pixel specks inside the room
    m = load_map(_write(tmp_path / "noisy.png", img))
    listed = [w for w in m.warnings if w.startswith("dropped a speck")]
    assert len(listed) == 20
    assert "dropped 150 more specks (150 px in all)" in m.warnings
    assert len(m.walls) == len(load_map(_write(tmp_path / "clean.png", _room())).walls)


def test_rgba_transparent_pixels_are_free(tmp_path: Path) -> None:
    grey = _room()
    rgba = np.dstack([grey, grey, grey, np.full_like(grey, 255)])
    rgba[30:40, 30:40] = (0, 0, 0, 0)  # transparent black: nothing drawn
    m = load_map(_write(tmp_path / "a.png", rgba))
    plain = load_map(_write(tmp_path / "b.png", grey))
    assert len(m.walls) == len(plain.walls)
    assert any("100 transparent pixels" in w for w in m.warnings)


def test_rgb_and_16_bit_pgm_load_like_grey(tmp_path: Path) -> None:
    grey = _room()
    base = load_map(_write(tmp_path / "g.png", grey))
    rgb = load_map(_write(tmp_path / "c.png", cv2.cvtColor(grey, cv2.COLOR_GRAY2BGR)))
    pgm16 = load_map(_write(tmp_path / "d.pgm", grey.astype(np.uint16) * 257))
    for other in (rgb, pgm16):
        np.testing.assert_allclose(other.points, base.points)


def test_yaml_origin_negate_and_resolution(tmp_path: Path) -> None:
    grey = _room()
    _write(tmp_path / "room.png", grey)
    _write(tmp_path / "neg.png", 255 - grey)
    a = load_map(_yaml(tmp_path / "a.yaml", "image: room.png\nresolution: 0.05\norigin: [1.0, -2.0, 0.0]\n"))
    assert a.extra["heightmap"]["frame"] == "map_server"
    x0, y0, x1, y1 = a.bounds
    rows, cols = np.nonzero(grey == 0)
    # x right from the origin, y up from the bottom row; outlines lie within a pixel of the edge
    assert x0 == pytest.approx(1.0 + cols.min() * 0.05, abs=0.03)
    assert y0 == pytest.approx(-2.0 + (60 - 1 - rows.max()) * 0.05, abs=0.03)
    assert x1 - x0 == pytest.approx((cols.max() + 1 - cols.min()) * 0.05, abs=0.05)
    b = load_map(_yaml(tmp_path / "b.yaml", "image: neg.png\nresolution: 0.05\norigin: [1.0, -2.0, 0.0]\nnegate: 1\n"))
    np.testing.assert_allclose(b.points, a.points)
    # a bare image: default 0.025 m/px, centred; --resolution overrides
    bare = load_map(tmp_path / "room.png")
    # x runs along the rows (up the image)
    assert bare.extent[0] == pytest.approx((rows.max() + 1 - rows.min()) * 0.025, abs=0.03)
    assert load_map(tmp_path / "room.png", resolution=0.05).extent[0] == pytest.approx(2 * bare.extent[0])


def test_sibling_yaml_is_used_only_when_it_names_the_image(tmp_path: Path) -> None:
    _write(tmp_path / "room.png", _room())
    _yaml(tmp_path / "room.yaml", "image: other.png\nresolution: 0.05\n")
    (tmp_path / "other.png").write_bytes((tmp_path / "room.png").read_bytes())
    assert load_map(tmp_path / "room.png").extra["heightmap"]["frame"] == "emc_centred"
    _yaml(tmp_path / "room.yaml", "image: room.png\nresolution: 0.05\n")
    assert load_map(tmp_path / "room.png").extra["heightmap"]["frame"] == "map_server"


BROKEN_YAMLS = [
    ("resolution: 0.05\n", "image", "missing key"),
    ("image: missing.png\nresolution: 0.05\n", "image", "does not exist"),
    ("image: room.png\n", "resolution", "missing key"),
    ("image: room.png\nresolution: -1\n", "resolution", "out of range"),
    ("image: room.png\nresolution: fast\n", "resolution", "must be a finite number"),
    ("image: room.png\nresolution: .nan\n", "resolution", "must be a finite number"),
    ("image: room.png\nresolution: 0.05\norigin: [1, 2, 3, 4]\n", "origin", "[x, y, yaw]"),
    ("image: room.png\nresolution: 0.05\norigin: [a, 0]\n", "origin", "[x, y, yaw]"),
    ("image: room.png\nresolution: 0.05\nnegate: 2\n", "negate", "must be 0 or 1"),
    ("image: room.png\nresolution: 0.05\noccupied_thresh: 1.5\n", "occupied_thresh", "out of range"),
    ("image: room.png\nresolution: 0.05\nfree_thresh: 0.9\noccupied_thresh: 0.5\n", "free_thresh", "must be below"),
    ("image: [room.png]\nresolution: 0.05\n", "image", "must be a file name"),
]


@pytest.mark.parametrize(("text", "field", "message"), BROKEN_YAMLS)
def test_broken_yaml_names_the_field(tmp_path: Path, text: str, field: str, message: str) -> None:
    _write(tmp_path / "room.png", _room())
    path = _yaml(tmp_path / "bad.yaml", text)
    with pytest.raises(MapError) as e:
        load_map(path)
    assert e.value.field == field
    assert message in str(e.value)
    assert str(path) in str(e.value)


def _garbage(tmp: Path) -> Path:
    (tmp / "x.png").write_bytes(b"this is not a png")
    return tmp / "x.png"


def _empty(tmp: Path) -> Path:
    (tmp / "x.pgm").write_bytes(b"")
    return tmp / "x.pgm"


def _white(tmp: Path) -> Path:
    return _write(tmp / "x.png", np.full((40, 40), 255, np.uint8))


def _specks_only(tmp: Path) -> Path:
    img = np.full((40, 40), 255, np.uint8)
    img[10, 10] = img[30, 20] = 0
    return _write(tmp / "x.png", img)


def _not_yaml(tmp: Path) -> Path:
    return _yaml(tmp / "x.yaml", "image: [unclosed\n")


def _yaml_list(tmp: Path) -> Path:
    return _yaml(tmp / "x.yaml", "- image\n")


def _yaml_bad_image(tmp: Path) -> Path:
    _garbage(tmp)
    return _yaml(tmp / "x.yaml", "image: x.png\nresolution: 0.05\n")


BROKEN_FILES = [
    (_garbage, "cannot read image"),
    (_empty, "cannot read image"),
    (_white, "no walls: the image has no dark (occupied) pixels"),
    (_specks_only, "no walls: the image has only specks"),
    (_not_yaml, "not valid YAML at line"),
    (_yaml_list, "must be a mapping"),
    (_yaml_bad_image, "cannot read image"),
    (lambda tmp: tmp / "missing.png", "no such file"),
    (lambda tmp: tmp / "map.txt", "unknown map format '.txt'"),
]


@pytest.mark.parametrize(("make", "message"), BROKEN_FILES)
def test_broken_images_raise_a_clear_map_error(tmp_path: Path, make, message: str) -> None:  # noqa: ANN001
    path = make(tmp_path)
    with pytest.raises(MapError) as e:
        load_map(path)
    assert message in str(e.value)
    assert str(path) in str(e.value)
