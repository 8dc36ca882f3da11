"""ROS 1 bag replay: the real PICO bag, the replay cursor, and broken bags."""

from __future__ import annotations

import math
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from pico_studio.config.sources_params import SourcesParams, TopicParams
from pico_studio.core.io import LaserData, OdometryData, RobotIO
from pico_studio.errors import SourceError
from pico_studio.sources import open_bag, open_source
from pico_studio.sources.recorder import BagRecorder

BAG = "pico_real_2019-05-07.bag"


@pytest.fixture
def real_bag(recordings_dir: Path) -> Path:
    return recordings_dir / BAG


def test_real_pico_bag_plays_every_scan(real_bag: Path) -> None:
    replay = open_bag(real_bag)
    assert isinstance(replay, RobotIO)
    assert replay.frame_count == 243
    assert not replay.has_odometry and replay.read_odometry() is None
    assert replay.truth_pose() is None
    t0, t1 = replay.time_span
    assert t1 - t0 == pytest.approx(6.8, abs=0.05)
    scans: list[LaserData] = []
    while replay.ok():
        scan = replay.read_laser()
        if scan is not None:
            scans.append(scan)
        replay.advance(0.01)  # faster than the laser (36 Hz): no scan is dropped
    assert len(scans) == 243 and replay.scans_dropped == 0
    s = scans[0]
    assert len(s.ranges) == 1081
    assert s.angle_min == pytest.approx(-2.35619, abs=1e-4)
    assert s.angles[-1] == pytest.approx(2.35619, abs=1e-4)
    assert s.angle_increment == pytest.approx(0.0043633, abs=1e-6)
    assert s.range_min == pytest.approx(0.023) and s.range_max == pytest.approx(60.0)
    assert all(b.timestamp > a.timestamp for a, b in zip(scans, scans[1:], strict=False))
    # a small room: most beams hit something within a few metres
    assert np.nanmedian(s.ranges) < 5.0
    assert replay.warnings == []


def test_slow_loop_drops_scans_like_the_robot(real_bag: Path) -> None:
    replay = open_bag(real_bag)
    delivered = 0
    while replay.ok():
        if replay.read_laser() is not None:
            delivered += 1
        replay.advance(0.05)  # 20 Hz loop against a 36 Hz laser
    assert 130 <= delivered <= 145
    assert delivered + replay.scans_dropped == 243


def test_read_returns_only_what_is_new(real_bag: Path) -> None:
    replay = open_bag(real_bag)
    first = replay.read_laser()
    assert first is not None and replay.frame_index == 0
    assert replay.read_laser() is None  # nothing new until the cursor moves
    replay.advance(replay.frame_times[1] - replay.frame_times[0])
    second = replay.read_laser()
    assert second is not None and second.timestamp > first.timestamp


def test_timeline_seek_and_random_access(real_bag: Path) -> None:
    replay = open_bag(real_bag)
    replay.seek(100)
    scan = replay.read_laser()
    assert scan is not None and replay.frame_index == 100
    assert scan.timestamp == replay.frame(100).time
    t = replay.frame_times[200] + 0.001
    replay.seek_time(t)
    assert replay.now() == pytest.approx(t)
    assert replay.read_laser() is replay.frame(200).laser
    replay.seek(replay.frame_count - 1)
    assert replay.read_laser() is not None and not replay.ok()
    with pytest.raises(IndexError):
        replay.seek(243)


def test_open_source_spellings(real_bag: Path) -> None:
    assert open_source(f"bag:{real_bag}").frame_count == 243
    assert open_source(str(real_bag)).frame_count == 243
    with pytest.raises(SourceError, match="no such bag file"):
        open_source("bag:/nonexistent.bag")
    with pytest.raises(SourceError, match="unknown source"):
        open_source("tape:x")


# --- broken bags -------------------------------------------------------------------------


def test_not_a_bag_is_a_clear_error(tmp_path: Path) -> None:
    bad = tmp_path / "notes.bag"
    bad.write_text("hello, this is not a bag\n")
    with pytest.raises(SourceError, match=r"notes\.bag: not a ROS 1 bag"):
        open_bag(bad)


def test_truncated_bag_replays_what_is_left(real_bag: Path, tmp_path: Path) -> None:
    data = real_bag.read_bytes()
    cut = tmp_path / "cut.bag"
    cut.write_bytes(data[: int(len(data) * 0.6)])  # index gone, third chunk gone
    replay = open_bag(cut)
    assert 90 <= replay.frame_count < 243
    assert any("index is unusable" in w for w in replay.warnings)
    assert any("file ends inside the record" in w for w in replay.warnings)
    whole = open_bag(real_bag)
    for i in (0, replay.frame_count - 1):
        assert np.array_equal(replay.frame(i).laser.ranges, whole.frame(i).laser.ranges)


def test_bag_with_damaged_index_is_read_from_its_chunks(real_bag: Path, tmp_path: Path) -> None:
    data = bytearray(real_bag.read_bytes())
    data[-200:] = b"\xff" * 200  # scribble over the index at the end of the file
    bad = tmp_path / "scribbled.bag"
    bad.write_bytes(bytes(data))
    replay = open_bag(bad)
    assert replay.frame_count == 243
    assert any("index is unusable" in w for w in replay.warnings)


def test_bag_without_the_laser_topic_names_the_setting(tmp_path: Path) -> None:
    path = tmp_path / "odom_only.bag"
    with BagRecorder(path) as rec:
        rec.record_odometry(OdometryData(1.0, 2.0, 0.5, 10.0))
    with pytest.raises(SourceError) as err:
        open_bag(path)
    text = str(err.value)
    assert "odom_only.bag" in text and "sources.topics.laser" in text and "/pico/odom" in text


def test_laser_topic_name_is_configuration(real_bag: Path, tmp_path: Path) -> None:
    moved = tmp_path / "moved.bag"
    src = open_bag(real_bag)
    topics = TopicParams(laser="/scan")
    with BagRecorder(moved, topics) as rec:
        for i in range(5):
            rec.record_laser(src.frame(i).laser)
    with pytest.raises(SourceError, match="/pico/laser"):
        open_bag(moved)
    params = SourcesParams(topics=topics)
    assert open_bag(moved, params).frame_count == 5


def _scan(t: float, n: int = 1081, inc: float = 0.0043633231) -> LaserData:
    return LaserData(0.023, 60.0, -2.3561945, 2.3561945, inc, t, np.full(n, 2.0))


def test_scan_whose_angles_disagree_with_its_beams_is_skipped(tmp_path: Path) -> None:
    path = tmp_path / "odd.bag"
    with BagRecorder(path) as rec:
        for i in range(6):
            rec.record_laser(_scan(1.0 + 0.1 * i, inc=0.0087266 if i == 3 else 0.0043633231))
    replay = open_bag(path)
    assert replay.frame_count == 5
    (warning,) = replay.warnings
    assert "odd.bag" in warning and "message 3 on /pico/laser" in warning
    assert "angle_increment" in warning and "1081" in warning


def test_message_that_cannot_be_decoded_is_skipped(tmp_path: Path) -> None:
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS1_NOETIC)
    good = tmp_path / "good.bag"
    with BagRecorder(good) as rec:
        for i in range(4):
            rec.record_laser(_scan(1.0 + i))
    raw = open_bag(good)  # re-write the same messages, the third one cut short
    bad = tmp_path / "short_message.bag"
    from rosbags.rosbag1 import Reader

    with Reader(good) as reader, Writer(bad) as writer:
        conn = writer.add_connection("/pico/laser", "sensor_msgs/msg/LaserScan", typestore=ts)
        for i, (_c, t, data) in enumerate(reader.messages()):
            writer.write(conn, t, data[:100] if i == 2 else data)
    replay = open_bag(bad)
    assert raw.frame_count == 4 and replay.frame_count == 3
    assert any("message 2 on /pico/laser: cannot be decoded" in w for w in replay.warnings)


def test_odometry_yaw_comes_from_the_quaternion(tmp_path: Path) -> None:
    path = tmp_path / "odom.bag"
    with BagRecorder(path) as rec:
        for i, a in enumerate((0.0, 1.0, math.pi - 0.01, -2.5)):
            rec.record_laser(_scan(1.0 + i))
            rec.record_odometry(OdometryData(0.5 * i, -0.25 * i, a, 1.0 + i))
    replay = open_bag(path)
    yaws = [replay.frame(i).odometry.a for i in range(4)]
    assert yaws == pytest.approx([0.0, 1.0, math.pi - 0.01, -2.5], abs=1e-12)


def test_copy_of_real_bag_with_active_suffix_is_guessed(real_bag: Path, tmp_path: Path) -> None:
    active = tmp_path / "run.bag.active"
    shutil.copy(real_bag, active)
    assert open_source(str(active)).frame_count == 243


def test_loop_that_advances_before_it_reads_meets_the_first_frame(real_bag: Path) -> None:
    """The emc loop (and the session) sleeps, then reads: frame 0 must not be skipped."""
    replay = open_bag(real_bag)
    replay.advance(0.05)
    first = replay.read_laser()
    assert first is not None and replay.frame_index == 0
    replay.seek(10)
    replay.advance(0.05)
    assert replay.read_laser() is replay.frame(10).laser
    replay.advance(0.05)  # from here on the cursor moves
    assert replay.now() == pytest.approx(replay.frame_times[10] + 0.05)


def test_laser_topic_of_the_wrong_type_is_a_clear_error(tmp_path: Path) -> None:
    from pico_studio.core.io import BaseReference

    path = tmp_path / "twist_on_laser.bag"
    with BagRecorder(path, TopicParams(laser="/scan", base_reference="/pico/laser")) as rec:
        rec.record_base_reference(BaseReference(0.1, 0.0, 0.0, 1.0))
    with pytest.raises(SourceError) as err:
        open_bag(path)
    text = str(err.value)
    assert "no usable laser scan" in text and "geometry_msgs/msg/Twist" in text and "LaserScan" in text


@pytest.mark.parametrize("compression", ["lz4", "bz2"])
def test_truncated_compressed_bag_replays_what_is_left(real_bag: Path, tmp_path: Path, compression: str) -> None:
    src = open_bag(real_bag)
    whole = tmp_path / "whole.bag"
    with BagRecorder(whole, compression=compression) as rec:
        rec._writer.chunk_threshold = 200_000  # several chunks, so a cut keeps some whole
        for i in range(src.frame_count):
            rec.record_laser(src.frame(i).laser)
    data = whole.read_bytes()
    cut = tmp_path / "cut.bag"
    cut.write_bytes(data[: len(data) // 2])
    replay = open_bag(cut)
    assert 0 < replay.frame_count < 243
    assert np.array_equal(replay.frame(0).laser.ranges, src.frame(0).laser.ranges)


def _damaged_copy(real_bag: Path, tmp_path: Path, name: str, change) -> Path:
    data = bytearray(real_bag.read_bytes())
    change(data)
    data[-200:] = b"\xff" * 200  # and the index, so the chunks are walked
    path = tmp_path / name
    path.write_bytes(bytes(data))
    return path


def test_message_record_without_its_time_field_is_skipped_naming_the_offset(real_bag: Path, tmp_path: Path) -> None:
    def change(b: bytearray) -> None:
        i = b.find(b"time=", 5000)
        b[i : i + 4] = b"tyme"

    replay = open_bag(_damaged_copy(real_bag, tmp_path, "no_time.bag", change))
    assert replay.frame_count == 242  # was: KeyError 'time'
    assert any("of the chunk at byte 4117: header has no 'time' field; skipped" in w for w in replay.warnings)


def test_chunk_with_a_damaged_header_is_skipped_and_the_next_one_read(real_bag: Path, tmp_path: Path) -> None:
    whole = open_bag(real_bag)

    def change(b: bytearray) -> None:
        j = b.find(b"\x04\x00\x00\x00op=\x05", 100_000)  # the second chunk's op field
        b[j - 30 : j] = b"\xee" * 30  # its header length and first field

    replay = open_bag(_damaged_copy(real_bag, tmp_path, "bad_chunk.bag", change))
    assert 0 < replay.frame_count < whole.frame_count
    assert any("is damaged" in w and "resumed at the chunk at byte" in w for w in replay.warnings), replay.warnings
    last = replay.frame(replay.frame_count - 1)  # chunks after the damaged one are still read
    assert np.array_equal(last.laser.ranges, whole.frame(whole.frame_count - 1).laser.ranges)


def test_junk_inside_a_chunk_skips_the_rest_of_that_chunk_only(real_bag: Path, tmp_path: Path) -> None:
    whole = open_bag(real_bag)

    def change(b: bytearray) -> None:
        j = b.find(b"\x04\x00\x00\x00op=\x05", 100_000)
        b[j + 40 : j + 2040] = b"\xaa" * 2000

    replay = open_bag(_damaged_copy(real_bag, tmp_path, "junk_chunk.bag", change))
    assert 0 < replay.frame_count < whole.frame_count
    assert any("framing lost" in w and "rest of the chunk skipped" in w for w in replay.warnings), replay.warnings


def test_bag_that_is_not_a_regular_file_is_refused_unopened(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe.bag"
    os.mkfifo(fifo)
    with pytest.raises(SourceError, match="is a FIFO"):
        open_bag(fifo)  # would block for ever if opened for reading
    with pytest.raises(SourceError, match="is a directory"):
        open_bag(tmp_path)
