"""The live ROS source without a master: lazy rospy, clear errors, no crash."""

from __future__ import annotations

import subprocess
import sys

import pytest

from pico_studio.config.sources_params import LiveRosParams, SourcesParams
from pico_studio.errors import SourceError


def test_pico_studio_does_not_import_rospy() -> None:
    code = (
        "import sys, pico_studio.sources, pico_studio.cli, pico_studio.sources.recorder\n"
        "from pico_studio.sources import open_source\n"
        "assert 'rospy' not in sys.modules, 'rospy imported'\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, timeout=60)


def test_missing_rospy_is_a_clear_error(monkeypatch: pytest.MonkeyPatch, tmp_path) -> None:
    from pico_studio.sources import ros_live

    monkeypatch.setitem(sys.modules, "rospy", None)  # import rospy -> ImportError
    monkeypatch.setattr(ros_live, "DEBIAN_ROS_PATH", str(tmp_path))
    with pytest.raises(SourceError) as err:
        ros_live.import_rospy()
    text = str(err.value)
    assert "python3-rospy" in text and "ros.pth" in text and "--source ros" in text


def test_no_master_is_reported_not_raised() -> None:
    from pico_studio.sources.ros_live import LiveRosSource, import_rospy

    try:
        import_rospy()
    except SourceError as e:
        pytest.skip(str(e))
    import socket

    with socket.socket() as s:  # a port where nothing listens
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    params = SourcesParams(ros=LiveRosParams(master_uri=f"http://127.0.0.1:{port}", master_check_interval=0.1))
    source = LiveRosSource(params)
    try:
        assert source.ok()  # like ros::ok(): the loop runs on while there is no master
        status = source.status()
        assert not status.connected
        assert not status.master_up and status.stale
        assert f"no ROS master at http://127.0.0.1:{port}" in status.message
        source.send_base_reference(0.3, 0.0, 0.0)  # nothing to send to: no crash
        source.open_door()
        assert source.read_laser() is None and source.read_odometry() is None
        with pytest.raises(SourceError, match="sources.ros.master_uri: no ROS master"):
            source.wait_connected(0.3)
    finally:
        source.close()
    assert not source.ok()


def test_master_uri_is_checked() -> None:
    from pico_studio.config.io import from_dict
    from pico_studio.errors import ConfigError

    with pytest.raises(ConfigError, match="sources.ros.master_uri"):
        from_dict(SourcesParams, {"ros": {"master_uri": "robot:11311"}}, prefix="sources.")
    with pytest.raises(ConfigError, match="sources.topics.odometry.*same topic"):
        from_dict(SourcesParams, {"topics": {"odometry": "/pico/laser"}}, prefix="sources.")


def test_run_without_a_master_is_one_line_and_exit_2(tmp_path, capsys: pytest.CaptureFixture[str]) -> None:
    from pico_studio.cli import main
    from pico_studio.sources.ros_live import import_rospy

    try:
        import_rospy()
    except SourceError as e:
        pytest.skip(str(e))
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    config = tmp_path / "robot.yaml"
    config.write_text(f"sources:\n  ros:\n    master_uri: http://127.0.0.1:{port}\n    connect_timeout: 0.5\n")
    assert main(["run", "--source", "ros", "--config", str(config), "--seconds", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"no ROS master at http://127.0.0.1:{port}" in err
