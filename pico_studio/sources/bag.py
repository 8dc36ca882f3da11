"""Replay of ROS 1 bags (format 2.0) with the `rosbags` package: no ROS install needed.

Topics (names from `cfg.sources.topics`):

| topic            | type                        | becomes                                   |
|------------------|-----------------------------|-------------------------------------------|
| laser            | sensor_msgs/LaserScan       | `LaserData` (required)                    |
| odometry         | nav_msgs/Odometry           | absolute `OdometryData`, yaw from the quaternion |
| base_reference   | geometry_msgs/Twist         | recorded `BaseReference`s                 |
| true_pose        | geometry_msgs/PoseStamped   | ground truth (recordings of simulated runs) |

Times are the message header stamps where set, else the time the bag recorded the message.

Bad input: a file that is not a bag, or that has no laser topic, is a `SourceError`. A bag
whose index is missing or damaged (the recorder died: truncated file, `.bag.active`) is
read by walking its chunks from the start, as `rosbag reindex` would, up to the first
unreadable record; a message that cannot be decoded, or a scan whose angle fields disagree
with its beam count, is skipped with a warning naming the file, the message index and the
field. The replay goes on with what is left.
"""

from __future__ import annotations

import bz2
import io
import math
import struct
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any, BinaryIO

import numpy as np
from rosbags.rosbag1 import Reader, ReaderError
from rosbags.typesys import Stores, get_typestore

from pico_studio.config.sources_params import ReplayParams, SourcesParams, TopicParams
from pico_studio.core.io import BaseReference, LaserData, OdometryData
from pico_studio.errors import SourceError
from pico_studio.sources.convert import beam_layout_problem, yaw_from_quaternion
from pico_studio.sources.replay import Recording, Replay, TimedPose

LASER_TYPE = "sensor_msgs/msg/LaserScan"
ODOMETRY_TYPE = "nav_msgs/msg/Odometry"
TWIST_TYPE = "geometry_msgs/msg/Twist"
POSE_TYPE = "geometry_msgs/msg/PoseStamped"

_TYPESTORE = get_typestore(Stores.ROS1_NOETIC)
_MAGIC = b"#ROSBAG V2.0\n"


@dataclass(frozen=True)
class RawMessage:
    topic: str
    msgtype: str  # rosbags' spelling: "sensor_msgs/msg/LaserScan"
    time_ns: int
    data: bytes


def open_bag(path: str | Path, params: SourcesParams | None = None) -> Replay:
    """A `Replay` of the bag at `path`."""
    return Replay(read_bag(path, params))


def read_bag(path: str | Path, params: SourcesParams | None = None) -> Recording:
    """Decode the robot's topics of a ROS 1 bag into a `Recording`."""
    params = params or SourcesParams()
    path = Path(path)
    if not path.is_file():
        raise SourceError("no such bag file", file=path)
    warnings: list[str] = []
    messages, info = _read_messages(path, warnings)

    topics = params.topics
    by_topic: dict[str, list[RawMessage]] = {}
    for m in messages:
        by_topic.setdefault(m.topic, []).append(m)
    if topics.laser not in by_topic:
        present = ", ".join(f"{t} ({msgs[0].msgtype})" for t, msgs in sorted(by_topic.items()))
        raise SourceError(
            f"the bag has no laser topic {topics.laser}; its topics: {present or 'none'} "
            "(set sources.topics.laser to the right one)",
            file=path, field="sources.topics.laser",
        )
    decode = _Decoder(path, topics, params.replay, warnings)
    recording = Recording(
        name=str(path),
        scans=decode.all(by_topic, topics.laser, LASER_TYPE, decode.laser),
        odometry=decode.all(by_topic, topics.odometry, ODOMETRY_TYPE, decode.odometry),
        base_references=decode.all(by_topic, topics.base_reference, TWIST_TYPE, decode.twist),
        truth=decode.all(by_topic, topics.true_pose, POSE_TYPE, decode.pose),
        warnings=warnings,
        info={"topics": {t: len(msgs) for t, msgs in sorted(by_topic.items())}, **info},
    )
    return recording


# --- reading the bag's records -----------------------------------------------------------


def _read_messages(path: Path, warnings: list[str]) -> tuple[list[RawMessage], dict[str, Any]]:
    """All messages of the bag: through its index, or by walking its chunks when the index
    is missing or damaged."""
    with path.open("rb") as f:
        magic = f.read(len(_MAGIC))
    if magic != _MAGIC:
        raise SourceError(
            f"not a ROS 1 bag (format 2.0): the file starts with {magic[:16]!r}", file=path
        )
    try:
        with Reader(path) as reader:
            messages = [
                RawMessage(c.topic, c.msgtype, t, bytes(raw))
                for c, t, raw in reader.messages()
            ]
        return messages, {"indexed": True}
    except (ReaderError, KeyError, struct.error, ValueError, EOFError, OSError) as e:
        messages = list(_walk_chunks(path, warnings))
        warnings.append(
            f"{path}: the bag's index is unusable ({e}); recovered {len(messages)} "
            "messages by reading its chunks in order"
        )
        return messages, {"indexed": False}


def _walk_chunks(path: Path, warnings: list[str]) -> Iterator[RawMessage]:
    """Messages of a bag read record by record from the start, without its index."""
    connections: dict[int, tuple[str, str]] = {}
    with path.open("rb") as f:
        f.seek(len(_MAGIC))
        while True:
            pos = f.tell()
            try:
                header, data = _read_record(f)
            except EOFError:
                if f.tell() != pos:
                    warnings.append(f"{path}: file ends inside the record at byte {pos}")
                return
            op = header.get("op", b"\xff")[0]
            if op == 0x05:  # chunk
                try:
                    chunk = _decompress(header.get("compression", b"none").decode(), data)
                except (OSError, ValueError, EOFError, RuntimeError) as e:
                    warnings.append(f"{path}: chunk at byte {pos} cannot be decompressed ({e})")
                    return
                yield from _chunk_messages(io.BytesIO(chunk), connections, path, pos, warnings)
            elif op == 0x07:  # connection record outside a chunk (after the index)
                _add_connection(connections, header, data)


def _chunk_messages(
    f: BinaryIO, connections: dict[int, tuple[str, str]], path: Path, pos: int, warnings: list[str]
) -> Iterator[RawMessage]:
    while True:
        try:
            header, data = _read_record(f)
        except EOFError:
            return
        op = header.get("op", b"\xff")[0]
        if op == 0x07:
            _add_connection(connections, header, data)
        elif op == 0x02:
            conn = struct.unpack("<I", header["conn"])[0]
            if conn not in connections:
                warnings.append(f"{path}: message in chunk at byte {pos} has unknown connection {conn}")
                continue
            sec, nsec = struct.unpack("<II", header["time"])
            topic, msgtype = connections[conn]
            yield RawMessage(topic, msgtype, sec * 1_000_000_000 + nsec, data)


def _add_connection(connections: dict[int, tuple[str, str]], header: dict[str, bytes], data: bytes) -> None:
    fields = _parse_header(data)
    ros1_type = fields.get("type", b"").decode()
    package, _, name = ros1_type.partition("/")
    connections[struct.unpack("<I", header["conn"])[0]] = (
        header["topic"].decode(), f"{package}/msg/{name}"
    )


def _read_record(f: BinaryIO) -> tuple[dict[str, bytes], bytes]:
    """One record: (header fields, data). EOFError when the file ends inside it."""
    header = _parse_header(_read_sized(f))
    return header, _read_sized(f)


def _read_sized(f: BinaryIO) -> bytes:
    size_bytes = f.read(4)
    if len(size_bytes) < 4:
        raise EOFError
    (size,) = struct.unpack("<I", size_bytes)
    data = f.read(size)
    if len(data) < size:
        raise EOFError
    return data


def _parse_header(buf: bytes) -> dict[str, bytes]:
    """A record header: a sequence of (uint32 length, b"name=value") fields."""
    fields: dict[str, bytes] = {}
    pos = 0
    while pos + 4 <= len(buf):
        (size,) = struct.unpack_from("<I", buf, pos)
        name, _, value = buf[pos + 4 : pos + 4 + size].partition(b"=")
        fields[name.decode(errors="replace")] = value
        pos += 4 + size
    return fields


def _decompress(compression: str, data: bytes) -> bytes:
    if compression == "none":
        return data
    if compression == "bz2":
        return bz2.decompress(data)
    if compression == "lz4":
        from lz4.frame import decompress  # rosbags depends on lz4

        return bytes(decompress(data))
    raise ValueError(f"compression {compression!r} is not supported")


# --- decoding the robot's messages -------------------------------------------------------


class _Decoder:
    """Turns raw messages into pico_studio's data types, skipping bad ones with a warning."""

    def __init__(self, path: Path, topics: TopicParams, replay: ReplayParams, warnings: list[str]):
        self.path = path
        self.topics = topics
        self.replay = replay
        self.warnings = warnings

    def all(self, by_topic: dict[str, list[RawMessage]], topic: str, msgtype: str, convert: Any) -> list:
        msgs = by_topic.get(topic, [])
        if msgs and msgs[0].msgtype != msgtype:
            self.warnings.append(
                f"{self.path}: topic {topic} holds {msgs[0].msgtype}, expected {msgtype}; ignored"
            )
            return []
        out = []
        for i, m in enumerate(msgs):
            where = f"{self.path}: message {i} on {topic}"
            try:
                msg = _TYPESTORE.deserialize_ros1(m.data, m.msgtype)
            except Exception as e:  # noqa: BLE001 - any decoding failure means a corrupt message
                self.warnings.append(f"{where}: cannot be decoded ({type(e).__name__}: {e}); skipped")
                continue
            item = convert(msg, _stamp(msg, m.time_ns), where)
            if item is not None:
                out.append(item)
        return out

    def laser(self, msg: Any, t: float, where: str) -> LaserData | None:
        ranges = np.asarray(msg.ranges, dtype=float)
        n = len(ranges)
        a0, a1, inc = float(msg.angle_min), float(msg.angle_max), float(msg.angle_increment)
        problem = beam_layout_problem(n, a0, a1, inc, self.replay)
        if problem is not None:
            field, text = problem
            self.warnings.append(f"{where}: {field}: {text}; scan skipped")
            return None
        return LaserData(
            range_min=float(msg.range_min), range_max=float(msg.range_max),
            angle_min=a0, angle_max=a1, angle_increment=inc, timestamp=t, ranges=ranges,
        )

    def odometry(self, msg: Any, t: float, where: str) -> OdometryData | None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        values = (p.x, p.y, q.x, q.y, q.z, q.w)
        if not all(math.isfinite(v) for v in values):
            self.warnings.append(f"{where}: pose.pose: not finite {values}; skipped")
            return None
        return OdometryData(float(p.x), float(p.y), yaw_from_quaternion(q.x, q.y, q.z, q.w), t)

    def twist(self, msg: Any, t: float, where: str) -> BaseReference | None:
        return BaseReference(float(msg.linear.x), float(msg.linear.y), float(msg.angular.z), t)

    def pose(self, msg: Any, t: float, where: str) -> TimedPose | None:
        p, q = msg.pose.position, msg.pose.orientation
        return TimedPose(t, (float(p.x), float(p.y), yaw_from_quaternion(q.x, q.y, q.z, q.w)))


def _stamp(msg: Any, time_ns: int) -> float:
    """The header stamp in seconds where the message has a non-zero one, else the bag time."""
    header = getattr(msg, "header", None)
    if header is not None and (header.stamp.sec or header.stamp.nanosec):
        return (header.stamp.sec * 1_000_000_000 + header.stamp.nanosec) / 1e9
    return time_ns / 1e9
