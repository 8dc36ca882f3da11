"""A simulated run recorded to a bag replays identically through the perceptor.

The simulator drives PICO through the 2019 hospital with the perceptor in the loop and a
`BagRecorder` as the session's recorder; the bag is then replayed through a fresh
perceptor, and every frame must give the same world model.

sensor_msgs/LaserScan holds ranges and angles as float32 (what the real robot's driver
sends, and emc's LaserData too), while the simulator computes in float64. So:

* the simulator as it is: the same world model structure in every frame (counts, end-point
  properties, convexity) and geometry within 1 cm — float32 rounding of 1e-7 m can tip
  which laser point ends a segment (measured: up to 9.5 mm on one segment end over
  3 x 200 frames, 1.4 mm in the 60 frames here);
* a simulator delivering float32 values, as the real driver does: identical to 1e-6.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pico_studio.core.config import Config
from pico_studio.core.io import LaserData
from pico_studio.core.perception import Perceptor
from pico_studio.session import Action, Session
from pico_studio.sim import Simulator
from pico_studio.sources import open_bag
from pico_studio.sources.recorder import BagRecorder
from pico_studio.sources.replay_run import run_replay

MAP = Path(__file__).resolve().parents[1] / "pico_studio" / "data" / "maps" / "hospital_2019.json"
TICKS = 60


class Float32Laser:
    """The simulator with its scans in float32, as the robot's laser driver sends them."""

    def __init__(self, sim: Simulator):
        self.sim = sim

    def read_laser(self) -> LaserData | None:
        scan = self.sim.read_laser()
        if scan is None:
            return None
        f32 = lambda v: float(np.float32(v))  # noqa: E731
        return replace(
            scan, ranges=scan.ranges.astype(np.float32).astype(float), angle_min=f32(scan.angle_min),
            angle_max=f32(scan.angle_max), angle_increment=f32(scan.angle_increment),
            range_min=f32(scan.range_min), range_max=f32(scan.range_max),
        )

    def __getattr__(self, name: str) -> Any:
        return getattr(self.sim, name)


def _arrays(wm: Any) -> dict[str, np.ndarray]:
    return {
        "current_map": wm.current_map,
        "local_map.walls": wm.local_map.walls,
        "local_map.endpoint_property": wm.local_map.endpoint_property,
        "corners": wm.corners,
        "corner_convex": wm.corner_convex,
        "doors": wm.doors,
        "possible_doors": wm.possible_doors,
        "pose": np.array(wm.pose),
        "beam_valid": wm.beam_valid,
    }


def _record_and_replay(tmp_path: Path, float32: bool) -> tuple[list, list, dict]:
    cfg = Config()
    bag = tmp_path / "sim.bag"
    sim = Simulator.from_files(MAP, None, cfg.sim, seed=3)
    source = Float32Laser(sim) if float32 else sim
    with BagRecorder(bag, cfg.sources.topics) as recorder:
        live = Session(
            source, perceptor=Perceptor(cfg.perception),
            behaviour=lambda frame, wm: Action(0.2, 0.0, 0.15), recorder=recorder, history=TICKS,
        )
        for _ in range(TICKS):
            live.tick(0.05)
    replay = open_bag(bag, cfg.sources)
    again = Session(replay, perceptor=Perceptor(cfg.perception), history=TICKS)
    report = run_replay(again, replay)
    recorded = [h for h in live.history if h.frame.laser is not None]
    replayed = [h for h in again.history if h.frame.laser is not None]
    return recorded, replayed, report


@pytest.mark.parametrize(("float32", "tolerance"), [(False, 0.01), (True, 1e-6)], ids=["sim", "sim-float32"])
def test_simulated_run_replays_identically_through_the_perceptor(tmp_path: Path, float32: bool, tolerance: float) -> None:
    recorded, replayed, report = _record_and_replay(tmp_path, float32)
    assert report["frames_read"] == len(recorded) == len(replayed) > 40
    assert report["frames_dropped"] == 0 and report["truth_poses"] == TICKS
    assert report["perceptor"]["frames_perceived"] == len(recorded)
    for a, b in zip(recorded, replayed, strict=True):
        assert b.frame.laser.timestamp == pytest.approx(a.frame.laser.timestamp, abs=1e-9)
        assert b.frame.truth["pose"] == pytest.approx(a.frame.truth["pose"], abs=1e-9)
        assert np.allclose(b.frame.laser.ranges, a.frame.laser.ranges, atol=1e-6)
        ours = _arrays(b.world_model)
        for name, x in _arrays(a.world_model).items():
            y = ours[name]
            assert x.shape == y.shape, f"frame {a.index}: {name} {x.shape} != {y.shape}"
            if x.dtype == bool or x.dtype.kind == "i":
                assert np.array_equal(x, y), f"frame {a.index}: {name} differs"
            else:
                assert np.allclose(x, y, atol=tolerance), f"frame {a.index}: {name} off by {np.max(np.abs(x - y)):.2e}"
