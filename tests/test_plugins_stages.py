"""The adapters between a plugin's plain code and the pipeline: what each stage kind is handed,
what is done with what it returns, and the config's view of its parameters."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from perception_scenes import SQUARE, scan_of
from plugin_helpers import EXAMPLE, unload_all, write_plugin

from pico_studio import plugins
from pico_studio.config import Config, dump_yaml, loads_config, params, with_value
from pico_studio.core.geometry import transform_points
from pico_studio.core.io import OdometryData
from pico_studio.core.perception import PerceptorState, perceive
from pico_studio.core.perception.scan import process_scan
from pico_studio.errors import ConfigError

STAGES = """
    from dataclasses import dataclass
    import numpy as np
    from pico_studio.plugins import door_detector, emit, param, perceptor, segmenter
    from pico_studio.core.world_model import WorldModel

    SEEN = []

    @dataclass(frozen=True)
    class Halves:
        parts: int = param(2, lo=1, hi=8, help="pieces per cluster")

    @segmenter("halves", Halves)
    def halves(points, params):
        SEEN.append((len(points), params.parts))
        cuts = np.linspace(0, len(points) - 1, params.parts + 1).astype(int)
        emit("first_point", points[:1])  # robot frame
        # plus two sloppy pieces the adapter must drop: reversed, and past the cluster's end
        return [(a, b) for a, b in zip(cuts[:-1], cuts[1:])] + [(5, 2), (0, len(points) + 3)]

    @door_detector("one_more", mode="add")
    def one_more(world_model, params):
        return [[9.0, 9.0, 10.0, 9.0]]

    @dataclass(frozen=True)
    class Gain:
        gain: float = param(1.0, lo=0.0, hi=10.0, help="scale")

    @perceptor("echo", Gain)
    class Echo:
        def __init__(self, params):
            self.params = params

        def step(self, laser, odometry):
            wm = WorldModel(time=laser.timestamp, pose=(0.0, 0.0, 0.0), zero_pose=None)
            wm.room = {"gain": self.params.gain}
            return wm
"""


@pytest.fixture(autouse=True)
def _stages(tmp_path: Path):
    unload_all()
    plugins.load_plugin(str(write_plugin(tmp_path, "stages.py", STAGES)))
    yield
    unload_all()


def _laser():
    return scan_of(SQUARE, (0.3, -0.2, 0.4), noise=0.0, seed=0)


def _module():
    return next(m for m in __import__("sys").modules.values() if getattr(m, "SEEN", None) is not None
                and getattr(m, "halves", None) is not None)


def test_a_segmenter_gets_each_cluster_and_its_params_and_only_sound_pieces_are_kept() -> None:
    cfg = with_value(with_value(Config(), "perception.scan.segmenter", "halves"), "perception.plugins.halves.parts", 3)
    wm, _ = perceive(PerceptorState.initial(), _laser(), None, cfg.perception)
    seen = _module().SEEN
    assert seen and all(parts == 3 for _, parts in seen)
    assert 1 <= len(wm.current_map) <= 3 * len(seen)  # refit, merged, filtered as built-ins
    assert wm.warnings == []


def test_an_extra_in_the_robot_frame_lands_in_the_zero_frame() -> None:
    cfg = with_value(Config(), "perception.scan.segmenter", "halves")
    laser = _laser()
    _, state = perceive(PerceptorState.initial(), laser, OdometryData(1.0, 2.0, 0.3, 0.0), cfg.perception)
    laser = dataclasses.replace(laser, timestamp=0.1)
    wm, _ = perceive(state, laser, OdometryData(1.5, 2.0, 0.8, 0.1), cfg.perception)
    assert math.hypot(wm.pose[0], wm.pose[1]) > 0.3 and abs(wm.pose[2]) > 0.3  # moved and turned
    scan, _ = process_scan(laser, cfg.perception.scan, cfg.perception.proximity)
    last_cluster_first = scan.points[scan.clusters[-1, 0]][None, :]  # the last call's emit wins
    np.testing.assert_allclose(wm.extras["first_point"], transform_points(last_cluster_first, wm.pose), atol=1e-9)


def test_an_adding_door_detector_keeps_the_builtin_doors() -> None:
    builtin, _ = perceive(PerceptorState.initial(), _laser(), None, Config().perception)
    cfg = with_value(Config(), "perception.identify.door_detector", "one_more")
    wm, _ = perceive(PerceptorState.initial(), _laser(), None, cfg.perception)
    assert len(wm.doors) == len(builtin.doors) + 1
    assert wm.doors[-1].tolist() == [9.0, 9.0, 10.0, 9.0]


def test_a_plugin_perceptors_params_follow_the_slider() -> None:
    cfg = with_value(Config(), "perception.perceptor", "echo")
    wm, state = perceive(PerceptorState.initial(), _laser(), None, cfg.perception)
    assert wm.room == {"gain": 1.0}
    moved = with_value(cfg, "perception.plugins.echo.gain", 4.5)
    wm, _ = perceive(state, _laser(), None, moved.perception)
    assert wm.room == {"gain": 4.5}


def test_plugin_params_validate_round_trip_and_list_like_builtins() -> None:
    cfg = Config()
    infos = {p.path: p for p in params(cfg)}
    assert infos["perception.plugins.halves.parts"].spec.hi == 8
    with pytest.raises(ConfigError) as e:
        with_value(cfg, "perception.plugins.halves.parts", 99)
    assert e.value.field == "perception.plugins.halves.parts" and "out of range" in str(e.value)
    text = dump_yaml(with_value(cfg, "perception.plugins.echo.gain", 2.5))
    assert loads_config(text).perception.plugins.echo.gain == 2.5
    with pytest.raises(ConfigError) as e:
        loads_config("perception:\n  plugins:\n    halves:\n      partz: 2\n")
    assert "did you mean 'parts'" in str(e.value)
    spec = infos["perception.perceptor"].spec
    assert list(spec.choices or ()) == ["builtin", "echo"]


def test_rebase_carries_values_over_a_reload_and_drops_what_went() -> None:
    cfg = with_value(Config(), "perception.plugins.halves.parts", 5)
    key = plugins.loaded()[0].key
    Path(key).write_text(Path(key).read_text().replace("hi=8", "hi=4"), encoding="utf-8")
    plugins.reload(key)
    moved = plugins.rebase(cfg)
    assert moved.perception.plugins.halves.parts == 2  # 5 is out of the new range: the default
    cfg = with_value(moved, "perception.plugins.echo.gain", 3.0)
    plugins.unload(key)
    gone = plugins.rebase(cfg)
    assert gone.perception.plugins.get("echo") is None


def test_the_example_imports_and_runs_as_a_plain_module_too() -> None:
    unload_all()
    p = plugins.load_plugin(str(EXAMPLE))
    assert p.origin == "file" and len(p.stages) == 3
