"""`pico-studio eval --plugin`: the example segmenter, selected from YAML, scored on hospital_2019
against the simulator's truth like the built-in split-and-merge — and its own slider counts."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from plugin_helpers import EXAMPLE, unload_all

from pico_studio.cli import main

MAP = Path(__file__).resolve().parents[1] / "pico_studio" / "data" / "maps" / "hospital_2019.json"


@pytest.fixture(autouse=True)
def _clean():
    unload_all()
    yield
    unload_all()


def _eval(capsys, tmp_path: Path, yaml_text: str | None, *extra: str) -> dict:
    args = ["eval", "--map", str(MAP), "--poses", "4", "--frames", "10", "--seed", "3", "--json", *extra]
    if yaml_text is not None:
        cfg = tmp_path / "cfg.yaml"
        cfg.write_text(yaml_text, encoding="utf-8")
        args += ["--config", str(cfg)]
    assert main(args) == 0
    return json.loads(capsys.readouterr().out)


def test_the_example_segmenter_scores_like_split_and_merge(capsys, tmp_path: Path) -> None:
    builtin = _eval(capsys, tmp_path, None)
    mine = _eval(capsys, tmp_path, "perception:\n  scan:\n    segmenter: chord_split\n", "--plugin", str(EXAMPLE))
    unload_all()
    coarse = _eval(capsys, tmp_path, "perception:\n  scan:\n    segmenter: chord_split\n"
                   "  plugins:\n    chord_split:\n      split: 0.5\n", "--plugin", str(EXAMPLE))
    assert builtin["wall_recall"] > 0.8
    assert mine["wall_precision"] >= builtin["wall_precision"] - 0.05
    assert mine["wall_recall"] >= builtin["wall_recall"] - 0.05
    assert mine["endpoint_error_m"] <= 1.5 * builtin["endpoint_error_m"] + 0.005
    # the plugin's own parameter reaches it through the config: a coarse split scores worse
    assert coarse["wall_recall"] < mine["wall_recall"] or coarse["endpoint_error_m"] > 2 * mine["endpoint_error_m"]


def test_selecting_a_plugin_stage_without_loading_it_is_a_config_error(capsys, tmp_path: Path) -> None:
    cfg = tmp_path / "cfg.yaml"
    cfg.write_text("perception:\n  scan:\n    segmenter: chord_split\n", encoding="utf-8")
    assert main(["eval", "--map", str(MAP), "--poses", "1", "--config", str(cfg)]) == 2
    err = capsys.readouterr().err
    assert "perception.scan.segmenter" in err and "chord_split" in err


def test_eval_workers_load_the_same_plugins(capsys, tmp_path: Path) -> None:
    """Spawned worker processes get the config by value and load the plugins first."""
    scenarios = tmp_path / "two.yaml"
    scenarios.write_text(
        f"name: two\nscenarios:\n"
        f"  - name: a\n    map: {MAP}\n    poses: 1\n    frames: 5\n    seed: 1\n"
        f"  - name: b\n    map: {MAP}\n    poses: 1\n    frames: 5\n    seed: 2\n", encoding="utf-8")
    cfg = tmp_path / "cfg.yaml"
    cfg.write_text("perception:\n  scan:\n    segmenter: chord_split\n  plugins:\n    chord_split:\n      split: 0.5\n",
                   encoding="utf-8")
    args = ["eval", "--scenarios", str(scenarios), "--config", str(cfg), "--plugin", str(EXAMPLE), "--json"]
    assert main([*args, "--workers", "2"]) == 0
    parallel = json.loads(capsys.readouterr().out)
    assert main(args) == 0
    serial = json.loads(capsys.readouterr().out)
    def scores(r: dict) -> dict:
        return {k: v for k, v in r["metrics"].items() if "ms_per" not in k}

    assert scores(parallel) == scores(serial)  # the workers ran the plugin, with its value
