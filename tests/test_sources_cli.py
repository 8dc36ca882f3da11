"""`pico-studio run --source bag:FILE|carmen:FILE` and `--record FILE.bag`."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from pico_studio.cli import main
from pico_studio.sources import open_bag, open_carmen

MAP = "pico_studio/data/maps/hospital_2019.json"


def _run_json(capsys: pytest.CaptureFixture[str], *args: str) -> dict:
    assert main(["run", *args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_run_the_real_bag(recordings_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    r = _run_json(capsys, "--source", f"bag:{recordings_dir / 'pico_real_2019-05-07.bag'}")
    assert r["frames"] == 243 and r["frames_read"] == 243 and r["frames_dropped"] == 0
    assert r["beams"] == [1081] and r["odometry_readings"] == 0
    figures = r["perceptor"]
    assert figures["frames_perceived"] == 243
    assert figures["valid_beams"]["median"] > 1000  # a small room: nearly every beam returns
    assert figures["current_map_segments"]["median"] >= 3  # the walls of the room
    # the perception issue's bar for the real robot: no worse than 7 walls a scan fitted to 5 mm
    assert 6 <= figures["current_map_segments"]["median"] <= 8
    assert 1.0 < figures["current_map_rms_mm"]["median"] <= 5.5


def test_run_the_real_bag_at_a_fixed_rate_drops_scans(recordings_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    r = _run_json(capsys, "--source", f"bag:{recordings_dir / 'pico_real_2019-05-07.bag'}", "--dt", "0.05")
    assert r["frames_read"] + r["frames_dropped"] == 243 and r["frames_dropped"] > 90


def test_run_the_carmen_log_for_a_while(recordings_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    r = _run_json(capsys, "--source", f"carmen:{recordings_dir / 'intel-corrected.log.gz'}", "--seconds", "60")
    assert r["frames"] == 910 and r["truth_poses"] == 910
    assert 5 < r["frames_read"] < 910


def test_carmen_log_converts_to_a_bag(recordings_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "intel.bag"
    log = recordings_dir / "intel-corrected.log.gz"
    r = _run_json(capsys, "--source", f"carmen:{log}", "--record", str(out), "--no-perceptor")
    assert r["perceptor"] is None
    assert r["recorded"]["messages"]["/pico/laser"] == 910
    bag, carmen = open_bag(out), open_carmen(log)
    assert bag.frame_count == 910 and bag.has_truth
    for i in (0, 455, 909):
        a, b = carmen.frame(i), bag.frame(i)
        assert b.time == a.time and np.array_equal(b.laser.ranges, a.laser.ranges.astype(np.float32))
        assert b.truth["pose"] == pytest.approx(a.truth["pose"], abs=1e-12)


def test_simulated_run_records_a_bag_that_replays(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "sim.bag"
    sim = _run_json(capsys, "--map", MAP, "--behaviour", "drive:0.2,0,0.1", "--seconds", "2", "--record", str(out))
    assert sim["recorded"]["messages"]["/pico/laser"] == 40
    replay = _run_json(capsys, "--source", f"bag:{out}")
    assert replay["frames_read"] == 40 and replay["truth_poses"] == 40 and replay["base_references"] == 40
    bag = open_bag(out)
    bag.seek(bag.frame_count - 1)
    bag.read_laser()
    assert bag.truth_pose() == pytest.approx(tuple(sim["true_pose"]), abs=1e-9)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--source", "bag:/no/such.bag"], "no such bag file"),
        (["--source", "tape:x"], "unknown source kind 'tape'"),
        (["--source", "sim"], "--map: the simulator needs a map"),
        (["--source", "ros", "--map", MAP], "--map is for the simulator"),
    ],
)
def test_bad_source_arguments_exit_2(args: list[str], message: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", *args]) == 2
    assert message in capsys.readouterr().err


def test_record_refuses_to_overwrite(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "taken.bag"
    out.write_text("keep me")
    assert main(["run", "--map", MAP, "--seconds", "0.2", "--record", str(out)]) == 2
    assert "exists already" in capsys.readouterr().err and out.read_text() == "keep me"


def test_broken_bag_is_one_line_and_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.bag"
    bad.write_bytes(b"#ROSBAG V2.0\n" + b"\x00" * 10)
    assert main(["run", "--source", f"bag:{bad}"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "bad.bag" in err
