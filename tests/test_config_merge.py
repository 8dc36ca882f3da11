"""An import merges over the current (tuned) values and says what it changed."""

from __future__ import annotations

import pytest

from pico_studio.config import Config, get_value, load_config, merge_config, with_value
from pico_studio.errors import ConfigError


def _tuned() -> Config:
    cfg = with_value(Config(), "perception.scan.min_range", 0.2)
    return with_value(cfg, "perception.merge.connect_radius", 0.3)


def test_partial_import_keeps_every_tuned_value_it_leaves_out() -> None:
    tuned = _tuned()
    merged = merge_config(tuned, "perception:\n  scan:\n    max_range: 7.5\n", file="part.yaml")
    cfg = merged.config
    assert get_value(cfg, "perception.scan.max_range") == 7.5
    # the two tuned values survive (before the merge existed they went back to the defaults)
    assert get_value(cfg, "perception.scan.min_range") == 0.2
    assert get_value(cfg, "perception.merge.connect_radius") == 0.3
    assert [(c.path, c.old, c.new) for c in merged.changed] == [
        ("perception.scan.max_range", get_value(Config(), "perception.scan.max_range"), 7.5)
    ]


def test_a_value_equal_to_the_current_one_is_no_change() -> None:
    merged = merge_config(_tuned(), "perception:\n  scan:\n    min_range: 0.2\n")
    assert merged.changed == []
    assert merged.config == _tuned()


def test_an_empty_file_changes_nothing() -> None:
    merged = merge_config(_tuned(), "")
    assert merged.config == _tuned() and merged.changed == []


def test_a_bad_value_is_refused_naming_file_and_field() -> None:
    with pytest.raises(ConfigError) as e:
        merge_config(_tuned(), "perception:\n  scan:\n    max_range: -3\n", file="bad.yaml")
    assert "bad.yaml" in str(e.value) and "perception.scan.max_range" in str(e.value)
    with pytest.raises(ConfigError, match="did you mean"):
        merge_config(_tuned(), "perception:\n  scan:\n    max_rnage: 3\n", file="bad.yaml")
    with pytest.raises(ConfigError, match="mapping"):
        merge_config(_tuned(), "perception: 3\n", file="bad.yaml")
    with pytest.raises(ConfigError, match="mapping"):
        merge_config(_tuned(), "- 1\n- 2\n", file="bad.yaml")


def test_cross_field_rules_see_the_merged_values() -> None:
    # door_min_width must stay below door_max_width: a file setting only the minimum is
    # judged against the current (tuned) maximum, not the default one
    cfg = with_value(Config(), "perception.identify.door_max_width", 1.0)
    with pytest.raises(ConfigError, match="door_min_width"):
        merge_config(cfg, "perception:\n  identify:\n    door_min_width: 1.05\n")
    ok = merge_config(Config(), "perception:\n  identify:\n    door_min_width: 1.05\n")
    assert get_value(ok.config, "perception.identify.door_min_width") == 1.05


def test_the_cli_load_is_the_same_merge_over_the_defaults(tmp_path) -> None:
    f = tmp_path / "part.yaml"
    f.write_text("perception:\n  scan:\n    max_range: 7.5\n", encoding="utf-8")
    assert load_config(f) == merge_config(Config(), f.read_text()).config
