"""A simulated run recorded to a bag replays identically through the perceptor.

The simulator drives PICO through the 2019 hospital with the perceptor in the loop and a
`BagRecorder` as the session's recorder; the bag is then replayed through a fresh
perceptor, and every frame must give the same world model: the same structure (counts,
end-point properties, convexity, valid beams) and the same geometry.

The simulator's ranges are float32, as sensor_msgs/LaserScan (and the real robot) hold
them, so they round-trip exactly; the angle fields are stored as float32 too, which moves
laser points by < 1e-6 m (measured: geometry within 6e-6 m over 3 x 200 frames), hence
the 1e-5 tolerance. (Before the simulator's ranges were float32, one segment end moved by
up to 9.5 mm: float32 rounding tipped which laser point ended it.)
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pico_studio.config import Config
from pico_studio.core.behaviours.registry import Drive
from pico_studio.core.perception import Perceptor
from pico_studio.session import Session
from pico_studio.sim import Simulator
from pico_studio.sources import open_bag
from pico_studio.sources.recorder import BagRecorder
from pico_studio.sources.replay_run import run_replay

MAP = Path(__file__).resolve().parents[1] / "pico_studio" / "data" / "maps" / "hospital_2019.json"
TICKS = 60
TOLERANCE = 1e-5  # m / rad


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


def _record_and_replay(tmp_path: Path) -> tuple[list, list, dict]:
    cfg = Config()
    bag = tmp_path / "sim.bag"
    sim = Simulator.from_files(MAP, None, cfg.sim, seed=3)
    with BagRecorder(bag, cfg.sources.topics) as recorder:
        live = Session(
            sim, perceptor=Perceptor(cfg.perception),
            behaviour=Drive(0.2, 0.0, 0.15), recorder=recorder, history=TICKS,
        )
        for _ in range(TICKS):
            live.tick(0.05)
    replay = open_bag(bag, cfg.sources)
    again = Session(replay, perceptor=Perceptor(cfg.perception), history=TICKS)
    report = run_replay(again, replay)
    recorded = [h for h in live.history if h.frame.laser is not None]
    replayed = [h for h in again.history if h.frame.laser is not None]
    return recorded, replayed, report


def test_simulated_run_replays_identically_through_the_perceptor(tmp_path: Path) -> None:
    recorded, replayed, report = _record_and_replay(tmp_path)
    assert report["frames_read"] == len(recorded) == len(replayed) > 40
    assert report["frames_dropped"] == 0 and report["truth_poses"] == TICKS
    assert report["perceptor"]["frames_perceived"] == len(recorded)
    for a, b in zip(recorded, replayed, strict=True):
        assert b.frame.laser.timestamp == pytest.approx(a.frame.laser.timestamp, abs=1e-9)
        assert b.frame.truth["pose"] == pytest.approx(a.frame.truth["pose"], abs=1e-9)
        assert np.array_equal(b.frame.laser.ranges, a.frame.laser.ranges)
        ours = _arrays(b.world_model)
        for name, x in _arrays(a.world_model).items():
            y = ours[name]
            assert x.shape == y.shape, f"frame {a.index}: {name} {x.shape} != {y.shape}"
            if x.dtype == bool or x.dtype.kind == "i":
                assert np.array_equal(x, y), f"frame {a.index}: {name} differs"
            else:
                assert np.allclose(x, y, atol=TOLERANCE), f"frame {a.index}: {name} off by {np.max(np.abs(x - y)):.2e}"
