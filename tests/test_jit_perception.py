"""Identify's compiled loops give the answers of their own Python (`.py_func`) on the very
arguments the perceptor passes them on real hospital_2019 scans (merge's: test_jit_merge.py)."""

from __future__ import annotations

import copy
import itertools
from typing import Any

import numpy as np
import pytest

from pico_studio import jit
from pico_studio.config import Config
from pico_studio.core.behaviours.registry import Drive
from pico_studio.core.perception import Perceptor, identify
from pico_studio.json_map import load_map
from pico_studio.session import Session
from pico_studio.sim import Simulator
from tests.conftest import MAPS
from tests.jit_scenes import hospital_frames, recorded_calls

KERNELS = {identify: ("ray_hits", "blocked_many", "door_pairs", "backed", "object_groups")}


@pytest.fixture(scope="module")
def calls() -> dict[str, list[tuple]]:
    """Every call of each kernel while a perceptor follows the robot turning on the spot
    for 12 frames at each of 6 free poses (so the local map fuses, merges and connects walls
    it has seen before, and walls drop out of view)."""
    with recorded_calls(KERNELS) as recorded:
        cfg = Config()
        gmap = load_map(MAPS / "hospital_2019.json")
        for first, _, _ in hospital_frames(6):
            sim = Simulator(gmap, cfg.sim, seed=0, initial_pose=first.truth.pose)
            session = Session(sim, behaviour=Drive(0.05, 0.0, 0.4))
            p = Perceptor(cfg.perception)
            for _ in itertools.islice(session.frames(dt=0.05), 12):
                p.step(session.last_laser, session.last_odometry)
    return recorded


ATOL: dict[str, float] = {}  # every kernel here is bit-exact


def _same(a: Any, b: Any, atol: float = 0.0) -> None:
    a, b = (a if isinstance(a, tuple) else (a,)), (b if isinstance(b, tuple) else (b,))
    assert len(a) == len(b)
    for x, y in zip(map(np.asarray, a), map(np.asarray, b), strict=True):
        assert x.dtype == y.dtype and x.shape == y.shape
        if atol and x.dtype.kind == "f":
            np.testing.assert_allclose(x, y, rtol=0, atol=atol)
        else:
            np.testing.assert_array_equal(x, y)  # the same floats, to the last bit


@pytest.mark.parametrize("module,name", [(m, n) for m, names in KERNELS.items() for n in names])
def test_kernel_equals_its_python_on_real_scans(calls: dict[str, list[tuple]], module: Any, name: str):
    kernel = getattr(module, name)
    assert calls[name], f"{name} was never called on the hospital scans"
    answered = 0
    for args in calls[name]:
        mine, theirs = copy.deepcopy(args), copy.deepcopy(args)  # connect_walk, fuse move their inputs
        got = kernel(*mine)
        atol = ATOL.get(name, 0.0)
        _same(got, jit.py_func(kernel)(*theirs), atol)
        _same(mine, theirs, atol)  # and moves them alike
        answered += len(args[0]) if got is None else sum(len(x) for x in (got if isinstance(got, tuple) else (got,)))
    assert answered > 0  # real work, not only empty inputs


def test_doors_found_on_real_scans(calls: dict[str, list[tuple]]):
    """The door-pair test is not vacuous: on hospital scans some pairs are doors."""
    assert any(out[4].any() for out in (identify.door_pairs(*a) for a in calls["door_pairs"]))
