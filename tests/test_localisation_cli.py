"""Localisation figures in `pico-studio run --localise` and `pico-studio eval`."""

from __future__ import annotations

import json
import math

import pytest

from pico_studio.cli import main


def _json(capsys: pytest.CaptureFixture[str], *args: str) -> dict:
    assert main(list(args)) == 0
    return json.loads(capsys.readouterr().out)


def test_run_reports_pose_and_heading_error(capsys):
    r = _json(capsys, "run", "--map", "examples/maps/restaurant_2024.json",
              "--sim-config", "examples/maps/restaurant_2024_sim.json", "--seconds", "3",
              "--behaviour", "drive:0.2,0,0.3", "--localise", "--json")
    loc = r["localisation"]
    assert loc["frames"] == 60
    assert loc["pose_error_m"]["median"] < 0.02 and loc["pose_error_m"]["max"] < 0.05
    assert loc["heading_error_rad"]["max"] < math.radians(2)
    assert loc["lost_fraction"] < 0.1  # only the first frames, until the fix is confirmed


def test_run_text_has_a_localisation_line(capsys):
    assert main(["run", "--map", "examples/maps/hospital_2019.json", "--seconds", "1", "--localise"]) == 0
    assert "localisation error median" in capsys.readouterr().out


def test_eval_reports_localisation(capsys):
    r = _json(capsys, "eval", "--map", "examples/maps/hospital_2019.json", "--poses", "2",
              "--frames", "6", "--json")
    loc = r["localisation"]
    assert loc["frames"] == 12
    assert loc["pose_error_m"]["max"] < 0.05 and loc["heading_error_rad"]["max"] < math.radians(2)
