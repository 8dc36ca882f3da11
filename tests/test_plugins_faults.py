"""User code that raises on a frame: a warning in that frame's world model, the built-in
fallback (or an empty model), and the next frame runs again — the loop never dies."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from perception_scenes import SQUARE, scan_of
from plugin_helpers import unload_all, write_plugin

from pico_studio import plugins
from pico_studio.config import Config, with_value
from pico_studio.core.behaviours.registry import make_behaviour
from pico_studio.core.io import STOP
from pico_studio.core.perception import Perceptor, PerceptorState, perceive

FAULTY = """
    from dataclasses import dataclass
    import numpy as np
    from pico_studio.core.world_model import WorldModel
    from pico_studio.plugins import behaviour, door_detector, emit, param, perceptor, segmenter, warn

    @dataclass(frozen=True)
    class Switch:
        fail: bool = param(True, help="raise on every frame")

    @segmenter("flaky_split", Switch)
    def flaky_split(points, params):
        if params.fail:
            raise RuntimeError("segmenter bug")
        emit("my_points", points[:3])
        warn("flaky_split ran")
        return [(0, len(points) - 1)]

    @door_detector("flaky_doors", Switch)
    def flaky_doors(world_model, params):
        if params.fail:
            raise KeyError("door bug")
        return np.array([[0.0, 0.0, 1.0, 0.0]])

    @perceptor("flaky_perceptor", Switch)
    class FlakyPerceptor:
        def __init__(self, params):
            self.params = params
            self.frames = 0

        def step(self, laser, odometry):
            self.frames += 1
            if self.params.fail:
                raise ZeroDivisionError("perceptor bug")
            wm = WorldModel(time=laser.timestamp, pose=(0.0, 0.0, 0.0), zero_pose=None)
            wm.room = {{"frames": self.frames}}
            return wm

    @behaviour("flaky_drive", Switch)
    class FlakyDrive:
        state = "driving"

        def __init__(self, params):
            self.params = params

        def step(self, world_model, laser, odometry, now, *, ok=True):
            if self.params.fail:
                raise ValueError("behaviour bug")
            from pico_studio.core.io import Command
            return Command(0.2)
"""


@pytest.fixture(autouse=True)
def _faulty(tmp_path: Path):
    unload_all()
    plugins.load_plugin(str(write_plugin(tmp_path, "faulty.py", FAULTY.replace("{{", "{").replace("}}", "}"))))
    yield
    unload_all()


def _laser(t: float = 0.0):
    return dataclasses.replace(scan_of(SQUARE, (0.3, -0.2, 0.4), noise=0.0, seed=0), timestamp=t)


def _cfg(**values: object) -> Config:
    cfg = Config()
    for path, value in values.items():
        cfg = with_value(cfg, path.replace("__", "."), value)
    return cfg


def test_a_raising_segmenter_gives_split_and_merges_walls_and_a_warning() -> None:
    builtin, _ = perceive(PerceptorState.initial(), _laser(), None, Config().perception)
    cfg = _cfg(perception__scan__segmenter="flaky_split")
    wm, state = perceive(PerceptorState.initial(), _laser(), None, cfg.perception)
    assert any("segmenter 'flaky_split' failed on this frame (RuntimeError: segmenter bug)" in w for w in wm.warnings)
    np.testing.assert_allclose(wm.current_map, builtin.current_map)
    assert state.time == 0.0 and len(wm.local_map.walls) > 0


def test_a_working_segmenter_warns_and_emits_into_its_frame_only() -> None:
    cfg = _cfg(perception__scan__segmenter="flaky_split", perception__plugins__flaky_split__fail=False)
    wm, _ = perceive(PerceptorState.initial(), _laser(), None, cfg.perception)
    assert "flaky_split ran" in wm.warnings
    assert wm.extras["my_points"].shape == (3, 2)
    again, _ = perceive(PerceptorState.initial(), _laser(), None, Config().perception)
    assert again.extras == {} and "flaky_split ran" not in again.warnings


def test_a_raising_door_detector_keeps_the_builtin_doors() -> None:
    builtin, _ = perceive(PerceptorState.initial(), _laser(), None, Config().perception)
    wm, _ = perceive(PerceptorState.initial(), _laser(), None,
                     _cfg(perception__identify__door_detector="flaky_doors").perception)
    assert any("door detector 'flaky_doors' failed" in w and "KeyError" in w for w in wm.warnings)
    np.testing.assert_array_equal(wm.doors, builtin.doors)
    fixed = _cfg(perception__identify__door_detector="flaky_doors", perception__plugins__flaky_doors__fail=False)
    wm, _ = perceive(PerceptorState.initial(), _laser(), None, fixed.perception)
    assert wm.doors.tolist() == [[0.0, 0.0, 1.0, 0.0]] and "door_detector" in wm.timings_ms


def test_a_raising_perceptor_gives_an_empty_model_with_a_warning_and_keeps_going() -> None:
    p = Perceptor(_cfg(perception__perceptor="flaky_perceptor").perception)
    for t in range(3):
        wm = p.step(_laser(0.1 * t), None)
        assert len(wm.current_map) == 0
        assert any("perceptor 'flaky_perceptor' failed on this frame (ZeroDivisionError" in w for w in wm.warnings)
    p.params = _cfg(perception__perceptor="flaky_perceptor", perception__plugins__flaky_perceptor__fail=False).perception
    assert [p.step(_laser(1.0 + t), None).room["frames"] for t in range(3)] == [1, 2, 3]


def test_a_plugin_perceptor_is_pure_the_state_before_a_frame_reprocesses_it_the_same() -> None:
    params = _cfg(perception__perceptor="flaky_perceptor", perception__plugins__flaky_perceptor__fail=False).perception
    _, s1 = perceive(PerceptorState.initial(), _laser(0.0), None, params)
    wm_a, _ = perceive(s1, _laser(0.1), None, params)
    wm_b, _ = perceive(s1, _laser(0.1), None, params)  # the same frame again, from the same state
    assert wm_a.room == wm_b.room == {"frames": 2}


def test_a_raising_behaviour_stops_with_a_warning_and_tries_again_next_tick() -> None:
    cfg = Config()
    b = make_behaviour("flaky_drive", cfg)
    wm, _ = perceive(PerceptorState.initial(), _laser(), None, cfg.perception)
    assert b.step(wm, None, None, 0.0, ok=True) == STOP
    assert any("behaviour 'flaky_drive' failed on this tick (ValueError: behaviour bug)" in w for w in wm.warnings)
    assert b.state.startswith("plugin failed")
    b.inner.params = with_value(cfg, "behaviour.plugins.flaky_drive.fail", False).behaviour.plugins.flaky_drive
    assert b.step(wm, None, None, 0.1, ok=True).vx == pytest.approx(0.2)
    assert b.state == "driving"


def test_the_session_loop_survives_a_plugin_segmenter_and_behaviour_that_always_raise() -> None:
    from sim_helpers import box_map

    from pico_studio.session import Session
    from pico_studio.sim import Simulator

    cfg = _cfg(perception__scan__segmenter="flaky_split")
    sim = Simulator(box_map(), initial_pose=(5.0, 5.0, 0.0))
    session = Session(sim, perceptor=Perceptor(cfg.perception), behaviour=make_behaviour("flaky_drive", cfg))
    frames = [session.tick(0.05) for _ in range(20)]
    models = [f.world_model for f in frames if f.world_model is not None]
    assert len(models) >= 15 and sim.ok()
    for wm in models:
        assert any("segmenter 'flaky_split' failed" in w for w in wm.warnings)
        assert any("behaviour 'flaky_drive' failed" in w for w in wm.warnings)
        assert len(wm.local_map.walls) >= 2  # split-and-merge's walls, as fallback
    assert all(f.command is None or f.command == STOP for f in frames)
