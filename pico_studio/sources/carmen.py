"""Replay of CARMEN log files (plain text or gzip), such as the Radish data sets.

One message a line, the last three fields always `ipc_timestamp ipc_hostname logger_timestamp`:

    FLASER n r1 .. rn  x y theta  odom_x odom_y odom_theta  ipc_timestamp host logger_timestamp
    ODOM   x y theta tv rv accel                           ipc_timestamp host logger_timestamp

* FLASER: a front scan of `n` beams spread over the field of view (`cfg.sources.carmen`,
  180 degrees for the SICK lasers of these logs), centred on the robot's x axis:
  beam i at `-fov/2 + i * fov/n`. `x y theta` is the pose of the scan; in a *corrected*
  log it is the SLAM-corrected pose, which the replay offers as ground truth. Angles are
  wrapped to (-pi, pi] (the logs hold some just beyond pi).
* ODOM: the raw wheel odometry, used as the robot's odometry. In corrected logs an ODOM
  line follows each FLASER repeating its corrected pose, with timestamp 0 or garbage
  (6e-62, 2.79 in the middle of a run at 2683 s): it is not odometry, so an ODOM line with
  timestamp 0 or with exactly the pose of the scan line before it is ignored. ODOM stamps
  jitter against the log's order; a reading stamped after something logged later takes
  that earlier stamp, so the replay delivers odometry in the order it was logged. A log
  without other ODOM lines uses the FLASER's `odom_*` fields instead.
* ROBOTLASER1 (the newer CARMEN scan line) carries its own start angle, resolution and
  maximum range, and the robot pose, used like FLASER's.
* With `sources.carmen.pose_is_truth` off (raw, uncorrected logs, whose scan poses are
  odometry) the replay offers no ground truth.
* Anything else (PARAM, SYNC, NEFF, RLASER, TRUEPOS, comments) is ignored.

A line with the wrong number of fields or a field that is not a number is skipped with a
warning naming the file, line and field; a gzip file that ends early replays what was read.

Bounded reading (`user_files.FileLimits`): the log must be a regular file within the
recording size cap; a gzip log is decompressed as a stream and stops, with a warning, once
it grows beyond `decompressed_ratio` x its compressed size (at least `decompressed_floor_bytes`) —
a gzip bomb (1 GiB of zeros in 1 MB) is cut off after ~100 MB instead of filling memory; a
line longer than `line_bytes` is skipped unread. The first `MAX_LISTED_WARNINGS` skipped
lines are listed, the rest counted.
"""

from __future__ import annotations

import gzip
import math
import zlib
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from pico_studio.config.sources_params import CarmenParams, SourcesParams
from pico_studio.core.geometry import wrap_angle
from pico_studio.core.io import LaserData, OdometryData
from pico_studio.errors import SourceError
from pico_studio.sources.replay import Recording, Replay, TimedPose
from pico_studio.user_files import FileLimits, check_file, limits, open_file

_TAIL = 3  # ipc_timestamp ipc_hostname logger_timestamp
_ODOM_FIELDS = 1 + 6 + _TAIL
MAX_LISTED_WARNINGS = 100  # a log of junk has a bad line per line: list these, count the rest


class _BadLine(Exception):
    def __init__(self, field: str, problem: str):
        super().__init__(f"{field}: {problem}")


def open_carmen(path: str | Path, params: SourcesParams | None = None) -> Replay:
    """A `Replay` of the CARMEN log at `path`."""
    return Replay(read_carmen(path, params))


def read_carmen(path: str | Path, params: SourcesParams | None = None) -> Recording:
    """Decode the FLASER and ODOM lines of a CARMEN log into a `Recording`."""
    cfg = (params or SourcesParams()).carmen
    path = Path(path)
    if not path.exists():
        raise SourceError("no such CARMEN log file", file=path)
    warnings: list[str] = []
    skipped = 0
    scans: list[LaserData] = []
    truth: list[TimedPose] = []
    flaser_odometry: list[OdometryData] = []
    odometry: list[OdometryData] = []
    pose_copies = 0
    scans_before: list[int] = []
    last_pose_tokens: list[str] = []
    for number, line in _lines(path, warnings):
        tokens = line.split()
        if not tokens or tokens[0].startswith("#"):
            continue
        try:
            if tokens[0] in ("FLASER", "ROBOTLASER1"):
                parse = _flaser if tokens[0] == "FLASER" else _robotlaser
                scan, pose, odom = parse(tokens, cfg)
                last_pose_tokens = _pose_tokens(tokens)
                scans.append(scan)
                truth.append(TimedPose(scan.timestamp, pose))
                flaser_odometry.append(odom)
            elif tokens[0] == "ODOM":
                reading = _odom(tokens)
                if reading.timestamp == 0.0 or (truth and tokens[1:4] == last_pose_tokens):
                    pose_copies += 1
                else:
                    odometry.append(reading)
                    scans_before.append(len(scans))
        except _BadLine as e:
            skipped += 1
            if skipped <= MAX_LISTED_WARNINGS:
                warnings.append(f"{path}: line {number}: {tokens[0][:40]} {e}; line skipped")
    if skipped > MAX_LISTED_WARNINGS:
        warnings.append(f"{path}: {skipped - MAX_LISTED_WARNINGS} more damaged lines skipped")
    if not scans and not warnings:
        raise SourceError(
            "holds no FLASER or ROBOTLASER1 line: not a CARMEN log with front laser scans", file=path
        )
    odometry, restamped = _in_log_order(odometry, scans_before, scans)
    return Recording(
        name=str(path),
        scans=scans,
        odometry=odometry or flaser_odometry,
        truth=truth if cfg.pose_is_truth else [],
        warnings=warnings,
        info={
            "odometry_from": "ODOM lines" if odometry else "the scan lines' odometry",
            "truth_from": "the scan lines' pose" if cfg.pose_is_truth else None,
            "odom_pose_copies_ignored": pose_copies,
            "odom_stamps_moved_to_log_order": restamped,
        },
    )


def _lines(path: Path, warnings: list[str]) -> Iterator[tuple[int, str]]:
    """(line number, text) of a plain or gzip file, read as a bounded stream; a damaged
    gzip, or one that decompresses beyond its cap, ends the lines early with a warning."""
    lim = limits()
    size = check_file(path, SourceError, "recording")
    with open_file(path, SourceError, "recording") as raw:
        gzipped = raw.read(2) == b"\x1f\x8b"
        raw.seek(0)
        stream = gzip.GzipFile(fileobj=raw, mode="rb") if gzipped else raw
        cap = _decompressed_cap(size, lim) if gzipped else size + lim.line_bytes
        reader = _BoundedLines(stream, cap, lim.line_bytes)
        number = 0
        try:
            for number, line in enumerate(reader, start=1):  # noqa: B007 - number used after the loop
                if line is None:
                    warnings.append(f"{path}: line {number}: longer than {lim.line_bytes >> 20} MB; line skipped")
                    continue
                yield number, line.decode("utf-8", errors="replace")
        except (EOFError, OSError, zlib.error) as e:
            warnings.append(f"{path}: the file is damaged after line {number} ({e}); replaying what was read")
        if reader.over_cap:
            warnings.append(
                f"{path}: decompressed beyond {cap >> 20} MB ({lim.decompressed_ratio} x its "
                f"{size / (1 << 20):.1f} MB) after line {number}: not a plausible log (a gzip bomb?); "
                "replaying what was read (PICO_STUDIO_MAX_DECOMPRESSED_RATIO raises the cap)"
            )


def _decompressed_cap(size: int, lim: FileLimits) -> int:
    return min(lim.recording_bytes, max(lim.decompressed_floor_bytes, lim.decompressed_ratio * size))


class _BoundedLines:
    """Lines of a binary stream, at most `cap` bytes in all; a line longer than
    `line_bytes` is consumed in pieces and yielded as None."""

    def __init__(self, stream: Any, cap: int, line_bytes: int):
        self.stream, self.cap, self.line_bytes = stream, cap, line_bytes
        self.total = 0
        self.over_cap = False

    def _read(self) -> bytes:
        piece = self.stream.readline(self.line_bytes + 1)
        self.total += len(piece)
        if self.total > self.cap:
            self.over_cap = True
            return b""
        return piece

    def __iter__(self) -> Iterator[bytes | None]:
        while True:
            line = self._read()
            if not line:
                return
            if len(line) <= self.line_bytes or line.endswith(b"\n"):
                yield line
                continue
            while line and not line.endswith(b"\n"):  # the rest of an overlong line
                line = self._read()
            yield None
            if self.over_cap:
                return


def _flaser(tokens: list[str], cfg: CarmenParams) -> tuple[LaserData, tuple[float, float, float], OdometryData]:
    n = _number(tokens, 1, "num_readings")
    if n != int(n) or n < 1:
        raise _BadLine("num_readings", f"must be a positive whole number, got {tokens[1]!r}")
    n = int(n)
    expected = 2 + n + 6 + _TAIL
    if len(tokens) != expected:
        raise _BadLine(
            "fields", f"with num_readings {n} needs {expected} fields, found {len(tokens)}"
        )
    ranges = _numbers(tokens, 2, n, "range")
    x, y, theta, ox, oy, otheta = (
        _number(tokens, 2 + n + k, name)
        for k, name in enumerate(("x", "y", "theta", "odom_x", "odom_y", "odom_theta"))
    )
    t = _number(tokens, 2 + n + 6, "ipc_timestamp")
    increment = cfg.field_of_view / n
    angle_min = -cfg.field_of_view / 2
    scan = LaserData(
        range_min=cfg.range_min, range_max=cfg.range_max,
        angle_min=angle_min, angle_max=angle_min + (n - 1) * increment,
        angle_increment=increment, timestamp=t, ranges=ranges,
    )
    return scan, (x, y, wrap_angle(theta)), OdometryData(ox, oy, wrap_angle(otheta), t)


def _in_log_order(
    readings: list[OdometryData], scans_before: list[int], scans: list[LaserData]
) -> tuple[list[OdometryData], int]:
    """The readings re-stamped, where needed, so that time agrees with the log's order,
    and how many were: ODOM stamps jitter (a reading stamped 0.3 s before the one logged
    just ahead of it; one logged before a scan stamped after it). Sorting by them would
    make the odometry jump back and forth, so a reading takes the earliest stamp of
    anything logged after it (later readings and scans) when that is earlier than its own.
    `scans_before[i]` is how many scans were logged before reading i."""
    out = list(readings)
    changed = 0
    bound = math.inf
    for i in range(len(out) - 1, -1, -1):
        k = scans_before[i]
        if k < len(scans):
            bound = min(bound, scans[k].timestamp)
        if out[i].timestamp > bound:
            out[i] = OdometryData(out[i].x, out[i].y, out[i].a, bound, out[i].form)
            changed += 1
        bound = min(bound, out[i].timestamp)
    return out, changed


def _pose_tokens(tokens: list[str]) -> list[str]:
    """The x y theta fields of a scan line, as written (to spot ODOM copies of them)."""
    if tokens[0] == "FLASER":
        n = int(float(tokens[1]))
        return tokens[2 + n : 5 + n]
    n, m = int(float(tokens[8])), int(float(tokens[9 + int(float(tokens[8]))]))
    return tokens[13 + n + m : 16 + n + m]


def _robotlaser(tokens: list[str], cfg: CarmenParams) -> tuple[LaserData, tuple[float, float, float], OdometryData]:
    """ROBOTLASER1 laser_type start_angle field_of_view angular_resolution maximum_range
    accuracy remission_mode n r1..rn m e1..em laser_x laser_y laser_theta robot_x robot_y
    robot_theta tv rv forward_safety_dist side_safety_dist turn_axis timestamp host logger_timestamp

    The angles are in the line itself; the robot pose is the pose (truth in a corrected
    log, else odometry) and, without ODOM lines, the odometry."""
    n = _count(tokens, 8, "num_readings")
    if n < 1:
        raise _BadLine("num_readings", "must be at least 1")
    m = _count(tokens, 9 + n, "num_remissions")
    expected = 10 + n + m + 6 + 5 + _TAIL
    if len(tokens) != expected:
        raise _BadLine(
            "fields", f"with num_readings {n} and num_remissions {m} needs {expected} fields, found {len(tokens)}"
        )
    start, increment, range_max = (_number(tokens, k, name) for k, name in (
        (2, "start_angle"), (4, "angular_resolution"), (5, "maximum_range")))
    ranges = _numbers(tokens, 9, n, "range")
    k = 10 + n + m
    x, y, theta = (_number(tokens, k + 3 + j, name) for j, name in enumerate(("robot_x", "robot_y", "robot_theta")))
    t = _number(tokens, k + 11, "timestamp")
    scan = LaserData(
        range_min=cfg.range_min, range_max=range_max, angle_min=start,
        angle_max=start + (n - 1) * increment, angle_increment=increment, timestamp=t, ranges=ranges,
    )
    return scan, (x, y, wrap_angle(theta)), OdometryData(x, y, wrap_angle(theta), t)


def _count(tokens: list[str], index: int, field: str) -> int:
    value = _number(tokens, index, field)
    if value != int(value) or value < 0:
        raise _BadLine(field, f"must be a whole number, got {tokens[index]!r}")
    return int(value)


def _odom(tokens: list[str]) -> OdometryData:
    if len(tokens) != _ODOM_FIELDS:
        raise _BadLine("fields", f"needs {_ODOM_FIELDS} fields, found {len(tokens)}")
    x, y, theta = (_number(tokens, k, name) for k, name in ((1, "x"), (2, "y"), (3, "theta")))
    return OdometryData(x, y, wrap_angle(theta), _number(tokens, 7, "ipc_timestamp"))


def _number(tokens: list[str], index: int, field: str) -> float:
    try:
        value = float(tokens[index])
    except (ValueError, IndexError):
        got = repr(tokens[index]) if index < len(tokens) else "nothing"
        raise _BadLine(field, f"must be a number, got {got}") from None
    if not math.isfinite(value):
        raise _BadLine(field, f"must be finite, got {tokens[index]!r}")
    return value


def _numbers(tokens: list[str], start: int, n: int, field: str) -> np.ndarray:
    """tokens[start:start+n] as floats in one go; the first bad one named when it fails."""
    try:
        values = np.array(tokens[start : start + n], dtype=float)
    except ValueError:
        values = np.array([_number(tokens, start + i, f"{field}[{i}]") for i in range(n)])
    bad = np.flatnonzero(~np.isfinite(values))
    if len(bad):
        raise _BadLine(f"{field}[{bad[0]}]", f"must be finite, got {tokens[start + bad[0]]!r}")
    return values

