"""The bag recorder: what it writes plays back identically through the bag reader."""

from __future__ import annotations

import math
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from pico_studio.core.io import BaseReference, LaserData, OdometryData
from pico_studio.errors import SourceError
from pico_studio.sources import open_bag, open_carmen
from pico_studio.sources.recorder import BagRecorder


def _scan(t: float) -> LaserData:
    return LaserData(0.01, 10.0, -2.0, 2.0, 4.0 / 999, t, np.full(1000, 3.0))


def test_record_then_read_back_identically(recordings_dir: Path, tmp_path: Path) -> None:
    """A CARMEN run (scans, odometry, truth) plus commands, written and read back."""
    src = open_carmen(recordings_dir / "intel-corrected.log.gz")
    path = tmp_path / "intel.bag"
    n = 120
    with BagRecorder(path) as rec:
        for i in range(n):
            f = src.frame(i)
            rec.record_laser(f.laser)
            rec.record_odometry(f.odometry)
            rec.record_true_pose(f.time, f.truth["pose"])
            rec.record_base_reference(BaseReference(0.3, -0.1, 0.05 * i, f.time))
            if i % 40 == 0:
                rec.record_open_door(f.time)
    back = open_bag(path)
    assert back.frame_count == n and back.warnings == []
    assert back.summary()["topics"]["/pico/open_door"] == 3
    for i in range(n):
        a, b = src.frame(i), back.frame(i)
        assert b.time == a.time
        # LaserScan holds float32 ranges: the CARMEN centimetres survive that exactly
        assert np.array_equal(b.laser.ranges, a.laser.ranges.astype(np.float32))
        assert b.laser.angle_min == pytest.approx(a.laser.angle_min, abs=1e-7)
        assert b.laser.angle_increment == pytest.approx(a.laser.angle_increment, abs=1e-9)
        assert len(b.laser.ranges) == 180
        assert (b.odometry.x, b.odometry.y) == (a.odometry.x, a.odometry.y)
        assert b.odometry.a == pytest.approx(a.odometry.a, abs=1e-12)
        assert b.truth["pose"] == pytest.approx(a.truth["pose"], abs=1e-12)
        ref = back.base_reference_at(a.time)
        assert (ref.vx, ref.vy, ref.va) == pytest.approx((0.3, -0.1, 0.05 * i))


def test_replay_of_a_recording_is_the_same_loop(recordings_dir: Path, tmp_path: Path) -> None:
    """Driving the loop over the original and over its recording gives the same reads."""
    src = open_bag(recordings_dir / "pico_real_2019-05-07.bag")
    path = tmp_path / "copy.bag"
    with BagRecorder(path) as rec:
        for i in range(src.frame_count):
            rec.record_laser(src.frame(i).laser)
    copy = open_bag(path)
    reads = []
    for replay in (src, copy):
        replay.seek(0)
        got = []
        while replay.ok():
            scan = replay.read_laser()
            got.append(None if scan is None else (scan.timestamp, scan.ranges.tobytes()))
            replay.advance(0.05)
        reads.append(got)
    assert reads[0] == reads[1]


def test_delta_odometry_is_recorded_as_a_pose(tmp_path: Path) -> None:
    path = tmp_path / "delta.bag"
    with BagRecorder(path) as rec:
        for i in range(4):
            rec.record_laser(_scan(1.0 + i))
            rec.record_odometry(OdometryData(1.0, 0.0, math.pi / 2, 1.0 + i, form="delta"))
    odom = [open_bag(path).frame(i).odometry for i in range(4)]
    assert (odom[0].x, odom[0].y) == pytest.approx((1.0, 0.0))
    assert (odom[1].x, odom[1].y) == pytest.approx((1.0, 1.0))
    assert (odom[3].x, odom[3].y) == pytest.approx((0.0, 0.0), abs=1e-12)
    assert odom[3].form == "absolute"


def test_recorder_refuses_to_overwrite_and_bad_times(tmp_path: Path) -> None:
    path = tmp_path / "x.bag"
    path.write_text("precious")
    with pytest.raises(SourceError, match="exists already"):
        BagRecorder(path)
    with pytest.raises(SourceError, match="folder does not exist"):
        BagRecorder(tmp_path / "nowhere" / "x.bag")
    with BagRecorder(path, overwrite=True) as rec, pytest.raises(SourceError, match="time"):
        rec.record_open_door(float("nan"))


@pytest.mark.ros
def test_rosbag_info_reads_a_recording(recordings_dir: Path, tmp_path: Path) -> None:
    """Debian's `rosbag` (the real ROS 1 tool) reads what the recorder wrote."""
    if shutil.which("rosbag") is None:
        pytest.skip("Debian's python3-rosbag is not installed (./dev test installs it as root)")
    src = open_bag(recordings_dir / "pico_real_2019-05-07.bag")
    path = tmp_path / "rec.bag"
    with BagRecorder(path) as rec:
        for i in range(10):
            f = src.frame(i)
            rec.record_laser(f.laser)
            rec.record_odometry(OdometryData(0.1 * i, 0.0, 0.0, f.time))
            rec.record_base_reference(BaseReference(0.2, 0.0, 0.1, f.time))
            rec.record_true_pose(f.time, (1.0, 2.0, 0.5))
    out = subprocess.run(
        ["rosbag", "info", "--yaml", str(path)], capture_output=True, text=True, timeout=60, check=True
    ).stdout
    for line in (
        "topic: /pico/laser", "type: sensor_msgs/LaserScan", "type: nav_msgs/Odometry",
        "type: geometry_msgs/Twist", "type: geometry_msgs/PoseStamped", "messages: 40",
    ):
        assert line in out


def test_record_a_session_frame(tmp_path: Path) -> None:
    """`record(frame, command)`: what the session loop hands its recorder each tick."""
    from dataclasses import dataclass

    from pico_studio.core.io import Frame

    @dataclass(frozen=True)
    class Command:
        vx: float
        vy: float
        va: float
        open_door: bool = False

    path = tmp_path / "session.bag"
    with BagRecorder(path) as rec:
        for i in range(1, 6):
            t = 0.05 * i
            frame = Frame(
                laser=_scan(t), odometry=OdometryData(0.01 * i, 0.0, 0.0, t), time=t,
                truth={"pose": (1.0 + 0.01 * i, 2.0, 0.1), "collisions": 0},
            )
            rec.record(frame, Command(0.2, 0.0, 0.1, open_door=(i == 3)))
        rec.record(Frame(laser=None, odometry=None, time=0.3), None)  # a tick with nothing new
    replay = open_bag(path)
    assert replay.frame_count == 5
    assert replay.summary()["topics"] == {
        "/pico/cmd_vel": 5, "/pico/laser": 5, "/pico/odom": 5, "/pico/open_door": 1, "/pico/true_pose": 5,
    }
    replay.seek(2)
    replay.read_laser()
    assert replay.truth_pose() == pytest.approx((1.03, 2.0, 0.1))
    assert replay.frame_times == pytest.approx([0.05, 0.10, 0.15, 0.20, 0.25])


@pytest.mark.parametrize("compression", ["lz4", "bz2"])
def test_compressed_recordings_play_back(recordings_dir: Path, tmp_path: Path, compression: str) -> None:
    src = open_bag(recordings_dir / "pico_real_2019-05-07.bag")
    path = tmp_path / f"{compression}.bag"
    with BagRecorder(path, compression=compression) as rec:
        for i in range(30):
            rec.record_laser(src.frame(i).laser)
    back = open_bag(path)
    assert back.frame_count == 30
    assert np.array_equal(back.frame(29).laser.ranges, src.frame(29).laser.ranges)
    assert path.stat().st_size < 30 * 1081 * 4  # smaller than the raw ranges
    if shutil.which("rosbag"):
        out = subprocess.run(["rosbag", "info", "--yaml", str(path)], capture_output=True, text=True,
                             timeout=60, check=True).stdout
        assert f"compression: {compression}" in out
