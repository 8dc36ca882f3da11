"""Real inputs for the compiled-vs-Python checks: simulated 1000-beam scans of hospital_2019
at random free poses (seeded), as the perception benchmark records them."""

from __future__ import annotations

import contextlib
import copy
from collections.abc import Callable, Iterator
from functools import cache
from typing import Any

import numpy as np
import pytest

from pico_studio.config import Config
from pico_studio.core.io import LaserData, OdometryData
from pico_studio.evaluation.poses import world_free_poses
from pico_studio.json_map import load_map
from pico_studio.sim import Simulator
from tests.conftest import MAPS


@cache
def hospital_frames(k: int, seed: int = 0) -> tuple[tuple[Simulator, LaserData, OdometryData | None], ...]:
    """K (simulator, its first scan, its odometry) of hospital_2019, each at its own free pose."""
    cfg = Config()
    gmap = load_map(MAPS / "hospital_2019.json")
    first = Simulator(gmap, cfg.sim, seed=seed)
    poses = world_free_poses(first.world, first.truth.pose[:2], k, 0.4,
                              np.random.default_rng(seed), gmap.bounds)
    out = []
    for i, pose in enumerate(poses):
        sim = Simulator(gmap, cfg.sim, seed=seed + i, initial_pose=pose)
        sim.advance(0.05)
        laser = sim.read_laser()
        assert laser is not None
        out.append((sim, laser, sim.read_odometry()))
    return tuple(out)


def hospital_scans(k: int, seed: int = 0) -> list[LaserData]:
    """K laser scans of hospital_2019."""
    return [laser for _, laser, _ in hospital_frames(k, seed)]


@contextlib.contextmanager
def recorded_calls(targets: dict[Any, tuple[str, ...]]) -> Iterator[dict[str, list[tuple]]]:
    """Within: every call of the functions `targets` names ({module: names}) is recorded,
    its arguments deep-copied (kernels move some in place), by name; undone on leaving."""
    recorded: dict[str, list[tuple]] = {name: [] for names in targets.values() for name in names}
    mp = pytest.MonkeyPatch()

    def recorder(name: str, fn: Callable[..., Any]) -> Callable[..., Any]:
        def call(*args: Any) -> Any:
            recorded[name].append(copy.deepcopy(args))
            return fn(*args)
        return call

    for module, names in targets.items():
        for name in names:
            mp.setattr(module, name, recorder(name, getattr(module, name)))
    try:
        yield recorded
    finally:
        mp.undo()
