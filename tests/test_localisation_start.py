"""Where localisation starts when nothing says where the robot is (`prior.prior_pose`).

hospital_2021.png has no start area and its sim config no `initial_pose`: the simulator puts
the robot at the origin facing +x (the official simulator's default), inside the central room,
which is close to symmetric. Localising from the whole map, `run --localise` and the page found
its mirror image (1.06 m and pi off, so the combined map confirmed no door over a whole run);
from where the simulator put the robot they find it to a few mm."""

from __future__ import annotations

import json

from pico_studio.cli import main
from pico_studio.config import Config, with_value
from pico_studio.core.localisation import prior_pose
from pico_studio.json_map import load_map
from pico_studio.ui.runtime import Studio
from pico_studio.ui.sources import make_source_factory

START = (0.5, -0.5, 0.3)


def test_the_prior_pose_is_the_given_one_then_the_config_or_map_then_the_sources(maps_dir):
    cfg = Config()
    bare = load_map(maps_dir / "hospital_2021.png", cfg.map)  # no start area
    with_area = load_map(maps_dir / "restaurant_2024.json", cfg.map)
    given = (6.0, 3.5, 3.14)
    assert prior_pose(given, with_area, cfg.localisation.prior, START) == given
    assert prior_pose(None, with_area, cfg.localisation.prior, START) is None  # the start area decides
    assert prior_pose(None, bare, cfg.localisation.prior, START) == START
    posed = with_value(cfg, "localisation.prior.source", "pose").localisation.prior
    assert prior_pose(None, bare, posed, START) is None  # the config's pose decides
    assert prior_pose(None, bare, cfg.localisation.prior, None) is None  # nothing known: the whole map


def test_run_localises_on_a_map_without_a_start_area(maps_dir, capsys):
    assert main(["run", "--map", str(maps_dir / "hospital_2021.png"), "--sim-config",
                 str(maps_dir / "hospital_2021_sim.json"), "--seconds", "2", "--localise", "--json"]) == 0
    loc = json.loads(capsys.readouterr().out)["localisation"]
    assert loc["pose_error_m"]["max"] < 0.05 and loc["heading_error_rad"]["max"] < 0.05


def test_the_page_localises_from_where_the_simulator_put_the_robot(maps_dir):
    cfg = Config()
    gmap = load_map(maps_dir / "hospital_2021.png", cfg.map)
    studio = Studio(cfg, gmap, make_source_factory("sim", str(maps_dir / "hospital_2021_sim.json"), 0),
                    map_name="hospital_2021.png")
    prior = studio.lmap.prior
    assert prior.origin == "pose" and abs(prior.x) < 1e-9 and abs(prior.y) < 1e-9 and prior.heading_known
    for _ in range(20):
        studio.tick(0.05)
    frame = studio.timeline.latest
    g, t = frame.wm.global_pose, frame.truth_pose  # the robot wanders meanwhile
    assert g is not None
    assert abs(g[0] - t[0]) < 0.05 and abs(g[1] - t[1]) < 0.05 and abs(g[2] - t[2]) < 0.05
