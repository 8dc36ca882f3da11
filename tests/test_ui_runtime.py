"""The page's core without a browser: wander, the studio loop and timeline, layer geometry,
inspect/measure, line colours, the generated config panel and `serve`'s bad input."""

from __future__ import annotations

import argparse
import math
import socket

import numpy as np
import pytest

from pico_studio.cli import main
from pico_studio.config import Config, params, with_value
from pico_studio.core.behaviours.wander import Wander
from pico_studio.core.geometry import point_segment_distance
from pico_studio.errors import ConfigError, UserError
from pico_studio.json_map import load_json_map
from pico_studio.sim import Simulator
from pico_studio.ui import style
from pico_studio.ui.colour import line_display
from pico_studio.ui.inspect import features_near, measure_text, nearest_feature, ray_to_ground
from pico_studio.ui.runtime import Studio
from pico_studio.ui.scene_data import LAYERS, PRIM_SPECS, frame_prims, map_prims
from pico_studio.ui.sources import DEFAULT_MAP, example_maps, make_source_factory
from pico_studio.ui.status import metrics_text


def _studio(cfg: Config | None = None, seed: int = 2) -> Studio:
    cfg = cfg or Config()
    return Studio(cfg, load_json_map(DEFAULT_MAP), make_source_factory("sim", None, seed), map_name=DEFAULT_MAP.name)


def test_wander_drives_around_the_hospital_without_hitting_anything() -> None:
    sim = Simulator(load_json_map(DEFAULT_MAP), seed=4)
    wander = Wander(Config().ui.wander)
    states = set()
    for _ in range(1200):  # 60 s at 20 Hz
        sim.advance(0.05)
        cmd = wander.step(None, sim.read_laser())
        states.add(wander.state)
        sim.send_base_reference(cmd.vx, cmd.vy, cmd.va)
    assert sim.truth.collisions == 0
    assert sim.truth.distance > 5.0
    assert states == {"drive", "turn"}  # it met walls and turned away from them


def test_timeline_keeps_the_last_n_frames() -> None:
    cfg = with_value(Config(), "ui.timeline_seconds", 1.0)
    s = _studio(cfg)
    for _ in range(35):
        s.tick(0.05)
    assert len(s.timeline) == 20
    assert s.timeline[0].index == 15 and s.timeline.latest.index == 34


def test_scrubbed_frame_is_reprocessed_with_the_new_value() -> None:
    s = _studio()
    for _ in range(40):
        s.tick(0.05)
    s.playing = False
    frame = s.scrub(10)
    assert frame is not None and frame.index == 10 and len(frame.wm.current_map) > 0
    live_state = s.state
    s.set_param("perception.scan.min_length", 5.0)
    assert len(s.shown().wm.current_map) == 0
    assert s.state is live_state  # re-processing an old frame leaves the live loop alone
    s.set_param("perception.scan.min_length", 0.1)
    assert len(s.shown().wm.current_map) > 0


def test_an_invalid_value_is_refused_and_the_config_kept() -> None:
    s = _studio()
    before = s.cfg
    with pytest.raises(ConfigError, match="clear_distance"):
        s.set_param("ui.wander.clear_distance", 0.1)  # below stop_distance
    assert s.cfg is before


def test_laser_points_are_drawn_on_the_walls() -> None:
    s = _studio()
    for _ in range(20):
        s.tick(0.05)
    prims = frame_prims(s, s.shown())
    pts = prims["laser"].data
    assert len(pts) > 500
    d = point_segment_distance(pts, s.global_map.solid_segments).min(axis=1)
    assert np.mean(d < 0.05) > 0.95
    assert len(prims["robot_true"]) == 5 and len(prims["robot_estimate"]) == 5
    # the combined map is drawn in the global frame, on the map's walls where matched
    combined = prims["combined"]
    assert len(combined) > 0 and combined.colors is not None
    matched = (combined.colors == style.COMBINED_MATCHED).all(axis=1)
    mid = (combined.data[matched, :2] + combined.data[matched, 2:]) / 2
    assert np.median(point_segment_distance(mid, s.global_map.solid_segments).min(axis=1)) < 0.05
    loc = s.metrics()["localisation"]
    assert loc["error_m"] < 0.1


def test_live_frames_are_scored_against_the_truth() -> None:
    s = _studio()
    for _ in range(30):
        s.tick(0.05)
    scores = s.metrics()["scores"]
    assert 0.5 < scores["run"]["wall P"] <= 1.0 and 0.0 <= scores["frame"]["wall R"] <= 1.0
    assert scores["frame"]["pose err m"] < 0.05  # exact odometry in the default simulator
    s.scrub(5)
    assert s.metrics()["scores"] == {}  # an old frame: the truth is no longer its truth


def test_map_layer_has_every_wall_and_cabinet_front() -> None:
    m = load_json_map(DEFAULT_MAP)
    prims = map_prims(m)
    assert len(prims["map_walls"]) == len(m.walls)
    assert len(prims["map_fronts"]) == len(m.objects)
    assert all(p.name in PRIM_SPECS for layer in LAYERS for p in layer.prims)


def test_inspect_finds_the_nearest_wall_with_its_numbers() -> None:
    prims = map_prims(load_json_map(DEFAULT_MAP))
    seg = prims["map_walls"].data[0]
    mid = ((seg[0] + seg[2]) / 2 + 0.02, (seg[1] + seg[3]) / 2)
    f = nearest_feature(mid, prims)
    assert f is not None and f.kind == "map wall"
    assert f.distance == pytest.approx(0.02, abs=0.021)
    assert f"length {math.hypot(seg[2] - seg[0], seg[3] - seg[1]):.3f} m" in f.describe()
    assert nearest_feature((100.0, 100.0), prims) is None
    corner = seg[:2]  # two walls meet here: both are listed, nearest first
    found = features_near((corner[0] + 0.01, corner[1]), prims)
    assert len(found) >= 2 and [f.distance for f in found] == sorted(f.distance for f in found)
    assert "distance 5.000 m" in measure_text((0.0, 0.0), (3.0, 4.0))
    assert ray_to_ground((1.0, 2.0, 10.0), (0.0, 0.0, -1.0)) == pytest.approx((1.0, 2.0))


def test_line_colours_show_as_declared() -> None:
    line_colours = {spec.color for spec in PRIM_SPECS.values() if spec.kind == "segments"}
    line_colours |= {style.MEASURE, style.INSPECT, style.COMBINED_UNMATCHED, style.HALLWAY, style.ROOM_JUMP}
    line_colours |= set(style.POSSIBLE_DOOR_KIND.values())
    for rgb in line_colours:
        shown = line_display(rgb)
        assert max(abs(a - b) for a, b in zip(shown, rgb, strict=True)) <= 2, (rgb, shown)


def test_examples_list_maps_not_sim_configs() -> None:
    names = set(example_maps())
    assert "hospital_2019.json" in names
    assert not any(n.endswith("_sim.json") for n in names)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_config_panel_has_an_input_for_every_parameter_and_reverts_bad_values(tmp_path) -> None:
    from pico_studio.cli.serve_cmd import build_app

    args = argparse.Namespace(
        map=None, sim_config=None, config=None, behaviour="wander", source="sim", host="127.0.0.1",
        port=_free_port(), seed=1, export_dir=str(tmp_path), paused=True,
    )
    app = build_app(args, verbose=False)
    try:
        handles = dict(app.layers.handles)
        app.studio.playing = True
        for _ in range(3):
            app.studio.tick(0.05)
            app.redraw()
        assert app.layers.handles == handles and app.layers.sizes["laser"] > 0  # assigned, not re-created
        assert app.layers.handles["laser"].points.dtype == np.float32
        app.studio.playing = False
        inputs = app.config_panel.inputs
        assert set(inputs) == {p.path for p in params(app.studio.cfg)}
        assert type(inputs["perception.scan.segmenter"]).__name__.startswith("GuiDropdown")
        assert type(inputs["perception.locate.laser_motion_without_odometry"]).__name__.startswith("GuiCheckbox")
        inputs["perception.scan.min_length"].value = 0.7  # a server-side write is quiet
        assert app.studio.cfg.perception.scan.min_length == Config().perception.scan.min_length
        with pytest.raises(UserError):  # invalid: below stop_distance
            app.config.edit("ui.wander.clear_distance", 0.1)  # what a user's edit does
        assert app.studio.cfg.ui.wander.clear_distance == Config().ui.wander.clear_distance
        assert inputs["ui.wander.clear_distance"].value == Config().ui.wander.clear_distance
        app.config.edit("perception.scan.min_length", 0.5)
        assert app.studio.cfg.perception.scan.min_length == 0.5
        assert app.update_ms  # the change was redrawn and timed
        restaurant = example_maps()["restaurant_2024.json"]
        app.switch_map(restaurant, restaurant.name, None)
        assert app.studio.map_name == "restaurant_2024.json"
        assert app.studio.playing and app.studio.shown() is not None  # plays at once, robot drawn
        assert app.layers.sizes["robot_true"] > 0
        assert app.layers.sizes["map_walls"] == len(app.studio.global_map.walls)
        assert app.studio.cfg.perception.scan.min_length == 0.5  # tuned values survive a map change
        png = example_maps()["escape_room.png"]  # a heightmap, vectorised on loading
        app.switch_map(png, png.name, None)
        assert app.studio.map_name == "escape_room.png" and app.layers.sizes["map_walls"] > 4
    finally:
        app.stop()


def test_serve_bad_input_is_one_line_and_exit_2(capsys: pytest.CaptureFixture[str], tmp_path) -> None:
    assert main(["serve", "--map", str(tmp_path / "missing.json")]) == 2
    assert "missing.json" in capsys.readouterr().err
    assert main(["serve", "--source", "tape:foo"]) == 2
    assert "--source" in capsys.readouterr().err
    assert main(["serve", "--behaviour", "dance"]) == 2
    assert "dance" in capsys.readouterr().err


def test_behaviour_target_and_plan_are_drawn_in_their_frame() -> None:
    s = _studio()
    for _ in range(5):
        s.tick(0.05)
    frame = s.shown()
    frame.behaviour_target, frame.behaviour_plan = (1.0, 0.0), np.array([[0.0, 0.0], [1.0, 0.0]])
    frame.behaviour_frame = "global"
    assert frame_prims(s, frame)["target"].data[0] == pytest.approx([1.0, 0.0])
    frame.behaviour_frame, frame.behaviour_pose = "odom", (0.0, 0.0, 0.0)
    robot = s.robot_pose_in_map(frame)
    # the target 1 m ahead of where the behaviour thinks it is = 1 m ahead of the robot
    ahead = (robot[0] + math.cos(robot[2]), robot[1] + math.sin(robot[2]))
    assert frame_prims(s, frame)["target"].data[0] == pytest.approx(ahead)
    assert len(frame_prims(s, frame)["plan"]) == 1


def test_core_behaviours_run_on_the_page_and_their_plan_is_drawn() -> None:
    s = Studio(Config(), load_json_map(DEFAULT_MAP), make_source_factory("sim", None, 2), behaviour="hospital:1,0")
    for _ in range(30):
        s.tick(0.05)
    frame = s.shown()
    assert frame.behaviour_state.startswith("hospital") and frame.behaviour_frame == "global"
    plan = frame_prims(s, frame)["plan"].data
    assert len(plan) >= 1
    x0, y0, x1, y1 = s.global_map.bounds
    assert ((plan[:, [0, 2]] >= x0 - 0.5) & (plan[:, [0, 2]] <= x1 + 0.5)).all()
    s.set_behaviour("escape-room")
    s.tick(0.05)
    assert s.shown().behaviour_state.startswith("escape-room")


def test_never_seen_map_walls_are_dashed_until_the_robot_sees_them() -> None:
    s = _studio()
    s.tick(0.05)
    m = s.global_map

    def unseen_walls() -> tuple[np.ndarray, set[int]]:
        wm = s.shown().wm
        seen = np.asarray(wm.combined.map_wall_seen, bool)
        assert len(seen) == len(m.walls)
        dashes = frame_prims(s, s.shown())["combined_unseen"].data
        # every dash lies on a wall never seen; every such wall has a dash on its middle
        walls = m.wall_segments
        d = point_segment_distance((dashes[:, :2] + dashes[:, 2:]) / 2, walls)
        on = d.argmin(axis=1)
        assert (d.min(axis=1) < 1e-6).all()
        mids = (walls[:, :2] + walls[:, 2:]) / 2
        covered = point_segment_distance(mids, dashes).min(axis=1) < 1e-6
        assert (covered == ~seen).all()
        return seen, set(on.tolist())

    seen0, _ = unseen_walls()
    for _ in range(60):
        s.tick(0.05)
    seen1, dashed = unseen_walls()
    assert seen1.sum() > seen0.sum() and (seen1 | ~seen0).all()  # seen stays seen
    assert not (dashed & set(np.flatnonzero(seen1).tolist()))


def test_dashes_cover_the_middle_and_a_share_of_each_wall() -> None:
    from pico_studio.ui.scene_data import dash_segments

    segs = np.array([[0.0, 0.0, 2.0, 0.0], [0.0, 1.0, 0.0, 1.1]])
    dashes, owner = dash_segments(segs, 0.15, 0.1)
    lengths = np.hypot(dashes[:, 2] - dashes[:, 0], dashes[:, 3] - dashes[:, 1])
    assert lengths[owner == 0].sum() == pytest.approx(2.0 * 0.15 / 0.25, abs=0.15)
    assert owner.tolist().count(1) == 1 and lengths[owner == 1][0] == pytest.approx(0.1)  # short: whole
    assert point_segment_distance(np.array([[1.0, 0.0]]), dashes[owner == 0]).min() < 1e-9


def test_doors_scan_corners_entrance_and_room_watch_are_drawn_from_the_world_model() -> None:
    s = _studio()
    for _ in range(40):
        s.tick(0.05)
    frame = s.shown()
    wm = frame.wm
    robot = s.robot_pose_in_map(frame)
    # fill the fields this stretch of the run may not have, as the perceptor would
    wm.spike_corners = np.array([[1.0, 0.0]])
    wm.vector_corners, wm.vector_corner_inner = np.array([[0.0, 1.0], [2.0, 0.0]]), np.array([True, False])
    wm.combined.possible_doors = np.array([[0.0, 0.0, 1.0, 0.0], [1.0, 1.0, 1.0, 2.0]])
    wm.combined.possible_door_kind = np.array(["loose_wall", "loose_loose"], dtype=object)
    wm.entrance, wm.hallway = (0.0, 2.0), True
    wm.room = {"side_range": 1.5, "jump": 0.9, "room": True, "edges": 2, "objects": 1}
    wm.laser_motion, wm.laser_motion_matches = (0.1, 0.0, 0.01), 5
    prims = frame_prims(s, frame)
    c, sn = math.cos(robot[2]), math.sin(robot[2])
    assert prims["spike_corners"].data[0] == pytest.approx([robot[0] + c, robot[1] + sn])
    assert prims["vector_corners"].colors.tolist() == [list(style.VECTOR_CORNER_INNER), list(style.VECTOR_CORNER_OUTER)]
    # doors in the global frame are the combined map's, possible doors coloured by kind
    assert prims["doors"].data == pytest.approx(np.asarray(wm.combined.doors).reshape(-1, 4))
    assert prims["possible_doors"].data == pytest.approx(wm.combined.possible_doors)
    kinds = [list(style.POSSIBLE_DOOR_KIND[k]) for k in ("loose_wall", "loose_loose")]
    assert prims["possible_doors"].colors.tolist() == kinds
    assert prims["entrance"].colors.tolist() == [list(style.HALLWAY)]
    assert prims["entrance"].data[0, 2:] == pytest.approx([robot[0] + 2 * c, robot[1] + 2 * sn])
    side = prims["room_side"].data[0]
    assert math.hypot(side[2] - side[0], side[3] - side[1]) == pytest.approx(1.5)
    assert prims["room_side"].colors.tolist() == [list(style.ROOM_JUMP)]
    label = prims["room_label"]
    assert "side 1.50 m" in label.text and "jump +0.90 m" in label.text and "objects 1" in label.text and "ROOM" in label.text
    assert math.dist(label.data[0], robot[:2]) < 1.0
    wm.current_map_rms = np.array([0.004, 0.006, 0.005])
    m = s.metrics()
    assert m["room"]["objects"] == 1 and m["hallway"] and m["entrance"] == (0.0, 2.0)
    assert m["fit_rms_mm"] == pytest.approx(5.0)
    assert "walls fitted to 5.0 mm" in metrics_text(m)
    assert m["laser_motion"] == (0.1, 0.0, 0.01) and m["laser_motion_matches"] == 5
    # without a combined map the doors are the perceptor's, zero frame placed on the map
    wm.combined = None
    wm.doors = np.array([[0.0, 0.0, 1.0, 0.0]])
    zero = s.zero_frame_in_map(frame)
    from pico_studio.core.geometry import transform_segments

    assert frame_prims(s, frame)["doors"].data == pytest.approx(transform_segments(wm.doors, zero))


def test_the_log_is_read_while_another_thread_writes_to_it() -> None:
    """A callback thread logs an upload's error while the loop's redraw counts the entries:
    the read copies under the book's lock (iterating the deque raised "deque mutated during
    iteration", which paused the live loop)."""
    import threading

    from pico_studio.ui.logbook import LogBook

    book = LogBook(max_entries=300)
    done = threading.Event()
    errors: list[BaseException] = []

    def write() -> None:
        for i in range(20000):
            book.add("warning" if i % 2 else "error", "upload", f"message {i}", frame=i)
        done.set()

    def read() -> None:
        try:
            while not done.is_set():
                n, warnings = book.counts()
                assert 0 <= warnings <= n <= 300
                assert len(book.newest(50)) <= 50 and len(book.all()) <= 300
        except BaseException as e:  # noqa: BLE001 - reported below
            errors.append(e)

    import sys

    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)  # threads switch often: a read that does not hold the lock is caught
    try:
        readers = [threading.Thread(target=read) for _ in range(2)]
        for t in readers:
            t.start()
        write()
        for t in readers:
            t.join()
    finally:
        sys.setswitchinterval(interval)
    assert not errors, errors
    assert book.counts() == (300, 150)


def test_a_panel_that_fails_to_refresh_is_logged_and_the_others_still_refresh(tmp_path) -> None:  # noqa: ANN001
    from pico_studio.cli.serve_cmd import build_app
    from pico_studio.ui.page import Panel

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    app = build_app(argparse.Namespace(
        map=None, sim_config=None, config=None, behaviour="wander", source="sim", host="127.0.0.1", port=port,
        seed=1, export_dir=str(tmp_path), paused=True), verbose=False)
    try:
        refreshed: list[int] = []

        class Broken(Panel):
            name = "broken"

            def refresh(self, shown) -> None:  # noqa: ANN001
                raise RuntimeError("deque mutated during iteration")

        class Counting(Panel):
            name = "counting"

            def refresh(self, shown) -> None:  # noqa: ANN001
                refreshed.append(shown.length)

        app.panels[:0] = [Broken(app.page)]
        app.panels.append(Counting(app.page))
        for _ in range(3):
            app.studio.tick(0.05)
            app.redraw()
        assert len(refreshed) == 3  # the panels after the broken one were refreshed each time
        (entry,) = [e for e in app.log.all() if e.stage == "broken panel"]
        assert "RuntimeError: deque mutated during iteration" in entry.message
    finally:
        app.stop()
