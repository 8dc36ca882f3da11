"""`pico-studio run`: the JSON report and bad input (one clear line, exit 2)."""

from __future__ import annotations

import json
import math

import pytest

from pico_studio.cli import main


def run(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    code = main(["run", *args])
    out, err = capsys.readouterr()
    return code, out, err


def test_run_json_report(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(
        capsys, "--map", "examples/maps/restaurant_2024.json", "--sim-config", "examples/maps/restaurant_2024_sim.json",
        "--seconds", "4", "--behaviour", "drive:0.2,0,0.1", "--seed", "5", "--json",
    )
    assert code == 0
    r = json.loads(out)
    for key in ("sim_seconds", "wall_seconds", "steps", "collisions", "distance_m", "true_pose", "odom_pose"):
        assert key in r
    assert r["sim_seconds"] == pytest.approx(4.0) and r["steps"] == 80
    # the first command goes out after the first tick's readings: 3.95 s of driving
    assert r["distance_m"] == pytest.approx(0.79)
    assert r["odom_pose"][2] == pytest.approx(0.395)  # exact odometry (uncertain_odom false), started at zero
    x, y, a = r["true_pose"]
    assert a == pytest.approx(math.remainder(3.14 + 0.395, 2 * math.pi))
    code2, out2, _ = run(
        capsys, "--map", "examples/maps/restaurant_2024.json", "--sim-config", "examples/maps/restaurant_2024_sim.json",
        "--seconds", "4", "--behaviour", "drive:0.2,0,0.1", "--seed", "5", "--json",
    )
    r2 = json.loads(out2)
    assert r2["true_pose"] == r["true_pose"] and r2["odom_pose"] == r["odom_pose"]
    assert r["perceptor"]["frames"] > 0  # the perceptor ran and was scored


def test_run_without_the_perceptor_drives_the_same(capsys: pytest.CaptureFixture[str]) -> None:
    common = ["--map", "examples/maps/hospital_2019.json", "--seconds", "3", "--behaviour", "drive:0.2,0,0.2", "--json"]
    code, out, _ = run(capsys, *common)
    code_bare, out_bare, _ = run(capsys, *common, "--no-perceptor")
    assert code == code_bare == 0
    with_p, bare = json.loads(out), json.loads(out_bare)
    assert bare["perceptor"] is None and with_p["perceptor"]["frames"] > 0
    assert bare["true_pose"] == with_p["true_pose"] and bare["steps"] == with_p["steps"]
    code, _, err = run(capsys, *common, "--no-perceptor", "--localise")
    assert code == 2 and "--localise" in err


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--behaviour", "drive:nan,0,0"], "--behaviour"),
        (["--behaviour", "fly"], "unknown behaviour"),
        (["--seconds", "nan"], "--seconds"),
    ],
)
def test_run_bad_arguments(capsys: pytest.CaptureFixture[str], args: list[str], needle: str) -> None:
    code, _, err = run(capsys, "--map", "examples/maps/emc_example.json", *args)
    last = err.strip().splitlines()[-1]
    assert code == 2 and needle in last and "Traceback" not in err
    # one line, or argparse's refusal of a number out of range (cli/limits.py): usage + one line
    assert err.count("\n") == 1 or last.startswith("pico-studio run: error: argument")


def test_run_bad_files(capsys: pytest.CaptureFixture[str], tmp_path) -> None:
    bad = tmp_path / "sim.json"
    bad.write_text('{"uncertain_odom": 1}')
    code, _, err = run(capsys, "--map", "examples/maps/emc_example.json", "--sim-config", str(bad))
    assert code == 2 and "uncertain_odom" in err and str(bad) in err
    inside = tmp_path / "inside.json"
    inside.write_text('{"initial_pose": [0.0, 0.0, 0.0]}')
    code, _, err = run(capsys, "--map", "examples/maps/emc_example.json", "--sim-config", str(inside))
    assert code == 2 and "initial_pose" in err and "inside a wall" in err
    yaml = tmp_path / "c.yaml"
    yaml.write_text("sim:\n  laser:\n    profile: velodyne\n")
    code, _, err = run(capsys, "--map", "examples/maps/emc_example.json", "--config", str(yaml))
    assert code == 2 and "sim.laser.profile" in err


def test_run_map_without_a_free_place(capsys: pytest.CaptureFixture[str], tmp_path) -> None:
    tiny = tmp_path / "tiny.json"
    tiny.write_text(json.dumps({
        "points": [{"x": 0, "y": 0}, {"x": 0.2, "y": 0}, {"x": 0.2, "y": 0.2}, {"x": 0, "y": 0.2}],
        "walls": [[0, 1], [1, 2], [2, 3], [3, 0]],
    }))
    code, _, err = run(capsys, "--map", str(tiny), "--seconds", "1")
    assert code == 2 and "no free place to start" in err and "start_area" in err


def test_run_with_moving_objects_and_uncertain_odometry(capsys: pytest.CaptureFixture[str], tmp_path) -> None:
    cfg = tmp_path / "sim.json"
    cfg.write_text(json.dumps({
        "initial_pose": [0.5, 0.6, 1.5708], "uncertain_odom": True, "show_full_map": True,
        "objects": [{"length": 0.3, "width": 0.3, "init_pose": [0.8, 2.6, 0], "final_pose": [0.8, 1.8, 0],
                     "velocity": 0.3, "trigger_radius": 3.0, "repeat": True}],
    }))
    code, out, _ = run(capsys, "--map", "examples/maps/emc_example.json", "--sim-config", str(cfg),
                       "--seconds", "6", "--behaviour", "drive:0.1,0,0", "--json")
    r = json.loads(out)
    assert code == 0
    # uncertain odometry: close to, but not exactly, the true motion (odometry started at 0)
    moved = [r["true_pose"][0] - 0.5, r["true_pose"][1] - 0.6]
    odom_dist = math.hypot(r["odom_pose"][0], r["odom_pose"][1])
    assert odom_dist != pytest.approx(math.hypot(*moved), abs=1e-12)
    assert abs(odom_dist - math.hypot(*moved)) <= 0.002 * r["distance_m"] + 1e-9


def test_every_run_reads_a_heightmap_with_the_configs_map_settings(capsys: pytest.CaptureFixture[str], tmp_path) -> None:
    """`run`, `run --behaviour` and `eval` load the map through one call with `cfg.map`: at
    twice the pixel size this heightmap's rooms leave no free place to start."""
    coarse = tmp_path / "coarse.yaml"
    coarse.write_text("map:\n  heightmap:\n    resolution: 0.05\n")
    png = "pico_studio/data/maps/doors_heightmap_example.png"
    for args in (["run", "--seconds", "0.05"], ["run", "--behaviour", "escape-room", "--seconds", "0.05"],
                 ["eval", "--poses", "1", "--frames", "2"]):
        assert main([*args, "--map", png, "--json"]) == 0
        capsys.readouterr()
        assert main([*args, "--map", png, "--json", "--config", str(coarse)]) == 2, args
        assert "no free place to start" in capsys.readouterr().err
