"""`pico-studio map generate KIND:SEED OUT.json`: a generated world written as the challenge's
JSON map and the official simulator's config beside it (its start, its walking people), so the
page and `run` can open the worlds the scenario sets score on."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pico_studio.cli import main
from pico_studio.evaluation.worlds import make_world
from pico_studio.json_map import load_map
from pico_studio.sim.sim_config import load_sim_config


def test_a_cafe_is_written_with_its_people_and_reads_back_the_same(tmp_path: Path, capsys) -> None:
    out = tmp_path / "cafe2.json"
    assert main(["map", "generate", "cafe:2", str(out), "--png", str(tmp_path / "cafe2.png")]) == 0
    said = capsys.readouterr().out
    assert "2 moving objects" in said and f"--sim-config {tmp_path / 'cafe2_sim.json'}" in said
    m, w = load_map(out), make_world("cafe:2")
    assert len(m.objects) == len(w.map.objects) and m.object_key == "tables"
    assert json.dumps(m.openings().round(6).tolist()) == json.dumps(w.map.openings().round(6).tolist())
    sc = load_sim_config(tmp_path / "cafe2_sim.json")
    assert sc.initial_pose == w.start and sc.objects == w.sim_config.objects
    assert (tmp_path / "cafe2.png").stat().st_size > 1000


def test_a_thin_walled_world_gets_its_start_pose(tmp_path: Path) -> None:
    out = tmp_path / "rooms5.json"
    assert main(["map", "generate", "rooms:5", str(out)]) == 0
    sc = load_sim_config(tmp_path / "rooms5_sim.json")
    assert sc.initial_pose == pytest.approx(make_world("rooms:5").start) and sc.objects == ()


@pytest.mark.parametrize("world, output, words", [
    ("maze:3", "m.json", "world: unknown world 'maze'"),
    ("ward:x", "m.json", "integer seed"),
    ("ward:3", "m.png", "name a .json file"),
])
def test_bad_requests_are_one_line(tmp_path: Path, capsys, world: str, output: str, words: str) -> None:
    assert main(["map", "generate", world, str(tmp_path / output)]) == 2
    err = capsys.readouterr().err
    assert words in err and len(err.strip().splitlines()) == 1
    assert not list(tmp_path.iterdir())
