"""Hypothesis fuzzing of the config loader: any YAML text, and any nested mapping over the
real keys with any values, give a `Config` or a `ConfigError` — never another exception.
Seeded (`derandomize=True`) and bounded."""

from __future__ import annotations

import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pico_studio.config import Config, loads_config, params
from pico_studio.errors import ConfigError

FUZZ = settings(derandomize=True, max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
PATHS = [p.path for p in params(Config())]

values = st.recursive(
    st.one_of(
        st.none(), st.booleans(), st.integers(-(10**40), 10**40), st.floats(allow_nan=True, allow_infinity=True),
        st.text(max_size=10), st.sampled_from(["split_merge", "ransac", "/pico/laser", "http://x:1"]),
    ),
    lambda inner: st.one_of(st.lists(inner, max_size=3), st.dictionaries(st.text(max_size=5), inner, max_size=3)),
    max_leaves=10,
)


def _load(text: str) -> None:
    try:
        cfg = loads_config(text, file="fuzz.yaml")
    except ConfigError as e:
        assert len(str(e)) < 2000  # one readable line, whatever the value was
        return
    assert isinstance(cfg, Config)


@FUZZ
@given(st.text(alphabet="abcdeimnps:.-_ \n\t[]{},&*!#'\"0123456789", max_size=200))
def test_any_yaml_text_is_a_config_or_a_config_error(text: str) -> None:
    _load(text)


@FUZZ
@given(st.lists(st.tuples(st.sampled_from(PATHS), values), min_size=1, max_size=6))
def test_real_keys_with_any_values_are_a_config_or_a_config_error(items: list[tuple[str, object]]) -> None:
    tree: dict = {}
    for path, value in items:
        *sections, name = path.split(".")
        node = tree
        for s in sections:
            node = node.setdefault(s, {}) if isinstance(node.get(s, {}), dict) else node
        node[name] = value
    try:
        text = yaml.safe_dump(tree)
    except yaml.YAMLError:
        return
    _load(text)


@FUZZ
@given(st.sampled_from(PATHS), values)
def test_duplicated_keys_are_refused_naming_the_line(a: str, value: object) -> None:
    section, _, key = a.rpartition(".")
    indent = "  " * section.count(".") if section else ""
    lines = []
    for depth, s in enumerate(section.split(".") if section else []):
        lines.append("  " * depth + f"{s}:")
    v = yaml.safe_dump(value, default_flow_style=True).strip().removesuffix("...").strip() or "null"
    body = f"{indent}  {key}: {v}" if section else f"{key}: {v}"
    text = "\n".join([*lines, body, body]) + "\n"
    try:
        loads_config(text, file="fuzz.yaml")
    except ConfigError as e:
        assert "duplicate key" in str(e) or "not valid YAML" in str(e), str(e)
        return
    raise AssertionError(f"a duplicated key was accepted:\n{text}")
