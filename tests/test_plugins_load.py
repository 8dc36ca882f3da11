"""Loading plugins: from a path, a module, an installed entry point; reload; refusals; errors."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest
from plugin_helpers import EXAMPLE, PLUGIN_PKG, install_dist_info, unload_all, write_plugin

from pico_studio import plugins
from pico_studio.cli import main
from pico_studio.config import Config, params
from pico_studio.core.behaviours.registry import BEHAVIOURS
from pico_studio.core.perception.plugin_hooks import DOOR_DETECTORS
from pico_studio.core.perception.segment import SEGMENTERS
from pico_studio.errors import PluginError


@pytest.fixture(autouse=True)
def _clean():
    unload_all()
    yield
    unload_all()


SEGMENTER = """
    from dataclasses import dataclass
    from pico_studio.plugins import param, segmenter

    @dataclass(frozen=True)
    class P:
        tol: float = param(0.1, lo=0.0, hi=1.0, help="tolerance")

    @segmenter("{name}", P)
    def run(points, params):
        return [(0, len(points) - 1)]
"""


def test_the_example_loads_from_its_path_with_all_three_stages() -> None:
    p = plugins.load_plugin(str(EXAMPLE))
    assert {(s.kind, s.name) for s in p.stages} == {
        ("segmenter", "chord_split"), ("door_detector", "gap_doors"), ("behaviour", "creep")}
    assert "chord_split" in SEGMENTERS and "gap_doors" in DOOR_DETECTORS and "creep" in BEHAVIOURS
    paths = {i.path for i in params(Config())}
    assert {"perception.plugins.chord_split.split", "perception.plugins.gap_doors.min_width",
            "behaviour.plugins.creep.speed"} <= paths
    assert plugins.load_plugin(str(EXAMPLE)) is p  # loading twice is a no-op
    plugins.unload(p.key)
    assert "chord_split" not in SEGMENTERS and "creep" not in BEHAVIOURS
    assert "perception.plugins.chord_split.split" not in {i.path for i in params(Config())}


def test_a_module_name_loads_and_an_installed_entry_point_is_found(tmp_path: Path, monkeypatch) -> None:
    site = tmp_path / "site"
    site.mkdir()
    install_dist_info(site, PLUGIN_PKG, "pico_plugin_example", "example")
    monkeypatch.syspath_prepend(str(site))
    found = plugins.load_entry_points()
    assert [p.origin for p in found] == ["entry point"]
    assert found[0].key == "pico_plugin_example"
    assert "whole_cluster" in SEGMENTERS
    spec = {i.path: i for i in params(Config())}["perception.plugins.whole_cluster.min_points"].spec
    assert spec.default == 3 and spec.lo == 2
    unload_all()
    assert plugins.load_plugin("pico_plugin_example").origin == "module"


def test_the_entry_point_plugin_shows_in_config_defaults_through_the_cli(tmp_path: Path, monkeypatch, capsys) -> None:
    site = tmp_path / "site"
    site.mkdir()
    install_dist_info(site, PLUGIN_PKG, "pico_plugin_example", "example")
    monkeypatch.syspath_prepend(str(site))
    monkeypatch.delenv("PICO_STUDIO_NO_ENTRY_POINTS", raising=False)
    assert main(["config", "defaults"]) == 0
    out = capsys.readouterr().out
    assert "whole_cluster:" in out and "min_points: 3" in out


def test_the_example_parameter_shows_in_config_defaults_with_plugin(capsys) -> None:
    assert main(["config", "defaults", "--plugin", str(EXAMPLE)]) == 0
    out = capsys.readouterr().out
    assert "chord_split:" in out
    assert "split: 0.04  # Split a piece where a point is farther than this from its chord [m]" in out
    assert "one of: split_merge, angle, ransac, chord_split" in out
    assert "speed: 0.3" in out  # the behaviour's, under behaviour.plugins.creep


def test_a_plugin_that_fails_to_import_is_one_line_naming_file_and_line(tmp_path: Path, capsys) -> None:
    bad = write_plugin(tmp_path, "bad.py", """
        import numpy as np

        x = 1
        raise RuntimeError("my plugin is broken")
    """)
    for command in (["config", "defaults"], ["serve", "--port", "1"], ["run"], ["eval", "--map", "x.json"]):
        assert main([*command, "--plugin", str(bad)]) == 2  # before the command starts anything
        err = capsys.readouterr().err.strip()
        assert err.count("\n") == 0
        assert f"{bad}:5" in err and "RuntimeError: my plugin is broken" in err


def test_a_syntax_error_names_its_line(tmp_path: Path) -> None:
    bad = write_plugin(tmp_path, "syntax.py", "x = 1\ndef broken(:\n    pass\n")
    with pytest.raises(PluginError) as e:
        plugins.load_plugin(str(bad))
    assert f"{bad}:2" in str(e.value) and "SyntaxError" in str(e.value)
    assert plugins.loaded() == []


def test_a_failed_import_leaves_nothing_registered(tmp_path: Path) -> None:
    half = write_plugin(tmp_path, "half.py", SEGMENTER.format(name="half_done") + "\nraise ValueError('late')\n")
    with pytest.raises(PluginError):
        plugins.load_plugin(str(half))
    assert "half_done" not in SEGMENTERS
    assert "perception.plugins.half_done.tol" not in {i.path for i in params(Config())}


@pytest.mark.parametrize(("kind", "name"), [("segmenter", "split_merge"), ("door_detector", "builtin"),
                                            ("perceptor", "builtin"), ("behaviour", "hospital")])
def test_a_name_clashing_with_a_builtin_is_refused(tmp_path: Path, kind: str, name: str) -> None:
    clash = write_plugin(tmp_path, f"clash_{kind}.py", f"""
        from pico_studio.plugins import {kind}

        @{kind}("{name}")
        def x(*args):
            return []
    """)
    with pytest.raises(PluginError) as e:
        plugins.load_plugin(str(clash))
    assert "clashes with a built-in" in str(e.value) and f"{clash}:4" in str(e.value)
    assert SEGMENTERS["split_merge"].__module__.startswith("pico_studio.core")
    assert plugins.loaded() == []


def test_another_plugins_name_is_refused(tmp_path: Path) -> None:
    a = write_plugin(tmp_path, "a.py", SEGMENTER.format(name="shared"))
    b = write_plugin(tmp_path, "b.py", SEGMENTER.format(name="shared"))
    plugins.load_plugin(str(a))
    with pytest.raises(PluginError) as e:
        plugins.load_plugin(str(b))
    assert "taken by the plugin" in str(e.value) and str(a) in str(e.value)


def test_reload_runs_the_edited_file_and_a_broken_edit_keeps_the_old_version(tmp_path: Path) -> None:
    path = write_plugin(tmp_path, "edit.py", SEGMENTER.format(name="editable"))
    p = plugins.load_plugin(str(path))
    pts = np.column_stack([np.linspace(0, 1, 10), np.zeros(10)])
    clusters = np.array([[0, 10]])
    assert SEGMENTERS["editable"](pts, clusters, Config().perception).tolist() == [[0, 9]]
    assert not p.changed()
    edited = SEGMENTER.format(name="editable").replace("[(0, len(points) - 1)]", "[(0, 4), (5, 9)]")
    write_plugin(tmp_path, "edit.py", edited.replace("param(0.1,", "param(0.2,"))
    os.utime(path, ns=(p.mtime + 10**9, p.mtime + 10**9))  # a later save, whatever the clock
    assert p.changed() and plugins.changed() == [p]
    plugins.reload(str(path))
    assert SEGMENTERS["editable"](pts, clusters, Config().perception).tolist() == [[0, 4], [5, 9]]
    assert Config().perception.plugins.editable.tol == 0.2
    path.write_text("raise ImportError('half saved')\n", encoding="utf-8")
    with pytest.raises(PluginError):
        plugins.reload(str(path))
    assert "half saved" in (p.error or "")
    assert SEGMENTERS["editable"](pts, clusters, Config().perception).tolist() == [[0, 4], [5, 9]]


def test_an_unknown_plugin_spec_is_a_plugin_error() -> None:
    with pytest.raises(PluginError):
        plugins.load_plugin("no_such_module_for_pico_studio")
    with pytest.raises(PluginError):
        plugins.load_plugin("/nonexistent/dir/plugin.py")
    assert "no_such_module_for_pico_studio" not in sys.modules


def test_params_of_a_plugin_not_loaded_say_so(tmp_path: Path, capsys) -> None:
    cfg = tmp_path / "c.yaml"
    cfg.write_text("perception:\n  plugins:\n    chord_split:\n      split: 0.1\n", encoding="utf-8")
    assert main(["config", "check", str(cfg)]) == 2
    err = capsys.readouterr().err
    assert "perception.plugins.chord_split: no plugin of that name is loaded (--plugin FILE.py)" in err
    assert main(["config", "check", str(cfg), "--plugin", str(EXAMPLE)]) == 0
    assert "perception.plugins.chord_split.split: 0.1" in capsys.readouterr().out


def test_the_cli_s_entry_point_group_is_the_plugins_one() -> None:
    from pico_studio.cli import plugin_args

    assert plugin_args.ENTRY_POINT_GROUP == plugins.ENTRY_POINT_GROUP
