"""Scoring against known answers, and the done-when bar of `pico-studio eval` on hospital_2019."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from pico_studio.cli import main
from pico_studio.config import load_config
from pico_studio.evaluation.frame_score import FrameScore, Tolerances, score_arrays
from pico_studio.evaluation.run_score import RunScore
from pico_studio.evaluation.runner import evaluate_map

SQ = np.array([[0, 0, 4, 0], [4, 0, 4, 4], [4, 4, 0, 4], [0, 4, 0, 0]], dtype=float)


def _score(walls, doors=None, corners=None, convex=None):
    doors = np.zeros((0, 4)) if doors is None else doors
    corners = np.zeros((0, 2)) if corners is None else corners
    convex = np.zeros(0, bool) if convex is None else convex
    return score_arrays(
        walls=walls, endpoint_property=np.full((len(walls), 2), 3), corners=corners,
        corner_convex=convex, doors=doors, solid=SQ, visible_walls=SQ[:3],
        true_vertices=SQ[:, :2], visible_corners=SQ[1:3, :2], visible_convex=np.array([False, False]),
        openings=np.array([[1.0, 4.0, 2.0, 4.0]]), visible_doors=np.array([[1.0, 4.0, 2.0, 4.0]]),
    )


def test_wall_scores_are_length_weighted():
    perfect = _score(SQ[:3])
    assert perfect.wall_len_ok == pytest.approx(perfect.wall_len)
    assert perfect.truth_len_ok == pytest.approx(12.0, abs=0.05)
    # half of the walls found, plus a phantom wall of 2 m in the middle of the room
    half = _score(np.array([[0, 0, 4, 0], [2, 1, 2, 3]], dtype=float))
    s = RunScore([half]).summary()
    assert s["wall_precision"] == pytest.approx(4 / 6, abs=0.02)
    assert s["wall_recall"] == pytest.approx(4 / 12, abs=0.02)
    # a wall at the right place but 45 degrees off is not that wall
    skew = _score(np.array([[3.8, 0.2, 4.2, -0.2]]))
    assert skew.wall_len_ok == 0


def test_corner_and_door_matching():
    s = _score(SQ[:3], doors=np.array([[1.05, 4.0, 1.95, 4.02], [3.0, 1.0, 3.0, 2.0]]),
               corners=np.array([[4.02, 0.01], [3.98, 4.0], [2.0, 2.0]]), convex=np.array([False, True, False]))
    r = RunScore([s]).summary()
    assert r["door_precision"] == 0.5 and r["door_recall"] == 1.0
    assert r["corner_precision"] == pytest.approx(2 / 3)
    assert r["corner_recall"] == 1.0
    assert r["convexity_accuracy"] == 0.5


def test_empty_run_is_not_a_division_by_zero():
    s = RunScore([FrameScore()]).summary()
    assert s["wall_precision"] == 1.0 and s["door_recall"] == 1.0


def test_hospital_bar_with_the_default_config(maps_dir):
    """The done-when bar, exactly as `pico-studio eval --map hospital_2019.json` runs it."""
    r = evaluate_map(str(maps_dir / "hospital_2019.json"))
    assert r["poses"] == 50 and r["doors_visible"] >= 40
    assert r["wall_precision"] >= 0.95 and r["wall_recall"] >= 0.95
    assert r["door_precision"] >= 0.9 and r["door_recall"] >= 0.9
    assert r["convexity_accuracy"] >= 0.95
    assert r["endpoint_error_m"] < 0.05


def test_a_broken_perceptor_fails_the_bar(maps_dir, tmp_path):
    cfg = tmp_path / "bad.yaml"
    cfg.write_text("perception:\n  identify:\n    door_min_width: 2.0\n    door_max_width: 3.0\n    wide_door_max_width: 3.0\n"
                   "  scan:\n    min_length: 2.0\n")
    r = evaluate_map(str(maps_dir / "hospital_2019.json"), load_config(cfg), poses=5, seed=0)
    assert r["door_recall"] < 0.5 and r["wall_recall"] < 0.9


def test_eval_cli_json(maps_dir, capsys):
    assert main(["eval", "--map", str(maps_dir / "hospital_2019.json"), "--poses", "2", "--frames", "5", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("wall_precision", "wall_recall", "endpoint_error_m", "corner_precision", "corner_recall",
                "convexity_accuracy", "door_precision", "door_recall", "ms_per_scan"):
        assert isinstance(out[key], float)


def test_eval_cli_scores_a_map_as_its_heightmap_image(maps_dir, capsys):
    """`eval --map FILE --heightmap`: the map drawn into an image and read back first (the
    official simulator's form), localised on its outlines; the summary says so."""
    assert main(["eval", "--map", str(maps_dir / "emc_example.json"), "--heightmap", "--poses", "3", "--seed", "1",
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["heightmap"] is True and out["wall_precision"] > 0.95
    assert out["localisation"]["lost_fraction"] <= 0.15 and out["localisation"]["pose_error_m"]["max"] < 0.01
    assert main(["eval", "--map", str(maps_dir / "emc_example.json"), "--heightmap", "--poses", "1",
                 "--frames", "2"]) == 0
    assert "emc_example.json as a heightmap: 1 poses" in capsys.readouterr().out


def test_eval_cli_bad_input(maps_dir, capsys, tmp_path):
    assert main(["eval", "--map", str(maps_dir / "hospital_2019.json"), "--poses", "0"]) == 2
    assert "--poses" in capsys.readouterr().err
    assert main(["eval", "--map", str(tmp_path / "missing.json")]) == 2
    assert "missing.json" in capsys.readouterr().err
    smoke = Path(__file__).resolve().parents[1] / "pico_studio" / "data" / "scenarios" / "smoke.yaml"
    assert main(["eval", "--scenarios", str(smoke), "--heightmap"]) == 2
    assert "--heightmap" in capsys.readouterr().err
    assert Tolerances().wall_distance > 0


def test_map_confirmed_doors_are_scored_on_their_own():
    """A localised world model's combined map: only the doors the map confirmed count in
    map_door_*; the perceptor's own doors (one true, one false) are scored as before."""
    from sim_helpers import box_map

    from pico_studio.core.localisation.combined import CombinedMap
    from pico_studio.core.world_model import WorldModel
    from pico_studio.evaluation.frame_score import score_frame
    from pico_studio.sim import Simulator

    # a 10 x 10 m room split at x = 5 with a 1 m gap (y 4..5), the robot facing it
    gap = box_map(more_points=[{"x": 5, "y": 0}, {"x": 5, "y": 4}, {"x": 5, "y": 5}, {"x": 5, "y": 10}],
                  more_walls=[[4, 5], [6, 7]])
    sim = Simulator(gap, initial_pose=(3.0, 4.5, 0.0))
    assert len(sim.truth.visible_doors()) == 1
    doors = np.array([[5.0, 4.0, 5.0, 5.0], [2.0, 2.0, 3.0, 2.0]])
    wm = WorldModel(pose=sim.truth.pose, doors=doors)
    assert "map_door_precision" not in RunScore([score_frame(wm, sim.truth)]).summary()
    wm.combined = CombinedMap(walls=np.zeros((0, 4)), wall_matched=np.zeros(0, dtype=bool),
                              map_wall_seen=np.zeros(0, dtype=bool), doors=doors,
                              door_confirmed=np.array([True, False]))
    s = RunScore([score_frame(wm, sim.truth)]).summary()
    assert s["door_precision"] == 0.5 and s["door_recall"] == 1.0
    assert s["map_door_precision"] == 1.0 and s["map_door_recall"] == 1.0 and s["map_doors_detected"] == 1
