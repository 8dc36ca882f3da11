"""examples/door_figures.py: the README's door tables from `eval --scenarios --json` output."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "examples" / "door_figures.py"


def _module():
    spec = importlib.util.spec_from_file_location("door_figures", SCRIPT)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _world(p: float, r: float, det: int, vis: int) -> dict:
    return {"summary": {"door_precision": p, "door_recall": r, "doors_detected": det, "doors_visible": vis,
                        "map_door_recall": 1.0, "map_door_precision": 1.0, "convexity_accuracy": 1.0,
                        "endpoint_error_m": 0.012, "wall_precision": 0.99}}


@pytest.fixture
def scores(tmp_path: Path) -> Path:
    data = {"scenarios": {"cafe1": _world(1.0, 0.5, 10, 20), "cafe2": _world(0.5, 1.0, 10, 20),
                          "h2021_s0": _world(0.9, 0.9, 10, 10),
                          "run": {"summary": {"perceptor": _world(1.0, 1.0, 5, 5)["summary"], "localisation": {}}}}}
    path = tmp_path / "scores.json"
    path.write_text(json.dumps(data))
    return path


def test_families_show_the_mean_and_the_worst_world(scores: Path, capsys: pytest.CaptureFixture[str]):
    _module().main([str(scores)])
    out = capsys.readouterr().out
    assert "| cafe | 2 | 0.750 (0.500) | 0.750 (0.500) | 1.000 |" in out
    assert "| h2021 | 1 | 0.900 | 0.900 |" in out
    assert "| run | 1 | 1.000 | 1.000 |" in out  # a whole run's nested perceptor scores


def test_pooled_over_doors_not_worlds(scores: Path, capsys: pytest.CaptureFixture[str]):
    _module().main([str(scores)])
    # precision: (10 + 5 + 9 + 5) / 35 doors found; recall: (10 + 20 + 9 + 5) / 55 doors seen
    assert f"own door precision {29 / 35:.3f}, recall {44 / 55:.3f}" in capsys.readouterr().out


def test_one_row_per_world(scores: Path, capsys: pytest.CaptureFixture[str]):
    _module().main([str(scores), "--worlds"])
    out = capsys.readouterr().out
    assert "| cafe2 | 0.500 | 1.000 | 1.000 | 1.000 | 1.000 | 1.2 | 0.990 |" in out
    assert sum(line.startswith("| ") for line in out.splitlines()) == 5  # the heading and four worlds
