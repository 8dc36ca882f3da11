"""`pico-studio tune --plugin`: a plugin's parameters are in the search space like built-ins."""

from __future__ import annotations

import json
from pathlib import Path

import optuna
import pytest
from plugin_helpers import EXAMPLE, unload_all, write_plugin

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


PICKY = """
    from dataclasses import dataclass
    from pico_studio.plugins import param, segmenter

    @dataclass(frozen=True)
    class Picky:
        a: float = param(0.1, lo=0.0, hi=1.0, step=0.01, help="one half")
        b: float = param(0.1, lo=0.0, hi=1.0, step=0.01, help="the other half")

        def check(self):
            return [("a", "a + b must stay below 1")] if self.a + self.b >= 1.0 else []

    @segmenter("picky_split", Picky)
    def picky_split(points, params):
        return [(0, len(points) - 1)]
"""


def test_failed_trials_are_recorded_and_the_study_goes_on(tmp_path: Path, capsys) -> None:
    """A section's own cross-field check() refuses about half the trials: each is a failed
    trial with the field named, and the study still runs every trial it was asked for."""
    scenarios = tmp_path / "tiny.yaml"
    scenarios.write_text(f"name: tiny\nscenarios:\n  - name: a\n    map: {MAP}\n    poses: 1\n    frames: 3\n    seed: 1\n",
                         encoding="utf-8")
    plugin = write_plugin(tmp_path, "picky.py", PICKY)
    out = tmp_path / "out"
    assert main(["tune", "--scenarios", str(scenarios), "--plugin", str(plugin), "--seed", "3",
                 "--params", "perception.plugins.picky_split.*", "--trials", "8", "--out", str(out), "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["trials"] == 8
    from optuna.storages.journal import JournalFileBackend, JournalStorage

    from pico_studio.tuning.study import JOURNAL

    study = optuna.load_study(study_name=result["study"], storage=JournalStorage(JournalFileBackend(str(out / JOURNAL))))
    failed = [t for t in study.trials if t.state == optuna.trial.TrialState.FAIL]
    assert failed and len(failed) < 8
    assert all("perception.plugins.picky_split.a" in t.user_attrs["error"] for t in failed)
