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
read by walking its chunks from the start, as `rosbag reindex` would: a damaged record in a
chunk (a header field missing or of the wrong size, a length past the end) is skipped, a
chunk that cannot be decompressed or whose framing is lost is skipped to the next chunk
header, each with a warning naming the byte offset; a message that cannot be decoded, or a
scan whose angle fields disagree with its beam count, is skipped with a warning naming the
file, the message index and the field. The replay goes on with what is left. The file must
be a regular file within the recording size cap (`user_files`), and a chunk decompresses to
at most the size its header declares.
"""

from __future__ import annotations

import bz2
import io
import math
import struct
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any

import numpy as np
from rosbags.rosbag1 import Reader
from rosbags.typesys import Stores, get_typestore

from pico_studio.config.sources_params import ReplayParams, SourcesParams, TopicParams
from pico_studio.core.io import BaseReference, LaserData, OdometryData
from pico_studio.errors import SourceError
from pico_studio.sources.convert import beam_layout_problem, yaw_from_quaternion
from pico_studio.sources.replay import Recording, Replay, TimedPose
from pico_studio.user_files import check_file, limits, open_file

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
    if not path.exists():
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
_CHUNK_OP = b"\x04\x00\x00\x00op=\x05"  # the "op=5" field of a chunk record's header
_RESYNC_WINDOW = 1 << 20  # bytes read at a time while looking for the next chunk
MAX_LISTED_WARNINGS = 100  # damaged records listed; the rest are counted


class _Damaged(Exception):
    """A record whose framing or header fields are unusable."""


def _read_messages(path: Path, warnings: list[str]) -> tuple[list[RawMessage], dict[str, Any]]:
    """All messages of the bag: through its index, or by walking its chunks when the index
    is missing or damaged."""
    check_file(path, SourceError, "recording")
    with open_file(path, SourceError, "recording") as f:
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
    except Exception as e:  # noqa: BLE001 - rosbags fails on damage in many ways (KeyError, AssertionError, ...): walk instead
        walker = _ChunkWalker(path)
        messages = list(walker.messages())
        warnings.extend(walker.report())
        warnings.append(
            f"{path}: the bag's index is unusable ({type(e).__name__}: {e}); recovered "
            f"{len(messages)} messages by reading its chunks in order"
        )
        return messages, {"indexed": False}


class _ChunkWalker:
    """Messages of a bag read record by record from the start, without its index, as
    `rosbag reindex` would. A damaged record inside a chunk is skipped (its framing still
    gives the next one); a chunk whose framing is lost, or that cannot be decompressed, is
    skipped to the next chunk header found after it. Every skip is a warning naming the byte
    offset in the file."""

    def __init__(self, path: Path):
        self.path = path
        self.size = path.stat().st_size
        self.connections: dict[int, tuple[str, str]] = {}
        self.problems: list[str] = []
        self.unlisted = 0

    def warn(self, text: str) -> None:
        if len(self.problems) < MAX_LISTED_WARNINGS:
            self.problems.append(f"{self.path}: {text}")
        else:
            self.unlisted += 1

    def report(self) -> list[str]:
        more = [f"{self.path}: {self.unlisted} more damaged records skipped"] if self.unlisted else []
        return self.problems + more

    def messages(self) -> Iterator[RawMessage]:
        with open_file(self.path, SourceError, "recording") as f:
            pos = len(_MAGIC)
            while pos < self.size:
                f.seek(pos)
                try:
                    header, data = _read_record(f, self.size - pos)
                    op = _field(header, "op", 1)[0]
                except EOFError:
                    self.warn(f"file ends inside the record at byte {pos}")
                    return
                except _Damaged as e:
                    found = _find_chunk(f, pos + 1, self.size)
                    if found is None:  # truncated, as a recorder that died leaves it, or damaged
                        self.warn(f"file ends inside the record at byte {pos} ({e}), or it is damaged")
                        return
                    self.warn(f"record at byte {pos} is damaged ({e}); resumed at the chunk at byte {found}")
                    pos = found
                    continue
                next_pos = f.tell()
                if op == 0x05:  # chunk
                    yield from self._chunk(header, data, pos)
                elif op == 0x07:  # connection record outside a chunk (after the index)
                    self._connection(header, data, pos)
                pos = next_pos

    def _chunk(self, header: dict[str, bytes], data: bytes, pos: int) -> Iterator[RawMessage]:
        try:
            chunk = _decompress(header, data)
        except (_Damaged, OSError, ValueError, EOFError, RuntimeError) as e:
            self.warn(f"chunk at byte {pos} cannot be decompressed ({e}); chunk skipped")
            return
        f = io.BytesIO(chunk)
        while f.tell() < len(chunk):
            inner = f.tell()
            where = f"record at byte {inner} of the chunk at byte {pos}"
            try:
                rec_header, rec_data = _read_record(f, len(chunk) - inner)
                op = _field(rec_header, "op", 1)[0]
            except (EOFError, _Damaged) as e:
                self.warn(f"{where}: framing lost ({e or 'ends early'}); rest of the chunk skipped")
                return
            try:
                if op == 0x07:
                    self._connection(rec_header, rec_data, pos)
                elif op == 0x02:
                    conn = struct.unpack("<I", _field(rec_header, "conn", 4))[0]
                    if conn not in self.connections:
                        self.warn(f"{where}: message has unknown connection {conn}; skipped")
                        continue
                    sec, nsec = struct.unpack("<II", _field(rec_header, "time", 8))
                    topic, msgtype = self.connections[conn]
                    yield RawMessage(topic, msgtype, sec * 1_000_000_000 + nsec, rec_data)
            except _Damaged as e:
                self.warn(f"{where}: {e}; skipped")

    def _connection(self, header: dict[str, bytes], data: bytes, pos: int) -> None:
        try:
            conn = struct.unpack("<I", _field(header, "conn", 4))[0]
            topic = _field(header, "topic").decode()
            ros1_type = _field(_parse_header(data), "type").decode()
        except (_Damaged, UnicodeDecodeError) as e:
            self.warn(f"connection record in/at byte {pos}: {e}; skipped")
            return
        package, _, name = ros1_type.partition("/")
        self.connections[conn] = (topic, f"{package}/msg/{name}")


def _field(header: dict[str, bytes], name: str, size: int | None = None) -> bytes:
    """A header field, `_Damaged` when it is missing or (with `size`) of the wrong length."""
    value = header.get(name)
    if value is None:
        raise _Damaged(f"header has no {name!r} field")
    if size is not None and len(value) != size:
        raise _Damaged(f"header field {name!r} has {len(value)} bytes, expected {size}")
    return value


def _find_chunk(f: IO[bytes], start: int, end: int) -> int | None:
    """Byte offset of the next well-formed chunk record header at or after `start`."""
    pos = start
    while pos < end:
        f.seek(pos)
        window = f.read(_RESYNC_WINDOW + 64)
        k = window.find(_CHUNK_OP)
        while k >= 0:
            # the record starts a little before its op field: its header length, then fields
            for back in range(4, 68, 1):
                c = pos + k - back
                if c < start:
                    break
                f.seek(c)
                try:
                    header, _ = _read_record(f, end - c)
                    if _field(header, "op", 1) == b"\x05":
                        return c
                except (EOFError, _Damaged):
                    continue
            k = window.find(_CHUNK_OP, k + 1)
        pos += _RESYNC_WINDOW
    return None


def _read_record(f: IO[bytes], remaining: int) -> tuple[dict[str, bytes], bytes]:
    """One record: (header fields, data). EOFError when the file ends inside it, `_Damaged`
    when a length cannot be right (beyond what is left, or a header that does not parse)."""
    head = _read_sized(f, remaining)
    header = _parse_header(head)
    return header, _read_sized(f, remaining - 4 - len(head))


def _read_sized(f: IO[bytes], remaining: int) -> bytes:
    size_bytes = f.read(4)
    if len(size_bytes) < 4:
        raise EOFError
    (size,) = struct.unpack("<I", size_bytes)
    if size > remaining - 4:  # truncated or damaged: the caller looks for a chunk after it
        raise _Damaged(f"a length of {size} bytes runs past the end")
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
        if pos + 4 + size > len(buf):
            raise _Damaged(f"header field at {pos} of {size} bytes runs past the header's {len(buf)}")
        name, eq, value = buf[pos + 4 : pos + 4 + size].partition(b"=")
        if not eq:
            raise _Damaged(f"header field at {pos} has no '='")
        fields[name.decode(errors="replace")] = value
        pos += 4 + size
    if pos != len(buf):
        raise _Damaged("header ends inside a field length")
    return fields


def _decompress(header: dict[str, bytes], data: bytes) -> bytes:
    """A chunk's records, decompressed to at most its declared `size` (a chunk claiming more
    than the recording cap, or inflating beyond its size, is damaged)."""
    compression = header.get("compression", b"none").decode(errors="replace")
    size = struct.unpack("<I", _field(header, "size", 4))[0] if "size" in header else len(data)
    if size > limits().recording_bytes:
        raise _Damaged(f"declares {size} bytes uncompressed")
    if compression == "none":
        return data
    if compression == "bz2":
        out = bz2.BZ2Decompressor().decompress(data, max_length=size + 1)
    elif compression == "lz4":
        from lz4.frame import LZ4FrameDecompressor  # rosbags depends on lz4

        out = bytes(LZ4FrameDecompressor().decompress(data, max_length=size + 1))
    else:
        raise ValueError(f"compression {compression!r} is not supported")
    if len(out) > size:
        raise _Damaged(f"inflates beyond its declared {size} bytes")
    return out


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
