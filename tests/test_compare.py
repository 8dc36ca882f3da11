"""`pico-studio compare A.yaml B.yaml` and the world-model diff it reports."""

from __future__ import annotations

import json

import numpy as np
import pytest

from pico_studio.cli import main
from pico_studio.evaluation.diff import (
    diff_arrays,
    diff_corners,
    diff_doors,
    diff_walls,
    wall_shares,
)

MAP = "pico_studio/data/maps/hospital_2019.json"


def _compare(capsys, *args: str) -> tuple[int, dict]:  # noqa: ANN001
    code = main(["compare", *args, "--json", "--workers", "1"])
    out = capsys.readouterr().out
    return code, json.loads(out) if out.strip() else {}


@pytest.fixture
def coarse(tmp_path):  # noqa: ANN001, ANN201
    f = tmp_path / "coarse.yaml"
    f.write_text("perception:\n  scan:\n    min_length: 1.5\n", encoding="utf-8")
    return str(f)


def test_a_vs_a_has_every_delta_zero_and_exits_0(capsys, maps_dir, tmp_path) -> None:
    a = tmp_path / "a.yaml"
    a.write_text("perception:\n  merge:\n    connect_radius: 0.3\n", encoding="utf-8")
    code, out = _compare(capsys, str(a), str(a), "--map", str(maps_dir / "hospital_2019.json"), "--seconds", "2",
                         "--fail-on", "perception_score,walls.recall")
    assert code == 0 and out["regressed"] == []
    assert out["frames"] == 40
    assert out["metrics"]["perception_score"]["a"] > 0.5
    assert all(m["delta"] == 0 for m in out["metrics"].values())
    assert set(out["diff"]) == {"walls_added", "walls_lost", "doors_added", "doors_lost", "corners_added",
                                "corners_lost"}
    assert not any(out["diff"].values()) and out["frames_differing"] == 0


def test_b_worse_on_a_fail_on_metric_exits_1_and_names_it(capsys, maps_dir, coarse) -> None:
    code, out = _compare(capsys, "defaults", coarse, "--map", str(maps_dir / "hospital_2019.json"), "--seconds", "2",
                         "--fail-on", "walls.recall,walls.precision", "--tolerance", "0.02")
    assert code == 1
    assert out["regressed"] == ["walls.recall"]  # fewer, longer walls: precision does not drop
    m = out["metrics"]["walls.recall"]
    assert m["delta"] == pytest.approx(m["b"] - m["a"]) and m["delta"] < -0.02
    assert out["diff"]["walls_lost"] > 0 and out["frames_differing"] > 0
    # within a tolerance wide enough, the same change passes
    code, out = _compare(capsys, "defaults", coarse, "--map", str(maps_dir / "hospital_2019.json"), "--seconds", "2",
                         "--fail-on", "walls.recall", "--tolerance", "1")
    assert code == 0 and out["regressed"] == []


def test_a_recording_compares_what_it_can_and_refuses_scores_it_cannot(capsys, recordings_dir, coarse) -> None:
    bag = f"bag:{recordings_dir / 'pico_real_2019-05-07.bag'}"
    code, out = _compare(capsys, "defaults", coarse, "--source", bag, "--seconds", "3")
    assert code == 0 and out["frames"] > 20
    assert out["metrics"]["count.walls"]["b"] < out["metrics"]["count.walls"]["a"]
    assert "walls.recall" not in out["metrics"]
    assert any("no simulator truth" in n for n in out["notes"])
    code = main(["compare", "defaults", coarse, "--source", bag, "--seconds", "3", "--fail-on", "walls.recall",
                 "--workers", "1"])
    assert code == 2
    assert "--fail-on" in capsys.readouterr().err


def test_bad_input_names_the_field(capsys, maps_dir) -> None:
    assert main(["compare", "defaults", "defaults"]) == 2
    assert "--map" in capsys.readouterr().err
    assert main(["compare", "defaults", "defaults", "--map", str(maps_dir / "hospital_2019.json"), "--seconds", "1",
                 "--fail-on", "door.recall", "--workers", "1"]) == 2
    assert "did you mean 'doors.recall'" in capsys.readouterr().err
    assert main(["compare", "defaults", "missing.yaml", "--map", MAP]) == 2
    assert "missing.yaml" in capsys.readouterr().err


# ----- the diff ------------------------------------------------------------------------------------


def test_diff_of_a_world_with_itself_is_empty_and_changes_are_found_within_tolerance() -> None:
    walls = np.array([[0, 0, 4, 0], [4, 0, 4, 3], [0, 3, 1, 3]], float)
    corners = np.array([[4, 0], [0, 0]], float)
    doors = np.array([[1, 3, 2, 3]], float)
    a = {"walls": walls, "corners": corners, "doors": doors}
    assert diff_arrays(a, a).empty
    # B: the same walls moved 3 cm (within tolerance), one wall gone, one new; a corner moved 5 cm,
    # one new corner; the door turned across its wall (another door)
    b = {"walls": np.vstack([walls[:2] + [0, 0.03, 0, 0.03], [[6, 0, 6, 2]]]),
         "corners": np.vstack([corners[:1] + 0.05, [[6, 2]]]),
         "doors": np.array([[1.5, 2.5, 1.5, 3.5]], float)}
    d = diff_arrays(a, b)
    np.testing.assert_array_equal(d.walls_added, [[6, 0, 6, 2]])
    np.testing.assert_array_equal(d.walls_lost, walls[2:])
    np.testing.assert_array_equal(d.corners_added, [[6, 2]])
    np.testing.assert_array_equal(d.corners_lost, [[0, 0]])
    assert len(d.doors_added) == len(d.doors_lost) == 1
    assert d.counts() == {"walls_added": 1, "walls_lost": 1, "corners_added": 1, "corners_lost": 1,
                          "doors_added": 1, "doors_lost": 1}


def test_a_wall_half_covered_is_the_same_wall_and_a_longer_one_too() -> None:
    a = np.array([[0, 0, 2, 0]], float)
    b = np.array([[0, 0, 3.5, 0]], float)  # B extends A's wall by 1.5 m: 57 % of it is A's
    assert wall_shares(b, a)[0] == pytest.approx((2 + 0.1) / 3.5, abs=0.01)  # + wall_distance past the end
    added, lost = diff_walls(a, b)
    assert len(added) == 0 and len(lost) == 0
    added, _ = diff_walls(a, np.array([[0, 0, 5, 0]], float))  # 40 %: another wall
    assert len(added) == 1
    assert diff_corners(np.zeros((0, 2)), np.zeros((0, 2)))[0].shape == (0, 2)
    assert diff_doors(np.zeros((0, 4)), np.array([[0, 0, 1, 0]], float))[0].shape == (1, 4)


def test_a_scenario_set_compares_every_method_and_a_vs_a_is_zero(capsys) -> None:
    smoke = "pico_studio/data/scenarios/smoke.yaml"
    code, out = _compare(capsys, "defaults", "defaults", "--scenarios", smoke, "--fail-on", "perception_score")
    assert code == 0 and out["regressed"] == [] and out["frames"] > 0
    assert "localisation.pose_error_m.median" in out["metrics"]  # the localised scenarios
    assert all(m["delta"] == 0 for m in out["metrics"].values())


def test_a_and_b_judged_in_worker_processes_give_the_same_report(capsys, maps_dir, coarse) -> None:
    args = ["compare", "defaults", coarse, "--map", str(maps_dir / "hospital_2019.json"), "--seconds", "2",
            "--localise", "--json", "--fail-on", "walls.recall", "--tolerance", "0.02"]
    reports = []
    for workers in ("1", "4"):  # here one after the other; A and B each in two processes at once
        code = main([*args, "--workers", workers])
        reports.append((code, json.loads(capsys.readouterr().out)))
    (code_1, here), (code_4, workers_4) = reports
    assert code_1 == code_4 == 1
    assert "localisation.pose_error_m.median" in here["metrics"]
    here.pop("ms_per_scan")
    workers_4.pop("ms_per_scan")
    assert workers_4 == here
