"""Hypothesis fuzzing of the map loader: any JSON value, any mutation of a valid map, any
bytes as a heightmap give a `GlobalMap` or a `MapError` — never another exception.
Seeded (`derandomize=True`) and bounded so CI is stable and quick."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pico_studio.errors import MapError
from pico_studio.json_map import load_map, map_from_dict
from pico_studio.json_map.model import GlobalMap
from pico_studio.user_files import parse_json

MAPS = Path(__file__).resolve().parents[1] / "examples" / "maps"
FUZZ = settings(derandomize=True, max_examples=150, deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

numbers = st.one_of(
    st.integers(-(10**30), 10**30), st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0, -1, 1, 2, 3, 1e308, -1e308, 10_001, 2**63]),
)
json_values = st.recursive(
    st.one_of(st.none(), st.booleans(), numbers, st.text(max_size=8)),
    lambda inner: st.one_of(st.lists(inner, max_size=5), st.dictionaries(st.text(max_size=6), inner, max_size=5)),
    max_leaves=30,
)
KEYS = ["points", "walls", "cabinets", "tables", "doors", "start_area", "finish", "x", "y"]


def _loads(m: object) -> None:
    try:
        out = map_from_dict(m, file="fuzz.json")
    except MapError:
        return
    assert isinstance(out, GlobalMap)
    assert np.isfinite(out.points).all() and (np.abs(out.points) <= 10_000).all()
    assert all(isinstance(w, str) for w in out.warnings)


@FUZZ
@given(json_values)
def test_any_json_value_is_a_map_or_a_map_error(value: object) -> None:
    _loads(value)


@FUZZ
@given(st.dictionaries(st.sampled_from(KEYS), json_values, max_size=6))
def test_any_object_with_map_keys_is_a_map_or_a_map_error(value: dict) -> None:
    _loads(value)


@FUZZ
@given(st.data())
def test_mutated_real_map_is_a_map_or_a_map_error(data: st.DataObject) -> None:
    m = json.loads((MAPS / "hospital_2019.json").read_text())
    for _ in range(data.draw(st.integers(1, 4))):
        key = data.draw(st.sampled_from([k for k in m if isinstance(m[k], list) and m[k]] or ["points"]))
        items = m.setdefault(key, [])
        if not items:
            continue
        i = data.draw(st.integers(0, len(items) - 1))
        items[i] = data.draw(json_values) if data.draw(st.booleans()) else _tweak(items[i], data)
    _loads(m)


def _tweak(item: object, data: st.DataObject) -> object:
    """Change one number inside an item (a point's coordinate, an index of a pair)."""
    if isinstance(item, dict) and item:
        k = data.draw(st.sampled_from(sorted(item)))
        return {**item, k: data.draw(numbers)}
    if isinstance(item, list) and item:
        j = data.draw(st.integers(0, len(item) - 1))
        return [*item[:j], data.draw(numbers), *item[j + 1 :]]
    return data.draw(numbers)


@FUZZ
@given(st.text(alphabet='[]{}",:0123456789.eE-+ \ntruefalsn', max_size=300))
def test_any_json_text_parses_or_is_a_map_error(text: str) -> None:
    try:
        parse_json(text, MapError, "fuzz.json")
    except MapError:
        pass


@FUZZ
@given(st.binary(max_size=400), st.sampled_from([".png", ".pgm"]))
def test_any_bytes_as_a_heightmap_are_a_map_or_a_map_error(tmp_path: Path, raw: bytes, suffix: str) -> None:
    prefix = {".png": b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR", ".pgm": b"P5\n"}[suffix]
    path = tmp_path / f"fuzz{suffix}"
    for body in (raw, prefix + raw):
        path.write_bytes(body)
        try:
            m = load_map(path)
        except MapError:
            continue
        assert isinstance(m, GlobalMap)
