"""Hypothesis fuzzing of the recording readers: CARMEN logs made of any mix of good, broken
and junk lines (plain and gzip, whole and cut), and bags with any bytes changed, give a
`Recording` (damage skipped with warnings) or a `SourceError` — never another exception.
Seeded (`derandomize=True`) and bounded."""

from __future__ import annotations

import gzip
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pico_studio.core.io import LaserData, OdometryData
from pico_studio.errors import SourceError
from pico_studio.sources.bag import read_bag
from pico_studio.sources.carmen import read_carmen
from pico_studio.sources.recorder import BagRecorder
from pico_studio.sources.replay import Recording

FUZZ = settings(derandomize=True, max_examples=80, deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

tokens = st.one_of(
    st.sampled_from(["FLASER", "ODOM", "ROBOTLASER1", "PARAM", "#", "nan", "inf", "-inf", "1e308", "host", "0", "180"]),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-5, 400).map(str),
    st.text(alphabet="abc\x00\xff\t", max_size=4),
)


def _good_flaser(t: float, n: int = 8) -> str:
    return f"FLASER {n} {' '.join(['1.5'] * n)} 1 2 0.1 1 2 0.1 {t} host {t}"


lines = st.one_of(
    st.lists(tokens, max_size=14).map(" ".join),
    st.floats(0, 100).map(_good_flaser),
    st.floats(0, 100).map(lambda t: f"ODOM 1 2 0.1 0 0 0 {t} host {t}"),
)


def _check(read, path: Path) -> None:
    try:
        rec = read(path)
    except SourceError as e:
        assert len(str(e)) < 5000
        return
    assert isinstance(rec, Recording)
    assert all(np.isfinite(s.timestamp) for s in rec.scans)
    assert len(rec.warnings) <= 200  # listed, then counted


@FUZZ
@given(st.lists(lines, max_size=30), st.sampled_from(["plain", "gzip", "gzip-cut"]))
def test_any_carmen_log_is_a_recording_or_a_source_error(tmp_path: Path, log: list[str], form: str) -> None:
    body = ("\n".join(log) + "\n").encode("utf-8", errors="replace")
    path = tmp_path / "fuzz.log"
    if form == "plain":
        path.write_bytes(body)
    else:
        z = gzip.compress(body)
        path.write_bytes(z if form == "gzip" else z[: max(3, len(z) * 2 // 3)])
    _check(read_carmen, path)


@pytest.fixture(scope="module")
def small_bag(tmp_path_factory: pytest.TempPathFactory) -> bytes:
    """A bag of 12 scans and odometry readings in several chunks."""
    path = tmp_path_factory.mktemp("bag") / "small.bag"
    with BagRecorder(path) as rec:
        rec._writer.chunk_threshold = 2_000
        for i in range(12):
            t = 1.0 + 0.1 * i
            rec.record_laser(LaserData(0.01, 10.0, -1.0, 1.0, 0.5, t, np.full(5, 2.0)))
            rec.record_odometry(OdometryData(0.1 * i, 0.0, 0.0, t))
    return path.read_bytes()


@FUZZ
@given(st.data())
def test_any_damaged_bag_is_a_recording_or_a_source_error(tmp_path: Path, small_bag: bytes, data: st.DataObject) -> None:
    b = bytearray(small_bag)
    for _ in range(data.draw(st.integers(1, 6))):
        i = data.draw(st.integers(13, len(b) - 1))
        if data.draw(st.booleans()):
            b[i] = data.draw(st.integers(0, 255))
        else:  # a run of junk: lengths and fields of a record
            n = data.draw(st.integers(1, 16))
            b[i : i + n] = data.draw(st.binary(min_size=n, max_size=n))
    if data.draw(st.booleans()):
        b = b[: data.draw(st.integers(13, len(b)))]
    path = tmp_path / "fuzz.bag"
    path.write_bytes(bytes(b))
    _check(read_bag, path)
