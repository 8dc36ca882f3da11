"""The page's recording controls: record a run to a bag, jump within a recording."""

from __future__ import annotations

import argparse
import socket
from pathlib import Path

import pytest

from pico_studio.sources import open_bag


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _app(tmp_path: Path, source: str = "sim"):  # -> StudioApp
    from pico_studio.cli.serve_cmd import build_app

    args = argparse.Namespace(
        map=None, sim_config=None, config=None, behaviour="wander", source=source, host="127.0.0.1",
        port=_free_port(), seed=1, export_dir=str(tmp_path), paused=True,
    )
    return build_app(args, verbose=False)


def test_record_button_writes_the_run_as_a_bag(tmp_path: Path) -> None:
    app = _app(tmp_path)
    try:
        controls, studio = app.recording, app.studio
        controls.toggle()
        assert controls.recorder.active and controls.button.label == "Stop recording"
        for _ in range(20):
            studio.tick(0.05)
        app.redraw()
        assert "20 scans so far" in controls.text.content
        controls.toggle()
        assert not controls.recorder.active and controls.button.label == "Record"
        bags = list(tmp_path.glob("pico_studio_run_*.bag"))
        assert len(bags) == 1 and str(bags[0]) in controls.text.content
        replay = open_bag(bags[0])
        assert replay.frame_count == 20 and replay.has_truth and replay.has_odometry
        assert replay.summary()["base_references"] > 0  # wander's commands
    finally:
        app.stop()


def test_reset_ends_a_recording_with_a_readable_file(tmp_path: Path) -> None:
    app = _app(tmp_path)
    try:
        app.recording.toggle()
        for _ in range(5):
            app.studio.tick(0.05)
        app.studio.reset()
        app.redraw()
        assert not app.recording.recorder.active
        for _ in range(5):
            app.studio.tick(0.05)  # the new session records nothing
        (bag,) = tmp_path.glob("*.bag")
        assert open_bag(bag).frame_count == 5
    finally:
        app.stop()


def test_recording_position_jumps_within_the_whole_bag(recordings_dir: Path, tmp_path: Path) -> None:
    app = _app(tmp_path, f"bag:{recordings_dir / 'pico_real_2019-05-07.bag'}")
    try:
        controls, studio = app.recording, app.studio
        app.redraw()
        assert app.timeline.max == 242  # the one scrubber covers the whole file
        assert app.behaviour.folder.visible is False and app.behaviour.teleop_folder.visible is False
        controls.seek(100)
        assert studio.source.frame_index == 100
        assert studio.timeline.latest.time == pytest.approx(studio.source.frame_times[100])
        assert studio.timeline.latest.wm is not None  # perceived at once
        assert "recording frame 101 / 243 · 2.80 / 6.80 s" in app.status_md.content
        assert not studio.playing and app.play.label == "Play"
        for _ in range(10):
            studio.tick(0.05)
        app.redraw()
        assert app.timeline.value == studio.source.frame_index > 100
        app.run.scrub(5)  # what the page's scrubber does
        assert studio.source.frame_index == 5 and app.timeline.value == 5
    finally:
        app.stop()


def test_simulator_has_no_recording_position(tmp_path: Path) -> None:
    app = _app(tmp_path)
    try:
        assert app.behaviour.folder.visible is not False
        assert "recording frame" not in app.status_md.content
    finally:
        app.stop()


def test_a_damaged_recording_plays_and_says_what_was_skipped(recordings_dir: Path, tmp_path: Path) -> None:
    data = (recordings_dir / "pico_real_2019-05-07.bag").read_bytes()
    cut = tmp_path / "cut.bag"
    cut.write_bytes(data[: len(data) // 2])
    app = _app(tmp_path, f"bag:{cut}")
    try:
        app.recording.seek(10)
        assert app.studio.timeline.latest.wm is not None
        text = app.recording.text.content
        assert "problem(s)" in text and "index is unusable" in text
    finally:
        app.stop()
