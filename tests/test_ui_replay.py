"""Replays on the page: one scrubber over the whole file, times from its start, no driving
controls, status and buttons that agree, and a jump that shows the world model built up to
the frame (the same as playing there)."""

from __future__ import annotations

import argparse
import re
import socket
from pathlib import Path

import numpy as np
import pytest

from pico_studio.config import Config
from pico_studio.errors import UserError
from pico_studio.ui.replay import ReplayDriver
from pico_studio.ui.runtime import Studio
from pico_studio.ui.sources import make_source_factory


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _app(tmp_path: Path, source: str, workers: int = 2):  # -> StudioApp
    from pico_studio.cli.serve_cmd import build_app

    args = argparse.Namespace(
        map=None, sim_config=None, config=None, behaviour="wander", source=source, host="127.0.0.1",
        port=_free_port(), seed=1, export_dir=str(tmp_path), paused=True, workers=workers,
    )
    return build_app(args, verbose=False)


def test_a_bag_replay_shows_relative_time_one_scrubber_and_no_driving(recordings_dir: Path, tmp_path: Path) -> None:
    app = _app(tmp_path, f"bag:{recordings_dir / 'pico_real_2019-05-07.bag'}")
    try:
        app.seek(0)
        assert app.timeline.max == app.studio.source.frame_count - 1 == 242  # the whole file
        assert not hasattr(app.recording, "position")  # no second scrubber
        status = app.status_md.content
        assert "behaviour" not in status and not re.search(r"\d{9,}\.\d", status), status  # no epoch time
        assert "0.00 / 6.80 s" in status
        assert app.behaviour.folder.visible is False and app.behaviour.teleop_folder.visible is False
        assert not app.behaviour.commands  # no teleop keys either
        app.studio.playing = True
        app.studio.speed = float("inf")  # as fast as it computes
        while app.studio.playing:
            app.replay.play(0.05, app.studio.speed)
        app.redraw()
        assert app.studio.source.frame_index == 242 and app.timeline.value == 242
        assert "paused" in app.status_md.content and app.play.label == "Play"  # they agree at the end
        # no map, so no localiser: its figures are absent, not "quality 0.00"
        assert app.studio.metrics()["localisation"] == {}
    finally:
        app.stop()


def test_a_jump_shows_the_world_model_built_up_to_the_frame(recordings_dir: Path) -> None:
    studio = Studio(Config(), None, make_source_factory(f"carmen:{recordings_dir / 'intel-corrected.log.gz'}", None),
                    behaviour="stop", map_name="intel")
    driver = ReplayDriver(studio, every=10)
    studio.playing = True
    for _ in range(75):
        driver.step()
    played = studio.timeline.latest
    assert played is not None and played.wm is not None
    walls = played.wm.local_map.walls.copy()
    assert len(walls) > 3  # built up over 75 scans
    driver.seek(5)
    assert len(studio.shown().wm.local_map.walls) < len(walls)  # earlier: less seen
    frame = driver.seek(74)
    assert driver.last_seek["from"] == 70 and driver.last_seek["frames"] == 5  # from a checkpoint
    assert frame is not None and frame.time == played.time
    np.testing.assert_allclose(frame.wm.local_map.walls, walls)
    # another config: the checkpoints made with the old one are not used when the start is near
    studio.set_param("perception.scan.min_length", 0.5)
    driver.seek(30)
    assert driver.last_seek["from"] == 0 and driver.last_seek["current_params"]


def test_recorded_truth_is_drawn_as_a_trajectory(recordings_dir: Path) -> None:
    from pico_studio.ui.scene_data import frame_prims

    studio = Studio(Config(), None, make_source_factory(f"carmen:{recordings_dir / 'intel-corrected.log.gz'}", None),
                    behaviour="stop", map_name="intel")
    driver = ReplayDriver(studio)
    frame = driver.step()
    prims = frame_prims(studio, frame)
    assert len(prims["truth_path"]) > 100  # the whole corrected trajectory
    assert studio.robot_pose_in_map(frame) == pytest.approx(frame.truth_pose)  # the view is in the truth frame


def test_a_guarded_error_and_a_skipped_message_go_to_the_log(recordings_dir: Path, tmp_path: Path) -> None:
    data = (recordings_dir / "pico_real_2019-05-07.bag").read_bytes()
    cut = tmp_path / "cut.bag"
    cut.write_bytes(data[: len(data) // 2])
    app = _app(tmp_path, f"bag:{cut}")
    try:
        app.seek(10)
        sources = [e for e in app.log.all() if e.stage == "source"]
        assert sources and "index is unusable" in " ".join(e.message for e in sources)

        def bad(_event: object) -> None:
            raise UserError("nope", field="thing")

        app.page.guard("testing", bad)(None)
        (entry,) = [e for e in app.log.all() if e.stage == "testing"]
        assert entry.level == "error" and entry.frame == 10 and "nope" in entry.message
        assert entry.time == pytest.approx(app.studio.source.frame_times[10] - app.studio.source.frame_times[0])
        app.redraw()
        assert "entries" in app.log_panel.summary.content
        app.jump_to_frame(3)  # what a click on an entry does
        assert app.studio.source.frame_index == 3
    finally:
        app.stop()


def test_serve_workers_1_re_judges_in_the_page_process(recordings_dir: Path, tmp_path: Path) -> None:
    """`serve --workers 1`: the What-if tab judges in a thread of the page's process, no
    worker processes (a machine with one core)."""
    from pico_studio.evaluation.rejudge import Rejudger

    app = _app(tmp_path, f"bag:{recordings_dir / 'pico_real_2019-05-07.bag'}", workers=1)
    try:
        assert app.whatif.workers == 1
        assert isinstance(app.whatif._workers["b"], Rejudger)  # started on attach: a thread
    finally:
        app.stop()
