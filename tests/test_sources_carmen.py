"""CARMEN log replay: the real Intel Research Lab log and broken lines."""

from __future__ import annotations

import gzip
import math
from pathlib import Path

import numpy as np
import pytest

from pico_studio.config.sources_params import CarmenParams, SourcesParams
from pico_studio.core.geometry import wrap_angle
from pico_studio.errors import SourceError
from pico_studio.sources import open_carmen, open_source

INTEL = "intel-corrected.log.gz"


@pytest.fixture
def intel(recordings_dir: Path) -> Path:
    return recordings_dir / INTEL


def test_intel_log_plays_with_corrected_pose_as_truth(intel: Path) -> None:
    replay = open_carmen(intel)
    assert replay.frame_count == 910
    assert replay.has_truth and replay.has_odometry
    assert replay.warnings == []
    scan = replay.read_laser()
    assert scan is not None and len(scan.ranges) == 180
    # 180 degree field of view in 1 degree steps, centred on the robot's x axis
    assert scan.angle_min == pytest.approx(-math.pi / 2)
    assert scan.angle_increment == pytest.approx(math.radians(1.0))
    assert scan.angles[-1] == pytest.approx(math.radians(89.0))
    assert replay.truth_pose() == pytest.approx((0.600266, -0.0320327, -0.354665))
    # odometry is the raw ODOM line at the scan's time, not the corrected pose
    odom = replay.read_odometry()
    assert odom is not None and (odom.x, odom.y, odom.a) == pytest.approx((0.698035, -0.0132843, -0.460915))
    assert replay.summary()["odom_pose_copies_ignored"] == 910


def test_intel_odometry_is_its_own_series_not_the_truth(intel: Path) -> None:
    """The ODOM lines (timed) are the odometry; the FLASER pose is only the truth."""
    replay = open_carmen(intel)
    differ = 0
    for i in range(replay.frame_count):
        f = replay.frame(i)
        assert f.odometry is not None and f.odometry.timestamp <= f.time
        tx, ty, ta = f.truth["pose"]
        differ += math.hypot(f.odometry.x - tx, f.odometry.y - ty) > 1e-3
        assert abs(wrap_angle(f.odometry.a)) <= math.pi
    assert differ > 800


def test_intel_odometry_keeps_the_log_order(intel: Path) -> None:
    """Jittering ODOM stamps and the corrected-pose copies (some with garbage stamps) must
    not make the odometry jump: readings come in log order, each step a short one."""
    replay = open_carmen(intel)
    odom = replay.recording.odometry
    stamps = np.array([o.timestamp for o in odom])
    steps = np.hypot(np.diff([o.x for o in odom]), np.diff([o.y for o in odom]))
    assert np.all(np.diff(stamps) >= 0)
    assert steps.max() < 0.3  # the robot moves < 0.3 m between two readings in this log
    info = replay.summary()
    assert info["odom_pose_copies_ignored"] == 910 and info["odometry_readings"] == 14541 - 910


def test_whole_intel_log_through_the_loop(intel: Path) -> None:
    replay = open_carmen(intel)
    scans = 0
    truth = []
    while replay.ok():
        if replay.read_laser() is not None:
            scans += 1
            truth.append(replay.truth_pose())
        replay.advance(0.5)
    assert scans + replay.scans_dropped == 910
    assert len(set(truth)) > 800


def test_plain_text_log_plays_too(intel: Path, tmp_path: Path) -> None:
    plain = tmp_path / "intel.log"
    plain.write_bytes(gzip.decompress(intel.read_bytes()))
    replay = open_source(f"carmen:{plain}")
    assert replay.frame_count == 910
    assert np.array_equal(replay.frame(10).laser.ranges, open_carmen(intel).frame(10).laser.ranges)


def test_field_of_view_is_configuration(intel: Path) -> None:
    params = SourcesParams(carmen=CarmenParams(field_of_view=math.radians(100)))
    scan = open_carmen(intel, params).frame(0).laser
    assert scan.angle_min == pytest.approx(math.radians(-50))


def _lines(intel: Path, n: int) -> list[str]:
    out = []
    with gzip.open(intel, "rt") as f:
        for line in f:
            out.append(line)
            if sum(x.startswith("FLASER") for x in out) >= n:
                return out
    return out


def test_line_with_the_wrong_field_count_is_skipped(intel: Path, tmp_path: Path) -> None:
    lines = _lines(intel, 5)
    flaser = [i for i, line in enumerate(lines) if line.startswith("FLASER")]
    tokens = lines[flaser[2]].split()
    lines[flaser[2]] = " ".join(tokens[:100]) + "\n"  # cut short
    lines[flaser[3]] = lines[flaser[3]].replace("FLASER 180 ", "FLASER 180 1.5 ", 1)  # one too many
    path = tmp_path / "broken.log"
    path.write_text("".join(lines))
    replay = open_carmen(path)
    assert replay.frame_count == 3
    assert len(replay.warnings) == 2
    w = replay.warnings[0]
    assert "broken.log" in w and f"line {flaser[2] + 1}" in w and "needs 191 fields, found 100" in w


def test_field_that_is_not_a_number_is_named(intel: Path, tmp_path: Path) -> None:
    lines = _lines(intel, 3)
    flaser = [i for i, line in enumerate(lines) if line.startswith("FLASER")]
    tokens = lines[flaser[1]].split()
    tokens[2 + 180 + 1] = "y?"
    lines[flaser[1]] = " ".join(tokens) + "\n"
    odom = next(i for i, line in enumerate(lines) if line.startswith("ODOM"))
    lines[odom] = "ODOM 1 2\n"
    path = tmp_path / "words.log"
    path.write_text("".join(lines))
    replay = open_carmen(path)
    assert replay.frame_count == 2
    assert any("FLASER y: must be a number, got 'y?'" in w for w in replay.warnings)
    assert any(f"line {odom + 1}: ODOM fields: needs 10 fields, found 3" in w for w in replay.warnings)


def test_truncated_gzip_replays_what_was_read(intel: Path, tmp_path: Path) -> None:
    data = intel.read_bytes()
    cut = tmp_path / "cut.log.gz"
    cut.write_bytes(data[: len(data) // 2])
    replay = open_carmen(cut)
    assert 300 < replay.frame_count < 910
    assert any("damaged after line" in w for w in replay.warnings)


def test_file_without_scans_is_a_clear_error(tmp_path: Path) -> None:
    path = tmp_path / "odom_only.log"
    path.write_text("PARAM robot_frontlaser_offset 0.0 nohost 0\nODOM 0 0 0 0 0 0 1.0 host 1.0\n")
    with pytest.raises(SourceError, match="odom_only.log: holds no FLASER or ROBOTLASER1 line"):
        open_carmen(path)


def test_file_with_only_broken_scans_says_why(tmp_path: Path) -> None:
    path = tmp_path / "all_bad.log"
    path.write_text("FLASER 3 1 2 3 0 0 0 0 0 0 1.0 host\n")
    with pytest.raises(SourceError, match="no usable laser scan.*needs 14 fields, found 13"):
        open_carmen(path)


def _robotlaser_line(flaser: str) -> str:
    """The same scan as a ROBOTLASER1 line (start -90 deg, 1 deg steps, 2 remissions)."""
    t = flaser.split()
    n = int(t[1])
    ranges, (x, y, a, _ox, _oy, _oa), tail = t[2 : 2 + n], t[2 + n : 8 + n], t[8 + n :]
    fields = ["ROBOTLASER1", "0", f"{-math.pi / 2!r}", f"{math.pi!r}", f"{math.pi / 180!r}", "81.9", "0.01", "0",
              str(n), *ranges, "2", "7", "8", x, y, a, x, y, a, "0", "0", "0.5", "0.3", "1", *tail]
    return " ".join(fields) + "\n"


def test_robotlaser1_lines_play_like_flaser(intel: Path, tmp_path: Path) -> None:
    lines = [line for line in _lines(intel, 4) if line.startswith("FLASER")]
    path = tmp_path / "robotlaser.log"
    path.write_text("".join(_robotlaser_line(line) for line in lines) + "ROBOTLASER1 0 0 3.14 0.01 80 0 0 5 1 2\n")
    replay = open_carmen(path)
    reference = open_carmen(intel)
    assert replay.frame_count == 4
    (warning,) = replay.warnings
    assert "ROBOTLASER1 num_remissions: must be a number" in warning
    for i in range(4):
        a, b = reference.frame(i), replay.frame(i)
        assert np.array_equal(a.laser.ranges, b.laser.ranges) and a.time == b.time
        assert b.laser.angle_min == pytest.approx(-math.pi / 2) and b.laser.range_max == 81.9
        assert b.laser.angle_increment == pytest.approx(a.laser.angle_increment)
        assert b.truth["pose"] == pytest.approx(a.truth["pose"])


def test_raw_logs_offer_no_truth(intel: Path) -> None:
    params = SourcesParams(carmen=CarmenParams(pose_is_truth=False))
    replay = open_carmen(intel, params)
    assert not replay.has_truth and replay.truth_pose() is None and replay.frame(3).truth == {}


def test_gzip_bomb_is_cut_off_at_the_decompressed_cap(tmp_path: Path) -> None:
    bomb = tmp_path / "bomb.log.gz"
    bomb.write_bytes(gzip.compress(b"\0" * (1 << 20), compresslevel=9) * 1024)  # 1 GiB of zeros in ~1 MB
    with pytest.raises(SourceError, match="decompressed beyond"):
        open_carmen(bomb)


def test_good_lines_before_a_bomb_are_replayed(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PICO_STUDIO_MAX_DECOMPRESSED_FLOOR_MB", "1")
    monkeypatch.setenv("PICO_STUDIO_MAX_DECOMPRESSED_RATIO", "1")
    scan = " ".join(["1.0"] * 180)
    good = "".join(f"FLASER 180 {scan} 1 1 0 1 1 0 {t / 10} host 0\n" for t in range(5)).encode()
    log = tmp_path / "then_bomb.log.gz"
    log.write_bytes(gzip.compress(good) + gzip.compress(b"\0" * (1 << 20)) * 200)
    replay = open_carmen(log)
    assert replay.frame_count == 5
    assert any("decompressed beyond" in w for w in replay.warnings)


def test_overlong_line_is_skipped_naming_it(tmp_path: Path) -> None:
    scan = " ".join(["1.0"] * 180)
    log = tmp_path / "long.log"
    log.write_text(
        f"FLASER 180 {scan} 1 1 0 1 1 0 0.0 host 0\n" + "FLASER " + "1 " * (3 << 20) + "\n"
        + f"FLASER 180 {scan} 1 1 0 1 1 0 0.1 host 0\n"
    )
    replay = open_carmen(log)
    assert replay.frame_count == 2
    assert any("line 2: longer than 4 MB; line skipped" in w for w in replay.warnings)


def test_scan_with_a_damaged_stamp_is_dropped(tmp_path: Path) -> None:
    scan = " ".join(["1.0"] * 180)
    stamps = [0.0, 0.1, 0.2, 1e12, 0.3, 0.4]
    log = tmp_path / "stamp.log"
    log.write_text("".join(f"FLASER 180 {scan} 1 1 0 1 1 0 {t} host 0\n" for t in stamps))
    replay = open_carmen(log)
    assert replay.frame_count == 5 and replay.time_span == (0.0, 0.4)
    assert any("scans 3 (1e+12 s)" in w for w in replay.warnings)
