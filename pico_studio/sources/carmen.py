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
  line with timestamp 0 follows each FLASER repeating the corrected pose: it has no time
  and is not odometry, so it is ignored. A log without timed ODOM lines uses the FLASER's
  `odom_*` fields instead.
* Anything else (PARAM, SYNC, NEFF, RLASER, TRUEPOS, comments) is ignored.

A line with the wrong number of fields or a field that is not a number is skipped with a
warning naming the file, line and field; a gzip file that ends early replays what was read.
"""

from __future__ import annotations

import gzip
import math
import zlib
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from pico_studio.core.config.sources_params import CarmenParams, SourcesParams
from pico_studio.core.io import LaserData, OdometryData
from pico_studio.errors import SourceError
from pico_studio.sources.replay import Recording, Replay, TimedPose

_TAIL = 3  # ipc_timestamp ipc_hostname logger_timestamp
_ODOM_FIELDS = 1 + 6 + _TAIL


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
    if not path.is_file():
        raise SourceError("no such CARMEN log file", file=path)
    warnings: list[str] = []
    scans: list[LaserData] = []
    truth: list[TimedPose] = []
    flaser_odometry: list[OdometryData] = []
    odometry: list[OdometryData] = []
    untimed_odom = 0
    for number, line in _lines(path, warnings):
        tokens = line.split()
        if not tokens or tokens[0].startswith("#"):
            continue
        try:
            if tokens[0] == "FLASER":
                scan, pose, odom = _flaser(tokens, cfg)
                scans.append(scan)
                truth.append(TimedPose(scan.timestamp, pose))
                flaser_odometry.append(odom)
            elif tokens[0] == "ODOM":
                reading = _odom(tokens)
                if reading.timestamp == 0.0:
                    untimed_odom += 1
                else:
                    odometry.append(reading)
        except _BadLine as e:
            warnings.append(f"{path}: line {number}: {tokens[0]} {e}; line skipped")
    if not scans and not warnings:
        raise SourceError("holds no FLASER line: not a CARMEN log with front laser scans", file=path)
    return Recording(
        name=str(path),
        scans=scans,
        odometry=odometry or flaser_odometry,
        truth=truth,
        warnings=warnings,
        info={
            "odometry_from": "ODOM lines" if odometry else "FLASER odom fields",
            "untimed_odom_lines_ignored": untimed_odom,
        },
    )


def _lines(path: Path, warnings: list[str]) -> Iterator[tuple[int, str]]:
    """(line number, text) of a plain or gzip file; a damaged gzip ends the lines early."""
    with path.open("rb") as f:
        gzipped = f.read(2) == b"\x1f\x8b"
    opener = gzip.open if gzipped else open
    number = 0
    try:
        with opener(path, "rt", encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, start=1):  # noqa: B007 - number used after the loop
                yield number, line
    except (EOFError, OSError, zlib.error) as e:
        warnings.append(f"{path}: the file is damaged after line {number} ({e}); replaying what was read")


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
    return scan, (x, y, _wrap(theta)), OdometryData(ox, oy, _wrap(otheta), t)


def _odom(tokens: list[str]) -> OdometryData:
    if len(tokens) != _ODOM_FIELDS:
        raise _BadLine("fields", f"needs {_ODOM_FIELDS} fields, found {len(tokens)}")
    x, y, theta = (_number(tokens, k, name) for k, name in ((1, "x"), (2, "y"), (3, "theta")))
    return OdometryData(x, y, _wrap(theta), _number(tokens, 7, "ipc_timestamp"))


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


def _wrap(a: float) -> float:
    """Wrap one angle to (-pi, pi] (the scalar twin of core.geometry.wrap_angle, which is
    vectorised and too slow called once per line)."""
    w = math.remainder(a, 2 * math.pi)
    return math.pi if w == -math.pi else w
