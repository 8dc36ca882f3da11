"""The simulator's core: laser, base, collisions, odometry, rates, seeds, errors."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from sim_helpers import box_map

from pico_studio.config import Config, with_value
from pico_studio.config.sim_params import SimParams
from pico_studio.core.io import RobotIO
from pico_studio.errors import ConfigError, MapError, SourceError
from pico_studio.json_map import load_map
from pico_studio.sim import Simulator, sim_config_from_dict


def params(**changes: object) -> SimParams:
    cfg = Config()
    for path, value in changes.items():
        cfg = with_value(cfg, "sim." + path.replace("__", "."), value)
    return cfg.sim


def test_simulator_is_a_robot_io() -> None:
    sim = Simulator(box_map(), initial_pose=(5, 5, 0))
    assert isinstance(sim, RobotIO)
    assert sim.ok() and sim.now() == 0.0


def test_beam_hits_wall_at_the_right_distance_within_noise() -> None:
    sim = Simulator(box_map(), initial_pose=(3.0, 5.0, 0.0))
    scan = sim.read_laser()
    assert scan is not None and len(scan.ranges) == 1000
    assert scan.angle_min == -2.0 and scan.angle_max == 2.0
    assert scan.angle_increment == pytest.approx(4 / 999)
    ang = scan.angles
    # straight ahead the wall x = 10 is 7 m away; every beam: 7 / cos(angle) while it hits x = 10
    front = np.abs(ang) < math.atan2(5.0, 7.0) - 0.01
    expected = 7.0 / np.cos(ang[front])
    err = scan.ranges[front] - expected
    assert np.all(np.abs(err) <= 0.01 + 1e-6)  # float32 ranges
    assert np.abs(err).max() > 0.005  # the noise is really there, uniform up to 0.01
    # turned by 90 degrees, the same beam sees the top wall (y = 10) 5 m away
    sim2 = Simulator(box_map(), initial_pose=(3.0, 5.0, math.pi / 2))
    mid = sim2.read_laser()
    assert mid is not None
    i = int(np.argmin(np.abs(mid.angles)))
    assert mid.ranges[i] == pytest.approx(5.0 / math.cos(mid.angles[i]), abs=0.0101)


@pytest.mark.parametrize("rule", ["zero", "inf", "range_max"])
def test_no_return_beams_follow_the_chosen_convention(rule: str) -> None:
    # a 30 m long corridor: looking along it, the far wall is beyond 10 m
    m = box_map(30.0, 2.0)
    sim = Simulator(m, params(laser__no_return=rule), initial_pose=(1.0, 1.0, 0.0))
    scan = sim.read_laser()
    assert scan is not None
    i = int(np.argmin(np.abs(scan.angles)))
    far = np.abs(scan.angles) < 0.05  # these beams reach the end wall 29 m away
    assert far.sum() > 5
    r = scan.ranges[far]
    if rule == "zero":
        assert np.all((r >= 0.0) & (r <= 0.01)) and scan.ranges[i] < scan.range_min + 1e-12
    elif rule == "inf":
        assert np.all(np.isposinf(r))
    else:
        assert np.all(r == scan.range_max)
    # beams that do hit the side walls are ordinary readings either way
    side = np.abs(scan.angles - math.pi / 2) < 0.05
    assert np.all(np.abs(scan.ranges[side] - 1.0 / np.sin(scan.angles[side])) <= 0.0101)


def test_hokuyo_profile() -> None:
    sim = Simulator(box_map(), params(laser__profile="hokuyo"), initial_pose=(5, 5, 0))
    scan = sim.read_laser()
    assert scan is not None and len(scan.ranges) == 1081
    assert scan.range_min == 0.023 and scan.range_max == 60.0
    assert scan.angle_increment == pytest.approx(0.0043633, abs=1e-6)


def test_unknown_laser_profile_is_a_clear_error() -> None:
    with pytest.raises(ConfigError, match="sim.laser.profile"):
        with_value(Config(), "sim.laser.profile", "velodyne")
    # built in code, past the config's validation
    bad = dataclasses.replace(SimParams(), laser=dataclasses.replace(SimParams().laser, profile="velodyne"))
    with pytest.raises(ConfigError, match="sim.laser.profile: unknown laser profile 'velodyne'"):
        Simulator(box_map(), bad, initial_pose=(5, 5, 0))


def test_speed_cap_and_disabling_it() -> None:
    sim = Simulator(box_map(20, 20), initial_pose=(2.0, 10.0, 0.0))
    sim.send_base_reference(2.0, 0.0, 5.0)
    sim.advance(1.0)
    x, y, a = sim.truth.pose
    # 0.5 m/s while turning at 1.2 rad/s: the arc's chord, heading turned by exactly 1.2 rad
    assert a == pytest.approx(1.2)
    assert math.hypot(x - 2.0, y - 10.0) == pytest.approx(2 * 0.5 / 1.2 * math.sin(0.6), rel=1e-9)
    assert sim.truth.distance == pytest.approx(0.5, rel=1e-9)
    free = Simulator(box_map(20, 20), sim_config=sim_config_from_dict({"disable_speedcap": True}), initial_pose=(2.0, 10.0, 0.0))
    free.send_base_reference(2.0, 0.0, 0.0)
    free.advance(1.0)
    assert free.truth.pose[0] == pytest.approx(4.0)


def test_holonomic_sideways_motion_is_in_the_robot_frame() -> None:
    sim = Simulator(box_map(), initial_pose=(5.0, 5.0, math.pi / 2))
    sim.send_base_reference(0.0, 0.4, 0.0)  # left of a robot facing +y is -x
    sim.advance(2.0)
    assert sim.truth.pose[0] == pytest.approx(4.2) and sim.truth.pose[1] == pytest.approx(5.0)


def test_collision_stops_the_robot_and_is_counted() -> None:
    sim = Simulator(box_map(), initial_pose=(8.0, 5.0, 0.0))
    sim.send_base_reference(0.5, 0.0, 0.0)
    for _ in range(200):
        sim.advance(0.05)
    x = sim.truth.pose[0]
    assert 10.0 - 0.08 - 0.03 < x < 10.0 - 0.08  # stopped just short of the wall
    assert sim.truth.collisions == 1  # one contact, not one per step
    assert sim.truth.collision_events[0].kind == "wall"
    assert sim.base.reference == (0.0, 0.0, 0.0)  # stopped until told otherwise
    sim.send_base_reference(-0.5, 0.0, 0.0)
    sim.advance(1.0)
    sim.send_base_reference(0.5, 0.0, 0.0)
    sim.advance(2.0)
    assert sim.truth.collisions == 2


def test_no_tunnelling_through_a_thin_wall_at_full_speed() -> None:
    # a zero-thickness wall at x = 5 inside the room; disable the cap and go 5 m/s with big steps
    m = box_map(more_points=[{"x": 5, "y": 1}, {"x": 5, "y": 9}], more_walls=[[4, 5]])
    cfg = sim_config_from_dict({"disable_speedcap": True})
    for dt in (0.05, 0.5):
        sim = Simulator(m, sim_config=cfg, initial_pose=(3.0, 5.0, 0.3))
        sim.send_base_reference(5.0, 0.0, 0.0)
        for _ in range(int(4 / dt)):
            sim.advance(dt)
        assert sim.truth.pose[0] < 5.0
        assert sim.truth.collisions == 1
    # and at the capped full speed, spinning too
    sim = Simulator(m, initial_pose=(4.0, 5.0, 0.0))
    for _ in range(100):
        sim.send_base_reference(0.5, 0.0, 0.0)
        sim.advance(0.05)
    assert 4.7 < sim.truth.pose[0] < 5.0
    assert sim.truth.collisions == 1


def test_nan_commands_are_a_clear_error() -> None:
    sim = Simulator(box_map(), initial_pose=(5, 5, 0))
    for bad in ((math.nan, 0, 0), (0, math.inf, 0), (0, 0, -math.inf)):
        with pytest.raises(SourceError, match="finite"):
            sim.send_base_reference(*bad)
    assert sim.base.reference == (0.0, 0.0, 0.0)


def test_sensor_rates_and_read_returns_none_until_new() -> None:
    sim = Simulator(box_map(), initial_pose=(5, 5, 0))
    assert sim.read_laser() is not None and sim.read_odometry() is not None
    assert sim.read_laser() is None and sim.read_odometry() is None
    laser, odom = 0, 0
    stamps = []
    for _ in range(1000):  # 1 s in 1 ms steps
        sim.advance(0.001)
        if (s := sim.read_laser()) is not None:
            laser += 1
            stamps.append(s.timestamp)
        odom += sim.read_odometry() is not None
    assert laser == 20 and odom == 50
    assert np.allclose(np.diff(stamps), 0.05)


def test_same_seed_same_run_different_seed_different_noise() -> None:
    def run(seed: int) -> list[np.ndarray]:
        m = load_map("examples/maps/hospital_2019.json")
        sim = Simulator(m, params(odometry__uncertain=True), seed=seed)
        out = []
        for k in range(60):
            sim.send_base_reference(0.4, 0.1 * math.sin(k / 5), 0.5)
            sim.advance(0.05)
            s, o = sim.read_laser(), sim.read_odometry()
            assert s is not None and o is not None
            out += [s.ranges, np.array([o.x, o.y, o.a]), np.array(sim.truth.pose)]
        return out

    a, b, c = run(7), run(7), run(8)
    assert all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))
    assert not all(np.array_equal(x, y) for x, y in zip(a, c, strict=True))


def test_odometry_offset_and_absolute_form() -> None:
    p = params(odometry__offset_x=100.0, odometry__offset_y=-3.0, odometry__offset_a=1.0)
    sim = Simulator(box_map(), p, initial_pose=(2.0, 5.0, 0.0))
    o = sim.read_odometry()
    assert o is not None and (o.x, o.y, o.a, o.form) == (100.0, -3.0, 1.0, "absolute")
    sim.send_base_reference(0.5, 0.0, 0.0)
    sim.advance(2.0)
    o = sim.read_odometry()
    assert o is not None
    # 1 m forward in a frame turned by 1 rad
    assert o.x == pytest.approx(100.0 + math.cos(1.0)) and o.y == pytest.approx(-3.0 + math.sin(1.0))
    seeded = Simulator(box_map(), params(odometry__random_offset=True), initial_pose=(2.0, 5.0, 0.0), seed=3)
    o2 = seeded.read_odometry()
    assert o2 is not None and (o2.x, o2.y) != (0.0, 0.0)


def test_delta_odometry_sums_to_the_motion_however_often_it_is_read() -> None:
    sim = Simulator(box_map(), params(odometry__form="delta"), initial_pose=(2.0, 5.0, 0.0))
    first = sim.read_odometry()
    assert first is not None and first.form == "delta" and (first.x, first.y, first.a) == (0.0, 0.0, 0.0)
    sim.send_base_reference(0.3, 0.0, 0.4)
    pose = (0.0, 0.0, 0.0)
    from pico_studio.core.geometry import compose, relative

    for k in range(100):
        sim.advance(0.013 if k % 2 else 0.071)  # odd steps, odometry latched at 50 Hz
        o = sim.read_odometry()
        if o is not None:
            pose = compose(pose, (o.x, o.y, o.a))
    # deltas accumulate to the motion up to the last latched reading
    truth = relative((2.0, 5.0, 0.0), sim.truth.pose)
    assert math.hypot(pose[0] - truth[0], pose[1] - truth[1]) < 0.3 * 0.02 + 1e-9


def test_uncertain_odometry_drift_stays_within_the_gain_errors() -> None:
    m = box_map(30.0, 10.0)
    sim = Simulator(m, params(odometry__uncertain=True), initial_pose=(1.0, 5.0, 0.0), seed=11)
    sim.send_base_reference(0.5, 0.0, 0.0)
    for _ in range(20 * 40):  # 40 s straight: 20 m, gains re-drawn 6 times
        sim.advance(0.05)
    o = sim.odometry.pose
    x = sim.truth.pose[0] - 1.0
    assert x == pytest.approx(20.0)
    err = math.hypot(o[0] - x, o[1])
    assert 0.0 < err <= 0.002 * 20.0 + 1e-9
    assert o[2] == 0.0  # no rotation commanded, none measured (gain times zero)
    exact = Simulator(m, initial_pose=(1.0, 5.0, 0.0), seed=11)
    exact.send_base_reference(0.5, 0.0, 0.0)
    exact.advance(40.0)
    assert exact.odometry.pose[0] == pytest.approx(20.0, abs=1e-9)


def test_start_pose_inside_a_wall_is_a_clear_error() -> None:
    with pytest.raises(SourceError, match="initial_pose.*inside a wall"):
        Simulator(box_map(), sim_config=sim_config_from_dict({"initial_pose": [0.05, 5.0, 0.0]}, file="cfg.json"))


def test_start_area_centre_and_default_free_place() -> None:
    r = load_map("examples/maps/restaurant_2024.json")
    sim = Simulator(r)
    c = r.start_center
    assert c is not None and sim.truth.pose == (c[0], c[1], 0.0)
    team = Simulator(load_map("examples/maps/hospital_2019_with_nodes.json"))
    assert team.truth.pose == (5.0, 2.5, 0.0)  # the centre of its `start` polygon
    h = load_map("examples/maps/hospital_2019.json")
    a, b = Simulator(h), Simulator(h)
    assert a.truth.pose == b.truth.pose  # deterministic
    assert not a.base.collides(a.truth.pose, a.world.segments()).any()
    assert a.world.enclosed(a.truth.pose[:2])


def test_map_without_a_free_place_is_a_clear_error() -> None:
    tiny = box_map(0.2, 0.2)
    with pytest.raises(MapError, match="no free place to start"):
        Simulator(tiny)


def test_sim_config_wrong_types_name_the_field() -> None:
    with pytest.raises(SourceError, match=r"c.json: uncertain_odom: must be true or false"):
        sim_config_from_dict({"uncertain_odom": "yes"}, file="c.json")
    with pytest.raises(SourceError, match=r"objects\[0\].velocity"):
        sim_config_from_dict({"objects": [{"length": 1, "width": 1, "init_pose": [0, 0, 0], "final_pose": [1, 0, 0], "velocity": "fast", "trigger_radius": 1}]})
    with pytest.raises(SourceError, match=r"initial_pose"):
        sim_config_from_dict({"initial_pose": [1, 2]})
    cfg = sim_config_from_dict({"show_full_map": True, "enable_taco": False, "provide_internal_pose": True})
    assert cfg.ignored == ("enable_taco", "provide_internal_pose", "show_full_map")


def test_real_sim_configs_load() -> None:
    from pico_studio.sim import load_sim_config

    r = load_sim_config("examples/maps/restaurant_2024_sim.json")
    assert r.initial_pose == (6.0, 3.5, 3.14) and len(r.objects) == 1 and r.uncertain_odom is False
    h = load_sim_config("examples/maps/hospital_2021_sim.json")
    assert len(h.objects) == 2 and h.objects[1].repeat is True and "show_full_map" in h.ignored


def test_params_are_frozen_dataclasses() -> None:
    assert dataclasses.is_dataclass(SimParams())


def test_realtime_pacing_waits_for_the_wall_clock() -> None:
    import time

    sim = Simulator(box_map(), params(realtime=True), initial_pose=(5, 5, 0))
    t = time.perf_counter()
    for _ in range(4):
        sim.advance(0.05)
    assert time.perf_counter() - t >= 0.15  # paced: never ahead of the wall clock by a step


def test_hokuyo_rate_and_custom_rates() -> None:
    sim = Simulator(box_map(), params(laser__profile="hokuyo", odometry__rate_hz=100.0), initial_pose=(5, 5, 0))
    sim.read_laser(), sim.read_odometry()
    scans = odoms = 0
    for _ in range(200):  # 2 s in 10 ms steps
        sim.advance(0.01)
        scans += sim.read_laser() is not None
        odoms += sim.read_odometry() is not None
    assert scans == 72 and odoms == 200


def test_random_driving_never_ends_inside_or_through_a_wall() -> None:
    m = load_map("examples/maps/hospital_2019.json")
    rng = np.random.default_rng(5)
    sim = Simulator(m, sim_config=sim_config_from_dict({"disable_speedcap": True}), seed=5)
    segs = sim.world.segments()
    for k in range(600):  # 60 s, a new random command (up to 3 m/s, 4 rad/s) every 0.5 s
        if k % 5 == 0:
            sim.send_base_reference(*rng.uniform(-3, 3, 2), rng.uniform(-4, 4))
        sim.advance(0.1)
        assert not sim.base.collides(sim.truth.pose, segs).any()
        assert sim.world.enclosed(sim.truth.pose[:2])
    assert sim.truth.collisions > 5  # it did hit things, and was stopped every time


def test_a_long_step_delivers_the_newest_scan_taken_where_it_was_due() -> None:
    sim = Simulator(box_map(), initial_pose=(2.0, 5.0, 0.0))
    sim.read_laser()
    sim.send_base_reference(0.5, 0.0, 0.0)
    sim.advance(1.01)  # scan times 0.05 ... 1.0 pass; the newest is the one at 1.0 s
    scan = sim.read_laser()
    assert scan is not None and scan.timestamp == pytest.approx(1.0)
    i = int(np.argmin(np.abs(scan.angles)))
    assert abs(scan.ranges[i] * math.cos(scan.angles[i]) - (10.0 - 2.5)) < 0.0101  # seen from x = 2.5, not 2.505
    assert sim.read_laser() is None


def test_default_start_is_the_origin_when_free_as_in_the_official_simulator() -> None:
    from pico_studio.json_map import map_from_dict

    corners = [(-1, -2), (9, -2), (9, 6), (-1, 6)]
    m = map_from_dict({"points": [{"x": x, "y": y} for x, y in corners], "walls": [[0, 1], [1, 2], [2, 3], [3, 0]]})
    assert Simulator(m).truth.pose == (0.0, 0.0, 0.0)  # free, though not the farthest place
    square = box_map(8.0, 8.0)  # the origin is a corner: the farthest free place instead
    x, y, _ = Simulator(square).truth.pose
    assert abs(x - 4.0) < 0.06 and abs(y - 4.0) < 0.06
    wide = box_map(10.0, 8.0)  # a tie along y = 4 for 4 <= x <= 6: the lowest x wins
    x, y, _ = Simulator(wide).truth.pose
    assert abs(x - 4.0) < 0.06 and abs(y - 4.0) < 0.06
