"""JSON maps: every real file loads, counts match, extra keys survive, broken maps fail clearly."""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest

from pico_studio.cli import main
from pico_studio.errors import MapError
from pico_studio.json_map import load_json_map, map_from_dict, save_json_map
from pico_studio.json_map.json_io import map_to_dict

REAL_JSON_MAPS = ["emc_example.json", "hospital_2019.json", "hospital_2019_with_nodes.json", "restaurant_2024.json"]


@pytest.mark.parametrize("name", REAL_JSON_MAPS)
def test_real_maps_load_and_write_back_identically(maps_dir, tmp_path, name: str) -> None:
    m = load_json_map(maps_dir / name)
    assert m.wall_segments.shape == (len(m.walls), 4)
    out = save_json_map(m, tmp_path / name)
    original = json.loads((maps_dir / name).read_text())
    assert json.loads(out.read_text()) == original


def test_hospital_2019_counts_and_extent(maps_dir, capsys) -> None:
    assert main(["map", "info", str(maps_dir / "hospital_2019.json"), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["counts"]["points"] == 56
    assert info["counts"]["walls"] == 40
    assert info["counts"]["cabinets"] == 4
    assert info["extent_m"] == [6.7, 6.4]


def test_restaurant_has_tables_door_and_start_area(maps_dir) -> None:
    m = load_json_map(maps_dir / "restaurant_2024.json")
    assert m.object_key == "tables" and len(m.objects) == 5
    assert len(m.doors) == 1 and len(m.start_area) == 1
    assert m.start_center is not None


def test_unordered_cabinet_segments_are_chained(maps_dir) -> None:
    # the official example lists cabinet 1's segments out of order: still one closed loop
    m = load_json_map(maps_dir / "emc_example.json")
    verts = m.object_polygons[1]
    assert verts.shape == (4, 2)
    np.testing.assert_allclose(m.object_fronts[1], [0.2, 2.8, 0.2, 2.4])
    # consecutive vertices are joined by a segment of the polygon
    edges = {frozenset(map(int, p)) for p in m.objects[1]}
    order = [int(np.flatnonzero((m.points == v).all(1))[0]) for v in verts]
    assert all(frozenset((order[i], order[(i + 1) % 4])) in edges for i in range(4))


def test_extra_keys_are_kept(maps_dir) -> None:
    m = load_json_map(maps_dir / "hospital_2019_with_nodes.json")
    assert set(m.extra) == {"start", "nodes", "nodelinks"}
    assert any("duplicates points[20]" in w for w in m.warnings)
    assert any("unused points" in w for w in m.warnings)
    assert list(map_to_dict(m)) == m.key_order


def _base() -> dict:
    return {
        "points": [{"x": 0, "y": 0}, {"x": 1, "y": 0}, {"x": 1, "y": 1}, {"x": 0, "y": 1}],
        "walls": [[0, 1], [1, 2], [2, 3], [3, 0]],
        "cabinets": [[[0, 1], [1, 2], [2, 3], [3, 0]]],
    }


def _broken(edit) -> dict:
    d = copy.deepcopy(_base())
    edit(d)
    return d


BROKEN = [
    (lambda d: d["walls"].append([0, 9]), "walls[4][1]: point index 9 out of range"),
    (lambda d: d["points"][1].pop("x"), "points[1].x: missing coordinate"),
    (lambda d: d["points"][2].update(y="1.0"), "points[2].y: must be a number"),
    (lambda d: d["points"][2].update(y=float("nan")), "points[2].y: must be finite"),
    (lambda d: d["walls"].append([1, 1]), "walls[4]: zero-length segment"),
    (lambda d: d.update(walls=[]), "walls: is empty"),
    (lambda d: d.pop("walls"), "walls: missing key"),
    (lambda d: d.pop("points"), "points: missing key"),
    (lambda d: d["cabinets"][0].pop(), "cabinets[0]: polygon is not closed"),
    (lambda d: d["cabinets"][0].__setitem__(3, [3, 1]), "cabinets[0]: polygon is not closed"),
    (lambda d: d["walls"].__setitem__(0, [0]), "walls[0]: must be a pair"),
    (lambda d: d.update(tables=[]), "tables: has both 'cabinets' and 'tables'"),
]


@pytest.mark.parametrize(("edit", "expected"), BROKEN)
def test_broken_maps_raise_clear_errors(edit, expected: str) -> None:
    with pytest.raises(MapError) as e:
        map_from_dict(_broken(edit), file="broken.json")
    assert str(e.value).startswith("broken.json: ")
    assert expected in str(e.value)


def test_warnings_listed_not_fixed() -> None:
    d = _base()
    d["points"].append({"x": 0, "y": 0})  # duplicate and unused
    d["walls"].append([1, 0])  # duplicate wall, reversed
    m = map_from_dict(d, file="w.json")
    assert len(m.points) == 5 and len(m.walls) == 5
    assert any("points[4] duplicates points[0]" in w for w in m.warnings)
    assert any("unused points: points[4]" in w for w in m.warnings)
    assert any("walls[4] duplicates walls[0]" in w for w in m.warnings)


def test_unreadable_and_non_json_files(tmp_path) -> None:
    with pytest.raises(MapError, match="cannot read"):
        load_json_map(tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text('{"points": [}')
    with pytest.raises(MapError, match=r"bad.json: not valid JSON at line 1"):
        load_json_map(bad)
