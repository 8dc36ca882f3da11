"""The config tree: declaration, YAML round trip, validation errors that name the field."""

from __future__ import annotations

import pytest

from pico_studio.cli import main
from pico_studio.config import (
    Config,
    dump_yaml,
    load_config,
    loads_config,
    params,
    to_dict,
    with_value,
)
from pico_studio.errors import ConfigError


def test_every_param_is_fully_declared() -> None:
    ps = params(Config())
    assert ps, "the tree declares parameters"
    for p in ps:
        assert p.spec.help, p.path
        if p.spec.kind in ("int", "float"):
            assert p.spec.lo is not None and p.spec.hi is not None, p.path
            assert p.spec.lo <= p.value <= p.spec.hi, p.path
            assert p.spec.step is not None and p.spec.step > 0, p.path


def test_yaml_round_trip_of_defaults_and_changes(tmp_path) -> None:
    cfg = with_value(Config(), "map.heightmap.resolution", 0.05)
    text = dump_yaml(cfg)
    assert "# Pixel size" in text and "[m/px]" in text
    again = loads_config(text)
    assert again == cfg
    assert to_dict(again)["map"]["heightmap"]["resolution"] == 0.05


def test_partial_file_merges_over_defaults(tmp_path) -> None:
    f = tmp_path / "partial.yaml"
    f.write_text("map:\n  heightmap:\n    min_speck_area: 9\n")
    cfg = load_config(f)
    assert cfg.map.heightmap.min_speck_area == 9
    assert cfg.map.heightmap.resolution == Config().map.heightmap.resolution


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("map:\n  heightmap:\n    resolutoin: 0.1\n", "map.heightmap.resolutoin: unknown key; did you mean 'resolution'?"),
        ("mapp: {}\n", "mapp: unknown key; did you mean 'map'?"),
        ("map:\n  heightmap:\n    resolution: 5\n", "map.heightmap.resolution: 5 is out of range; allowed 0.001 .. 1 m/px"),
        ("map:\n  heightmap:\n    resolution: .nan\n", "map.heightmap.resolution: must be a finite number"),
        ("map:\n  heightmap:\n    min_speck_area: 2.5\n", "map.heightmap.min_speck_area: must be a whole number"),
        ("map:\n  heightmap:\n    resolution: fast\n", "map.heightmap.resolution: must be a number"),
        ("map:\n  heightmap:\n    door_grey_low: 220\n", "map.heightmap.door_grey_low: must be below door_grey_high"),
        ("map: [1, 2]\n", "map: must be a mapping"),
        ("map: {heightmap: [\n", "not valid YAML at line 2"),
    ],
)
def test_bad_config_names_file_and_field(tmp_path, text: str, expected: str) -> None:
    f = tmp_path / "bad.yaml"
    f.write_text(text)
    with pytest.raises(ConfigError) as e:
        load_config(f)
    assert str(e.value).startswith(f"{f}: ")
    assert expected in str(e.value)


def test_an_old_file_with_moved_and_gone_parameters_still_loads(tmp_path) -> None:
    """A page export from before the map's openings moved names sim.truth.door_max_width and
    localisation.combined.jamb_confirm_distance: the value is read at map.openings, the gone
    key dropped, and a value given at the new place too wins. Given to from_dict directly (no
    file merge), the old key says where it went."""
    from pico_studio.config.io import from_dict

    f = tmp_path / "old.yaml"
    f.write_text("sim:\n  truth:\n    door_max_width: 1.2\n    jamb_reach: 0.4\n"
                 "localisation:\n  combined:\n    jamb_confirm_distance: 0.1\n")
    cfg = load_config(f)
    assert cfg.map.openings.door_max_width == 1.2 and cfg.sim.truth.jamb_reach == 0.4
    f.write_text("sim:\n  truth:\n    door_max_width: 1.2\nmap:\n  openings:\n    door_max_width: 1.1\n")
    assert load_config(f).map.openings.door_max_width == 1.1
    with pytest.raises(ConfigError, match="moved to map.openings.door_max_width"):
        from_dict(Config, {"sim": {"truth": {"door_max_width": 1.2}}})


def test_with_value_validates() -> None:
    with pytest.raises(ConfigError, match="out of range"):
        with_value(Config(), "map.heightmap.resolution", -1.0)
    with pytest.raises(ConfigError, match="did you mean 'map.heightmap.resolution'"):
        with_value(Config(), "map.heightmap.resolutio", 0.1)


def test_cli_defaults_and_check(tmp_path, capsys) -> None:
    assert main(["config", "defaults"]) == 0
    text = capsys.readouterr().out
    f = tmp_path / "defaults.yaml"
    f.write_text(text)
    assert main(["config", "check", str(f)]) == 0
    assert "OK (0 value(s) differ" in capsys.readouterr().out
    f.write_text("map:\n  heightmap:\n    resolution: 2\n")
    assert main(["config", "check", str(f)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "map.heightmap.resolution" in err and "Traceback" not in err
