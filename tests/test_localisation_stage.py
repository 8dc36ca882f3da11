"""Localisation behind the real perceptor, in the session loop: the WorldModel's
global_pose, localisation_quality, lost and combined map are filled; a box that is not on
the map shows up as unmatched walls of the combined map."""

from __future__ import annotations

import math

import numpy as np

from pico_studio.config import Config
from pico_studio.core.behaviours.registry import Drive
from pico_studio.core.localisation import Localiser
from pico_studio.core.localisation.combined import CombinedMap
from pico_studio.core.localisation.stage import LocalisingPerceptor
from pico_studio.core.perception import Perceptor
from pico_studio.evaluation.run_score import PoseScore
from pico_studio.json_map import load_json_map
from pico_studio.session import Session
from pico_studio.sim import MovingObjectSpec, Simulator
from pico_studio.sim.sim_config import SimConfigFile


def test_session_fills_the_world_model_and_tags_an_unknown_box(maps_dir):
    cfg = Config()
    gmap = load_json_map(maps_dir / "hospital_2019.json")
    start = (3.5, 0.6, math.pi / 2)
    box = MovingObjectSpec(length=0.4, width=0.4, init_pose=(3.2, 2.4, 0.0), final_pose=(3.2, 2.4, 0.0),
                           velocity=0.0, trigger_radius=0.0, repeat=False)
    sim = Simulator(gmap, cfg.sim, SimConfigFile(objects=(box,)), seed=0, initial_pose=start)
    perceptor = LocalisingPerceptor(Perceptor(cfg.perception), Localiser(cfg.localisation, gmap, start))
    session = Session(sim, perceptor=perceptor, behaviour=Drive(0.0, 0.0, 0.3))
    score = PoseScore()
    for _ in range(60):  # 3 s turning on the spot, facing the box now and then
        session.tick(0.05)
        wm = session.world_model
        if wm is not None:
            score.add(wm.global_pose, sim.truth.pose, wm.lost)
    wm = session.world_model
    assert wm.global_pose is not None and not wm.lost
    assert wm.localisation_quality > 0.8
    assert "localisation" in wm.timings_ms
    s = score.summary()
    assert s["pose_error_m"]["max"] < 0.05 and s["heading_error_rad"]["median"] < math.radians(1)
    assert isinstance(wm.combined, CombinedMap)
    assert wm.combined.map_wall_seen.shape == (len(gmap.walls),) and wm.combined.map_wall_seen.any()
    d = wm.to_dict()
    assert set(d["combined"]) >= {"walls", "wall_matched", "map_wall_seen"}
    # walls of the local map on the map are matched; any wall on the box is not
    walls, matched = wm.combined.walls, wm.combined.wall_matched
    assert len(walls) and matched.mean() > 0.5
    mid = (walls[:, 0:2] + walls[:, 2:4]) / 2
    on_box = np.hypot(mid[:, 0] - 3.2, mid[:, 1] - 2.4) < 0.3
    assert on_box.any() and not matched[on_box].any()
    perceptor.reset()
    assert perceptor.localiser.last is None
