"""The behaviours driving the real simulator in generated and shipped worlds (a small subset of
the benchmark's matrix, kept fast), the registry and the run command's behaviour output."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from pico_studio.cli import main
from pico_studio.config.tree import Config
from pico_studio.core.behaviours.escape_room import EscapeRoom
from pico_studio.core.behaviours.hospital import HospitalTour, object_spots
from pico_studio.core.behaviours.registry import make_behaviour
from pico_studio.core.behaviours.room_finder import RoomFinder
from pico_studio.errors import UserError
from pico_studio.evaluation.judges import EscapeJudge
from pico_studio.evaluation.runner import run_behaviour
from pico_studio.evaluation.worlds import escape_world, room_finder_world
from pico_studio.json_map import GlobalMap, load_json_map
from pico_studio.sim import Simulator
from pico_studio.sim.sim_config import SimConfigFile

CFG = Config()
UNCERTAIN = SimConfigFile(uncertain_odom=True)


def sim_in(world, seed):
    return Simulator(world.map, CFG.sim, UNCERTAIN, seed=seed, initial_pose=world.start)


def test_escape_room_gets_out_of_a_generated_room_without_touching_a_wall():
    w = escape_world(7)
    r = run_behaviour(sim_in(w, 7), EscapeRoom(CFG.behaviour), seconds=120)
    assert r["escaped"] and r["escape_seconds"] < 120
    assert r["collisions"] == 0 and r["state"] == "done"


def test_escape_room_gives_up_cleanly_in_a_closed_room():
    pts = np.array([[0, 0], [4, 0], [4, 3], [0, 3]], dtype=float)
    m = GlobalMap(points=pts, walls=np.array([[0, 1], [1, 2], [2, 3], [3, 0]]))
    sim = Simulator(m, CFG.sim, UNCERTAIN, seed=1, initial_pose=(2.0, 1.5, 0.3))
    r = run_behaviour(sim, EscapeRoom(CFG.behaviour), seconds=400)
    assert r["state"] == "gave up" and not r["escaped"] and r["collisions"] == 0
    assert "no entrance" in r["notes"][0]


def test_room_finder_finds_every_room_and_counts_its_objects():
    w = room_finder_world(2)
    r = run_behaviour(sim_in(w, 2), RoomFinder(CFG.behaviour), seconds=300)
    expected = [room["objects"] for room in w.rooms]
    got = [room["objects"] for room in r["rooms"]]
    # the robot goes round from whichever corner it starts at: the same rooms, rotated
    assert len(got) == len(expected)
    assert any(got == expected[k:] + expected[:k] for k in range(len(expected)))
    assert r["collisions"] == 0 and r["state"] == "done"


def test_hospital_tour_visits_tables_in_order_through_the_restaurant(maps_dir):
    m = load_json_map(maps_dir / "restaurant_2024.json")
    sim = Simulator(m, CFG.sim, SimConfigFile(uncertain_odom=True, initial_pose=(6.0, 3.5, 3.14)), seed=0)
    b = HospitalTour(CFG.behaviour, m, [1, 4], initial_pose=sim.truth.pose)
    r = run_behaviour(sim, b, seconds=200)
    assert r["cabinets_visited"] == [1, 4] and r["collisions"] == 0 and r["state"] == "done"
    # it stands in front of the last table, facing it
    x, y, a = sim.truth.pose
    spot = min(object_spots(m, 4, CFG.behaviour.hospital.front_distance),
               key=lambda s: math.hypot(s[0] - x, s[1] - y))
    assert math.hypot(spot[0] - x, spot[1] - y) < 0.2
    assert abs(math.remainder(spot[2] - a, 2 * math.pi)) < 0.2


def test_hospital_bad_targets_are_clear_errors(maps_dir):
    m = load_json_map(maps_dir / "hospital_2019.json")
    with pytest.raises(UserError, match="no cabinet 7"):
        make_behaviour("hospital:0,7", CFG.behaviour, m, (1.0, 1.0, 0.0))
    with pytest.raises(UserError, match="indices"):
        make_behaviour("hospital:x", CFG.behaviour, m)
    with pytest.raises(UserError, match="unknown behaviour"):
        make_behaviour("teleport", CFG.behaviour, m)
    with pytest.raises(UserError, match="takes no argument"):
        make_behaviour("escape-room:3", CFG.behaviour, m)
    # a cabinet whose front faces a wall 0.2 m away: its spot is inside the inflated wall
    pts = np.array([[0, 0], [4, 0], [4, 3], [0, 3], [1, 0.2], [2, 0.2], [2, 1], [1, 1]], dtype=float)
    walled = GlobalMap(points=pts, walls=np.array([[0, 1], [1, 2], [2, 3], [3, 0]]),
                       objects=[np.array([[4, 5], [5, 6], [6, 7], [7, 4]])])
    with pytest.raises(UserError, match="inside a wall"):
        HospitalTour(CFG.behaviour, walled, [0], initial_pose=(3.0, 2.0, 0.0))


def test_hospital_gives_up_when_the_cabinet_cannot_be_reached():
    # two rooms with no way between them; the cabinet is in the other one
    pts = np.array([[0, 0], [6, 0], [6, 3], [0, 3], [3, 0], [3, 3],
                    [4.5, 1.0], [5.0, 1.0], [5.0, 1.5], [4.5, 1.5]], dtype=float)
    m = GlobalMap(points=pts, walls=np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5]]),
                  objects=[np.array([[6, 9], [9, 8], [8, 7], [7, 6]])])
    sim = Simulator(m, CFG.sim, UNCERTAIN, seed=0, initial_pose=(1.5, 1.5, 0.0))
    r = run_behaviour(sim, HospitalTour(CFG.behaviour, m, [0], initial_pose=(1.5, 1.5, 0.0)), seconds=30)
    assert r["state"] == "gave up" and "cannot be reached" in r["notes"][0] and r["collisions"] == 0


def test_escape_judge_uses_the_finish_line_or_the_bounding_box():
    w = escape_world(3)
    j = EscapeJudge(w.map)
    f = w.map.finish_segments[0]
    mid = (f[:2] + f[2:]) / 2
    inner = mid - (mid - np.array([2.0, 2.0])) * 0.05
    j.update(tuple(inner), 1.0)
    assert j.escaped_at is None
    j.update(tuple(mid + (mid - inner)), 2.0)
    assert j.escaped_at == 2.0
    box = EscapeJudge(GlobalMap(points=np.array([[0, 0], [1, 0]], float), walls=np.array([[0, 1]])))
    box.update((1.2, 0.0), 1.0)
    assert box.escaped_at is None
    box.update((1.31, 0.0), 2.0)
    assert box.escaped_at == 2.0


def test_run_command_reports_a_behaviour_as_json(capsys, maps_dir):
    code = main(["run", "--map", str(maps_dir / "restaurant_2024.json"), "--behaviour", "hospital:1",
                 "--sim-config", str(maps_dir / "restaurant_2024_sim.json"), "--json"])
    assert code == 0
    r = json.loads(capsys.readouterr().out)
    for key in ("escaped", "escape_seconds", "rooms", "cabinets_visited", "collisions", "state"):
        assert key in r
    assert r["cabinets_visited"] == [1] and r["state"] == "done" and r["collisions"] == 0
    # it localises on the map: the error against the truth, as the median and the maximum
    loc = r["localisation"]
    assert loc["frames"] > 0 and loc["pose_error_m"]["max"] < 0.1 and loc["heading_error_rad"]["median"] < 0.02
    assert set(loc["pose_error_m"]) == {"median", "max"}


def test_a_behaviour_that_does_not_localise_reports_no_pose_error_unless_asked(capsys, maps_dir):
    args = ["run", "--map", str(maps_dir / "emc_example.json"), "--behaviour", "escape-room", "--seconds", "2",
            "--json"]
    assert main(args) == 0
    assert "localisation" not in json.loads(capsys.readouterr().out)
    assert main([*args, "--localise"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert r["localisation"]["frames"] == 40 and r["localisation"]["pose_error_m"]["median"] < 0.05


def test_run_command_rejects_a_bad_behaviour(capsys, maps_dir):
    assert main(["run", "--map", str(maps_dir / "hospital_2019.json"), "--behaviour", "hospital:0,9"]) == 2
    assert "no cabinet 9" in capsys.readouterr().err


def test_hospital_replans_round_a_box_that_is_not_on_the_map():
    from pico_studio.sim.sim_config import MovingObjectSpec

    # a 6 x 3 m room, the cabinet at the far end, a box (never triggered: it stays) in the way
    pts = np.array([[0, 0], [6, 0], [6, 3], [0, 3], [5.6, 1.2], [5.9, 1.2], [5.9, 1.8], [5.6, 1.8]], dtype=float)
    m = GlobalMap(points=pts, walls=np.array([[0, 1], [1, 2], [2, 3], [3, 0]]),
                  objects=[np.array([[4, 7], [7, 6], [6, 5], [5, 4]])])
    box = MovingObjectSpec(length=0.5, width=1.2, init_pose=(3.0, 1.5, 0.0), final_pose=(3.0, 1.5, 0.0),
                           velocity=0.0, trigger_radius=0.0, repeat=False)
    sim = Simulator(m, CFG.sim, SimConfigFile(uncertain_odom=True, objects=(box,)), seed=0,
                    initial_pose=(0.8, 1.5, 0.0))
    b = HospitalTour(CFG.behaviour, m, [0], initial_pose=(0.8, 1.5, 0.0))
    r = run_behaviour(sim, b, seconds=120)
    assert r["cabinets_visited"] == [0] and r["collisions"] == 0
    assert r["replans"] >= 1


def test_escape_room_with_a_dead_end_hallway_gives_up_without_touching_a_wall():
    w = escape_world(5)
    m = w.map
    f = m.finish  # close the hallway's far end with a wall
    closed = GlobalMap(points=m.points, walls=np.vstack([m.walls, f]))
    sim = Simulator(closed, CFG.sim, UNCERTAIN, seed=5, initial_pose=w.start)
    b = EscapeRoom(CFG.behaviour)
    r = run_behaviour(sim, b, seconds=600)
    assert not r["escaped"] and r["collisions"] == 0
    assert r["state"] == "gave up" and len(b._dead_ends) >= 1


def test_hospital_asks_the_door_on_its_plan_to_open_and_goes_through():
    # two rooms joined only by a closed sliding door; the cabinet is behind it
    pts = np.array([[0, 0], [6, 0], [6, 3], [0, 3], [3, 0], [3, 1.0], [3, 2.0], [3, 3],
                    [2.95, 1.0], [3.05, 1.0], [3.05, 2.0], [2.95, 2.0],
                    [5.6, 1.2], [5.9, 1.2], [5.9, 1.8], [5.6, 1.8]], dtype=float)
    m = GlobalMap(points=pts, walls=np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [6, 7]]),
                  objects=[np.array([[12, 15], [15, 14], [14, 13], [13, 12]])],
                  doors=[np.array([[8, 9], [9, 10], [10, 11], [11, 8]])])
    sim = Simulator(m, CFG.sim, UNCERTAIN, seed=0, initial_pose=(1.0, 1.5, 0.0))
    r = run_behaviour(sim, HospitalTour(CFG.behaviour, m, [0], initial_pose=(1.0, 1.5, 0.0)), seconds=120)
    assert r["cabinets_visited"] == [0] and r["collisions"] == 0 and r["state"] == "done"
    assert sim.truth.pose[0] > 4.5


def test_one_registry_makes_every_behaviour_with_the_step_protocol():
    from pico_studio.core.behaviours.registry import BEHAVIOURS, Drive, register_behaviour
    from pico_studio.core.behaviours.wander import Wander
    from pico_studio.core.io import STOP, Command

    m = load_json_map("pico_studio/data/maps/hospital_2019.json")
    for name in BEHAVIOURS:
        spec = "drive:0.1,0,0.2" if name == "drive" else name
        b = make_behaviour(spec, CFG, m, (1.0, 1.0, 0.0))
        cmd = b.step(None, None, None, 0.0, ok=True)
        assert cmd is None or isinstance(cmd, Command), name
        assert isinstance(b.result(), dict) and b.name == name
    assert make_behaviour("drive:0.1,0,0.2", CFG).step(None, None, None, 0.0) == Command(0.1, 0.0, 0.2)
    assert make_behaviour("drive:0.1,0,0.2", CFG).step(None, None, None, 0.0, ok=False) == STOP
    assert make_behaviour("idle", CFG).step(None, None, None, 0.0) is None
    assert make_behaviour("stop", CFG).step(None, None, None, 0.0) == STOP
    # the whole config gives wander its section; bare behaviour params give it the defaults
    tuned = CFG.ui.wander.__class__(speed=0.11)
    from dataclasses import replace

    cfg = replace(CFG, ui=replace(CFG.ui, wander=tuned))
    assert make_behaviour("wander", cfg).params.speed == 0.11
    assert isinstance(make_behaviour("wander", CFG.behaviour), Wander)
    for bad, words in (("drive:1,2", "three numbers"), ("drive:1,nan,0", "finite"), ("idle:3", "no argument")):
        with pytest.raises(UserError, match=words) as e:
            make_behaviour(bad, CFG)
        assert e.value.field == "--behaviour"
    register_behaviour("creep", lambda arg, s, m, pose: Drive(0.05, 0, 0), help="slowly ahead")
    try:
        assert make_behaviour("creep", CFG).step(None, None, None, 0.0) == Command(0.05, 0.0, 0.0)
    finally:
        del BEHAVIOURS["creep"]
