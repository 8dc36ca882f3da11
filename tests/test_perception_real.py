"""The perceptor over every scan of both real recordings: no exception, sensible output.

The PICO bag (1081 beams, ±135°, no odometry: the pose comes from the laser motion) and the
Intel Research Lab CARMEN log (180 beams over 180°, raw odometry, a 30 m building: the
local map keeps walls within 6 m and odometry steps up to 2 m between its sparse scans).
"""

from __future__ import annotations

import numpy as np
import pytest

from pico_studio.config import Config, with_value
from pico_studio.core.perception import Perceptor
from pico_studio.sources import open_bag, open_carmen


def _run(replay, params):
    p = Perceptor(params)
    out = []
    for i in range(replay.frame_count):
        f = replay.frame(i)
        wm = p.step(f.laser, f.odometry)
        assert not any("perceptor failed" in w for w in wm.warnings), wm.warnings
        out.append(wm)
    return out


@pytest.mark.parametrize("name", ["pico_real_2019-05-07.bag", "intel-corrected.log.gz"])
def test_every_scan_of_a_real_recording(recordings_dir, name):
    cfg = Config()
    if name.endswith(".bag"):
        replay = open_bag(recordings_dir / name)
    else:
        replay = open_carmen(recordings_dir / name)
        cfg = with_value(cfg, "perception.merge.keep_radius", 6.0)
        cfg = with_value(cfg, "perception.locate.jump_distance", 2.0)
    wms = _run(replay, cfg.perception)
    assert len(wms) == replay.frame_count > 200
    beams = len(replay.frame(0).laser.ranges)
    assert all(wm.beam_valid.shape == (beams,) for wm in wms)
    walls = np.array([len(wm.current_map) for wm in wms])
    assert np.median(walls) >= 3  # rooms and corridors: several walls in every scan
    local = np.array([len(wm.local_map.walls) for wm in wms])
    assert local.max() <= cfg.perception.merge.max_walls
    assert np.median(local) >= 3
    assert sum(len(wm.corners) for wm in wms) > len(wms)


def test_bag_without_odometry_moves_by_the_laser(recordings_dir):
    replay = open_bag(recordings_dir / "pico_real_2019-05-07.bag")
    assert not replay.has_odometry
    wms = _run(replay, Config().perception)
    motions = [wm.laser_motion for wm in wms if wm.laser_motion is not None]
    assert len(motions) > len(wms) // 2
    # 6.8 s in a small room: the laser-estimated pose stays inside it
    assert all(np.hypot(*wm.pose[:2]) < 3.0 for wm in wms)
