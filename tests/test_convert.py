"""Rasterising and converting maps both ways, with the round-trip IoU; the `map` CLI."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from pico_studio.cli import main
from pico_studio.config.map_params import HeightmapParams, RasterParams
from pico_studio.errors import MapError
from pico_studio.json_map import convert, load_map, rasterise, tolerant_iou
from pico_studio.json_map.convert import round_trip
from pico_studio.json_map.grid import GridFrame
from pico_studio.json_map.heightmap import classify, read_heightmap, vectorise
from pico_studio.json_map.raster import DOOR, FREE, OCCUPIED, frame_for, recorded_frame, wall_loops

REAL_JSON = ["emc_example.json", "hospital_2019.json", "hospital_2019_with_nodes.json", "restaurant_2024.json"]
REAL_IMAGES = ["doors_heightmap_example.png", "escape_room.png", "hospital_2021.png", "restaurant_2024.png", "restaurant_2024.yaml"]


# ----- tolerant IoU ---------------------------------------------------------------------------
def test_tolerant_iou_forgives_one_pixel_but_not_three() -> None:
    a = np.zeros((50, 50), bool)
    a[10:40, 20:23] = True
    assert tolerant_iou(a, a) == 1.0
    assert tolerant_iou(a, np.roll(a, 1, axis=1)) == 1.0
    assert tolerant_iou(a, np.roll(a, 1, axis=1), tolerance_px=0) == pytest.approx(0.5)
    assert tolerant_iou(a, np.roll(a, 5, axis=1)) == 0.0
    assert tolerant_iou(np.zeros_like(a), np.zeros_like(a)) == 1.0
    assert tolerant_iou(a, np.zeros_like(a)) == 0.0


# ----- rasterising ----------------------------------------------------------------------------
def _value_at(r, xy) -> int:  # noqa: ANN001
    u, v = np.floor(r.frame.to_pixel(np.array([xy]))[0]).astype(int)
    return int(r.image[v, u])


def test_rasterise_hospital_2019(maps_dir: Path) -> None:
    m = load_map(maps_dir / "hospital_2019.json")
    r = rasterise(m)
    assert r.resolution == 0.025 and r.origin == (0.0, 0.0)  # the map lies in x, y >= 0
    assert r.image.shape == (266, 278)  # 6.4 m + 0.25 m margin up, 6.7 + 0.25 m across
    assert set(np.unique(r.image)) == {OCCUPIED, FREE}
    seg = m.wall_segments[0]
    assert _value_at(r, (seg[:2] + seg[2:]) / 2) == OCCUPIED
    for poly in m.object_polygons:  # cabinets are filled
        assert _value_at(r, poly.mean(axis=0)) == OCCUPIED
    assert _value_at(r, (1.5, 3.0)) == FREE
    thick = rasterise(m, params=RasterParams(wall_thickness=7))
    assert thick.occupied.sum() > 1.5 * r.occupied.sum()


def test_rasterise_restaurant_doors_and_frames(maps_dir: Path) -> None:
    m = load_map(maps_dir / "restaurant_2024.json")
    r = rasterise(m, resolution=0.05)
    assert r.resolution == 0.05
    assert _value_at(r, m.door_polygons[0].mean(axis=0)) == DOOR
    assert _value_at(r, m.start_center) == FREE
    assert not rasterise(m, resolution=0.05, doors=False).doors.any()
    # into a given frame, e.g. shifted so the map has negative coordinates
    shifted = GridFrame.map_server((120, 160), 0.05, (-0.5, -0.5))
    assert rasterise(m, shifted).image.shape == (120, 160)


def test_frame_for_a_map_with_negative_coordinates(maps_dir: Path) -> None:
    m = load_map(maps_dir / "hospital_2021.png")
    f = frame_for(m)
    x0, y0, x1, y1 = m.bounds
    fx0, fy0, fx1, fy1 = f.world_bounds
    assert fx0 <= x0 - 0.2 and fy0 <= y0 - 0.2 and fx1 >= x1 + 0.2 and fy1 >= y1 + 0.2
    assert f.kind == "map_server" and recorded_frame(m).kind == "emc_centred"


def test_wall_loops() -> None:
    square = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    loops = wall_loops(np.vstack([square, square + 4]))
    assert [sorted(lp.tolist()) for lp in loops] == [[0, 1, 2, 3], [4, 5, 6, 7]]
    assert wall_loops(np.array([[0, 1], [1, 2]])) is None  # an open chain is not a loop


# ----- conversion both ways on every real file ---------------------------------------------------
@pytest.mark.parametrize("name", REAL_JSON)
def test_json_to_heightmap_round_trip(maps_dir: Path, tmp_path: Path, name: str) -> None:
    m = load_map(maps_dir / name)
    res = convert(maps_dir / name, tmp_path / "out.png")
    png, yml = res.written
    assert png.name == "out.png" and yml.name == "out.yaml"
    assert res.check.iou >= 0.95
    meta = yml.read_text()
    assert "image: out.png" in meta and "resolution: 0.025000" in meta
    # the image fed back through its YAML lies where the JSON does (walls drawn 3 px thick,
    # so the outer outline is up to 3 px beyond the JSON's zero-thickness walls)
    back = load_map(yml)
    np.testing.assert_allclose(back.bounds, m.bounds, atol=0.075)
    assert len(back.doors) == len(m.doors)


@pytest.mark.parametrize("name", REAL_IMAGES)
def test_heightmap_to_json_round_trip(maps_dir: Path, tmp_path: Path, name: str) -> None:
    res = convert(maps_dir / name, tmp_path / "out.json")
    assert res.check.iou >= 0.95
    if res.check.iou_doors is not None:
        assert res.check.iou_doors >= 0.95
    data = json.loads((tmp_path / "out.json").read_text())
    assert data["heightmap"]["walls"] == "outlines"
    back = load_map(tmp_path / "out.json")
    assert len(back.walls) == len(res.map.walls)
    # and back to an image again: the same geometry, in the same place (the YAML's origin is
    # negative for the centred bare images)
    again = convert(tmp_path / "out.json", tmp_path / "again.png")
    assert again.check.iou >= 0.95
    np.testing.assert_allclose(load_map(tmp_path / "again.yaml").bounds, back.bounds, atol=0.1)


def test_round_trip_detects_a_wrong_map(maps_dir: Path) -> None:
    # the check can fail: a map shifted by 4 px no longer matches the image
    img = read_heightmap(maps_dir / "hospital_2021.png")
    m = vectorise(img)
    occ, doors = classify(img, HeightmapParams())
    assert round_trip(occ, doors, m, img.frame).iou >= 0.95
    m.points = m.points + np.array([0.1, 0.0])
    assert round_trip(occ, doors, m, img.frame).iou < 0.8


def test_convert_resolution_and_yaml_output(maps_dir: Path, tmp_path: Path) -> None:
    res = convert(maps_dir / "hospital_2019.json", tmp_path / "h.yaml", resolution=0.05)
    assert [p.name for p in res.written] == ["h.png", "h.yaml"]
    assert cv2.imread(str(tmp_path / "h.png"), cv2.IMREAD_GRAYSCALE).shape == (133, 139)
    assert res.check.iou >= 0.95
    pgm = convert(maps_dir / "emc_example.json", tmp_path / "e.pgm")
    assert pgm.written[0].suffix == ".pgm" and pgm.check.iou >= 0.95


@pytest.mark.parametrize(
    ("src", "dst", "message"),
    [
        ("hospital_2019.json", "out.txt", "unknown output format '.txt'"),
        ("missing.json", "out.png", "cannot read"),
        ("hospital_2021_sim.json", "out.png", "missing key"),
        ("hospital_2021.png", "a_file/out.json", "cannot write"),
        ("hospital_2019.json", "a_file/out.png", "cannot write"),
    ],
)
def test_convert_errors(maps_dir: Path, tmp_path: Path, src: str, dst: str, message: str) -> None:
    (tmp_path / "a_file").write_text("not a directory")
    with pytest.raises(MapError, match=message.replace("(", r"\(")):
        convert(maps_dir / src, tmp_path / dst)


def test_convert_refuses_to_overwrite_its_input(tmp_path: Path, maps_dir: Path) -> None:
    src = tmp_path / "h.json"
    src.write_bytes((maps_dir / "hospital_2019.json").read_bytes())
    with pytest.raises(MapError, match="overwrite"):
        convert(src, src)


# ----- CLI -------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", REAL_JSON + REAL_IMAGES)
def test_map_info_every_real_file(maps_dir: Path, name: str, capsys) -> None:  # noqa: ANN001
    assert main(["map", "info", str(maps_dir / name), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["counts"]["walls"] > 0
    assert all(e > 0 for e in info["extent_m"])


def test_map_info_facts_of_the_issue(maps_dir: Path, capsys) -> None:  # noqa: ANN001
    assert main(["map", "info", str(maps_dir / "hospital_2019.json"), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["counts"] == {"points": 56, "walls": 40, "cabinets": 4, "doors": 0, "start_area": 0}
    assert info["extent_m"] == [6.7, 6.4]
    assert main(["map", "info", str(maps_dir / "restaurant_2024.json"), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["counts"]["tables"] == 5 and info["counts"]["doors"] == 1
    assert info["counts"]["start_area"] == 1


def test_map_info_png_draws_the_map(maps_dir: Path, tmp_path: Path, capsys) -> None:  # noqa: ANN001
    out = tmp_path / "r.png"
    assert main(["map", "info", str(maps_dir / "restaurant_2024.json"), "--png", str(out)]) == 0
    text = capsys.readouterr().out
    assert "5 tables" in text and str(out) in text
    img = cv2.imread(str(out))
    assert img is not None and max(img.shape[:2]) <= 900
    # red table fronts, orange door, green start area, black walls are all there
    b, g, r = img[..., 0].astype(int), img[..., 1].astype(int), img[..., 2].astype(int)
    assert ((r > 180) & (g < 60) & (b < 60)).sum() > 50
    assert ((r > 200) & (g > 120) & (g < 200) & (b < 120)).sum() > 50
    assert ((g > 200) & (r < 220) & (b < 220) & (g - r > 25)).sum() > 50
    assert ((r < 30) & (g < 30) & (b < 30)).sum() > 500


def test_map_convert_prints_the_iou(maps_dir: Path, tmp_path: Path, capsys) -> None:  # noqa: ANN001
    assert main(["map", "convert", str(maps_dir / "hospital_2021.png"), str(tmp_path / "h.json")]) == 0
    text = capsys.readouterr().out
    assert "round trip: IoU 1.0000" in text or "round trip: IoU 0.9" in text
    assert main(["map", "convert", str(tmp_path / "h.json"), str(tmp_path / "h.png"), "--resolution", "0.05"]) == 0
    assert "round trip: IoU" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["map", "info", "nothing.png"], "nothing.png: no such file"),
        (["map", "info", "map.txt"], "unknown map format"),
        (["map", "convert", "nothing.json", "out.png"], "nothing.json"),
    ],
)
def test_map_cli_errors_are_one_line_exit_2(argv: list[str], message: str, capsys, tmp_path: Path, monkeypatch) -> None:  # noqa: ANN001
    monkeypatch.chdir(tmp_path)
    (tmp_path / "map.txt").write_text("x")
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err


@pytest.mark.parametrize("argv", [["map", "--help"], ["map", "info", "--help"], ["map", "convert", "--help"]])
def test_map_help(argv: list[str], capsys) -> None:  # noqa: ANN001
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 0
    assert "usage:" in capsys.readouterr().out
