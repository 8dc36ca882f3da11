"""`pico-studio tune --plugin`: a plugin's parameters are in the search space like built-ins."""

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


def test_tune_searches_a_plugin_parameter(tmp_path: Path, capsys) -> None:
    """... with two worker processes (spawned: each loads the plugin before its trials)."""
    scenarios = tmp_path / "tiny.yaml"
    scenarios.write_text(f"name: tiny\nscenarios:\n  - name: a\n    map: {MAP}\n    poses: 1\n    frames: 5\n    seed: 1\n",
                         encoding="utf-8")
    cfg = tmp_path / "use.yaml"
    cfg.write_text("perception:\n  scan:\n    segmenter: chord_split\n", encoding="utf-8")
    out = tmp_path / "out"
    assert main(["tune", "--scenarios", str(scenarios), "--config", str(cfg), "--plugin", str(EXAMPLE),
                 "--params", "perception.plugins.chord_split.*", "--trials", "3", "--workers", "2", "--out", str(out), "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["complete"] == 3
    assert list(result["best"]["params"]) == ["perception.plugins.chord_split.split"]
    assert 0.005 <= result["best"]["params"]["perception.plugins.chord_split.split"] <= 0.5
