"""The live ROS 1 source against a real ROS 1 master, with Debian's ROS packages.

A real `rosmaster` on a free port, the real PICO bag played into it with `rosbag play`, and
`rostopic echo` listening on the command topics: the same programs as on the robot.
`./dev test` installs the packages (root + apt); elsewhere the tests skip with the reason,
but under CI they must run, so a missing package fails there.

Every process is started in its own session and killed with its group at the end; every
wait has a deadline, so nothing here can hang.
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import time
import xmlrpc.client
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest
import yaml

from pico_studio.config.sources_params import LiveRosParams, SourcesParams
from pico_studio.core.io import LaserData
from pico_studio.errors import SourceError
from pico_studio.sources import open_bag

pytestmark = [
    pytest.mark.ros,
    pytest.mark.filterwarnings("ignore:notifyAll:DeprecationWarning"),  # inside Debian's rospy
]

BAG = Path(__file__).parent / "data" / "recordings" / "pico_real_2019-05-07.bag"
ROS_PROGRAMS = ("rosmaster", "rosbag", "rostopic")
DEADLINE = 30.0  # seconds any one wait may take before the test fails


def _ros_missing() -> str | None:
    missing = [p for p in ROS_PROGRAMS if shutil.which(p) is None]
    if missing:
        return (
            f"Debian's ROS 1 packages are not installed ({', '.join(missing)} missing); "
            "`./dev test` installs them when run as root with apt"
        )
    from pico_studio.sources.ros_live import import_rospy

    try:
        import_rospy()
    except SourceError as e:
        return str(e)
    return None


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _wait(what: str, condition: Callable[[], bool], timeout: float = DEADLINE) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {timeout:g} s waiting for {what}")
        time.sleep(0.05)


@dataclass
class RosRig:
    """A master on a free port, the processes started against it, and the live source."""

    port: int
    env: dict[str, str]
    logs: Path
    procs: list[subprocess.Popen] = field(default_factory=list)
    source: object = None

    @property
    def uri(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    def start(self, *args: str, capture: bool = False) -> subprocess.Popen:
        log = (self.logs / f"{args[0]}-{len(self.procs)}.log").open("w")
        proc = subprocess.Popen(
            args, env=self.env, start_new_session=True, stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE if capture else log, stderr=log, text=True,
        )
        self.procs.append(proc)
        return proc

    def start_master(self) -> subprocess.Popen:
        master = self.start("rosmaster", "--core", "-p", str(self.port))
        _wait("the ROS master to answer", self.master_answers)
        return master

    def master_answers(self) -> bool:
        try:
            return self.master().getPid("/test")[0] == 1
        except OSError:
            return False

    def master(self) -> xmlrpc.client.ServerProxy:
        return xmlrpc.client.ServerProxy(self.uri)

    def has_subscriber(self, topic: str, prefix: str) -> bool:
        _, _, (_, subscribers, _) = self.master().getSystemState("/test")
        return any(t == topic and any(n.startswith(prefix) for n in nodes) for t, nodes in subscribers)

    def stop(self, proc: subprocess.Popen) -> None:
        if proc.poll() is None:
            for sig, wait in ((signal.SIGINT, 5.0), (signal.SIGKILL, 5.0)):
                try:
                    os.killpg(proc.pid, sig)
                except ProcessLookupError:
                    break
                try:
                    proc.wait(timeout=wait)
                    break
                except subprocess.TimeoutExpired:
                    continue
        if proc.stdout is not None:
            proc.stdout.close()

    def stop_all(self) -> None:
        for proc in reversed(self.procs):
            self.stop(proc)


@pytest.fixture(scope="module")
def ros(tmp_path_factory: pytest.TempPathFactory) -> Iterator[RosRig]:
    reason = _ros_missing()
    if reason is not None:
        if os.environ.get("CI"):
            pytest.fail(f"CI must run the ROS integration test: {reason}")
        pytest.skip(reason)
    from pico_studio.sources.ros_live import LiveRosSource

    home = tmp_path_factory.mktemp("ros_home")
    port = _free_port()
    env = {
        **{k: v for k, v in os.environ.items() if not k.startswith(("ROS_", "PYTHON", "VIRTUAL_ENV"))},
        "ROS_MASTER_URI": f"http://127.0.0.1:{port}",
        "ROS_IP": "127.0.0.1",
        "ROS_HOME": str(home),
        "ROS_LOG_DIR": str(home / "log"),
    }
    rig = RosRig(port, env, home)
    os.environ.setdefault("ROS_HOME", str(home))  # the in-process node's logs, when HOME has none
    try:
        rig.start_master()
        params = SourcesParams(
            ros=LiveRosParams(master_uri=rig.uri, stale_timeout=0.5, master_check_interval=0.2)
        )
        rig.source = LiveRosSource(params)
        rig.source.wait_connected(DEADLINE)
        yield rig
    finally:
        if rig.source is not None:
            rig.source.close()
        rig.stop_all()


def _collect(source: object, count: int, timeout: float = DEADLINE) -> list[LaserData]:
    scans: list[LaserData] = []
    deadline = time.monotonic() + timeout
    while len(scans) < count and time.monotonic() < deadline:
        source.advance(0.02)
        scan = source.read_laser()
        if scan is not None:
            scans.append(scan)
    assert len(scans) >= count, f"only {len(scans)} of {count} scans arrived in {timeout:g} s"
    return scans


def _drain(source: object, quiet: float = 0.5, timeout: float = DEADLINE) -> None:
    """Read and drop scans until none has arrived for `quiet` seconds."""
    deadline = time.monotonic() + timeout
    last = time.monotonic()
    while time.monotonic() - last < quiet and time.monotonic() < deadline:
        source.advance(0.02)
        if source.read_laser() is not None:
            last = time.monotonic()


def _echo_one(rig: RosRig, topic: str, send: Callable[[], None]) -> str:
    """What `rostopic echo -n 1 TOPIC` prints of the first message, while `send()` repeats."""
    echo = rig.start("rostopic", "echo", "-n", "1", topic, capture=True)
    _wait(f"rostopic to subscribe to {topic}", lambda: rig.has_subscriber(topic, "/rostopic"))
    deadline = time.monotonic() + DEADLINE
    while echo.poll() is None and time.monotonic() < deadline:
        rig.source.advance(0.05)
        rig.source.read_laser()
        send()
    if echo.poll() is None:
        rig.stop(echo)
        raise AssertionError(f"rostopic echo {topic} got nothing in {DEADLINE:g} s")
    assert echo.stdout is not None
    out = echo.stdout.read()
    echo.stdout.close()
    assert echo.returncode == 0, f"rostopic echo {topic} failed: {out!r}"
    return out


def test_live_source_receives_the_real_bag_scans(ros: RosRig) -> None:
    known = {f.laser.ranges.astype(np.float32).tobytes() for f in map(open_bag(BAG).frame, range(243))}
    player = ros.start("rosbag", "play", "-q", "-d", "1", str(BAG))
    try:
        scans = _collect(ros.source, 60)
    finally:
        ros.stop(player)
    for scan in scans:
        assert len(scan.ranges) == 1081
        assert scan.angle_min == pytest.approx(-2.356194, abs=1e-5)
        assert scan.angle_max == pytest.approx(2.356194, abs=1e-5)
        assert scan.angle_increment == pytest.approx(0.00436332, abs=1e-7)
        assert scan.range_max == pytest.approx(60.0)
        # exactly one of the recorded scans, beam for beam
        assert scan.ranges.astype(np.float32).tobytes() in known
    assert len({s.timestamp for s in scans}) == len(scans)
    assert ros.source.status().scans_received >= 60


def test_a_recorded_simulation_plays_into_ros(ros: RosRig, tmp_path: Path) -> None:
    """A bag written by pico_studio's recorder is played by `rosbag play` and received
    beam for beam: the recordings are real ROS 1 bags."""
    from pico_studio.cli import main

    out = tmp_path / "sim.bag"
    assert main(["run", "--map", str(BAG.parents[3] / "pico_studio" / "data" / "maps" / "hospital_2019.json"),
                 "--behaviour", "drive:0.2,0,0.1", "--seconds", "3", "--record", str(out)]) == 0
    known = {f.laser.ranges.astype(np.float32).tobytes() for f in map(open_bag(out).frame, range(60))}
    _drain(ros.source)  # scans of an earlier test's player still queued or in flight
    player = ros.start("rosbag", "play", "-q", "-d", "1", str(out))
    try:
        scans = _collect(ros.source, 10)
    finally:
        ros.stop(player)
    for scan in scans:
        assert len(scan.ranges) == 1000 and scan.angle_min == pytest.approx(-2.0, abs=1e-6)
        assert scan.ranges.astype(np.float32).tobytes() in known


def test_base_reference_and_open_door_arrive_on_their_topics(ros: RosRig) -> None:
    player = ros.start("rosbag", "play", "-q", "-l", "-d", "1", str(BAG))
    try:
        _collect(ros.source, 3)  # fresh scans: the base is not held at zero
        out = _echo_one(ros, "/pico/cmd_vel", lambda: ros.source.send_base_reference(0.25, -0.1, 0.3))
        twist = yaml.safe_load(out.split("---")[0])
        assert twist["linear"] == {"x": 0.25, "y": -0.1, "z": 0.0}
        assert twist["angular"] == {"x": 0.0, "y": 0.0, "z": 0.3}
        out = _echo_one(ros, "/pico/open_door", ros.source.open_door)
        assert "---" in out
    finally:
        ros.stop(player)


def test_stale_data_is_reported_and_stops_the_base(ros: RosRig) -> None:
    _wait("the data to go stale", lambda: ros.source.status().stale)
    status = ros.source.status()
    assert "stale" in status.message or "no scan" in status.message
    out = _echo_one(ros, "/pico/cmd_vel", lambda: ros.source.send_base_reference(0.4, 0.0, 0.0))
    twist = yaml.safe_load(out.split("---")[0])
    assert twist["linear"]["x"] == 0.0


def test_scan_with_a_wrong_beam_layout_is_skipped_with_a_warning(ros: RosRig) -> None:
    before = ros.source.skipped_scans
    bad = ros.start(
        "rostopic", "pub", "-r", "5", "/pico/laser", "sensor_msgs/LaserScan",
        "{angle_min: -1.0, angle_max: 1.0, angle_increment: 0.5, range_max: 10.0, ranges: [1, 1, 1]}",
    )
    try:
        _wait("the bad scan to arrive", lambda: ros.source.skipped_scans > before)
    finally:
        ros.stop(bad)
    scan = ros.source.read_laser()  # a bad scan never reaches the reader
    assert scan is None or len(scan.ranges) == 1081
    assert any("/pico/laser" in w and "angle_increment" in w and "ranges holds 3" in w for w in ros.source.warnings)


def test_run_command_on_the_live_robot(ros: RosRig, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """`pico-studio run --source ros` against the master, recording what it saw."""
    import json

    from pico_studio.cli import main

    config = tmp_path / "robot.yaml"
    config.write_text(f"sources:\n  ros:\n    master_uri: {ros.uri}\n")
    out = tmp_path / "live.bag"
    player = ros.start("rosbag", "play", "-q", "-l", "-d", "1", str(BAG))
    try:
        _collect(ros.source, 3)
        code = main(["run", "--source", "ros", "--config", str(config), "--seconds", "1.5",
                     "--behaviour", "drive:0.1,0,0", "--record", str(out), "--json"])
    finally:
        ros.stop(player)
    assert code == 0
    report = json.loads(capsys.readouterr().out)
    assert report["master_up"] and report["frames_read"] >= 20
    assert open_bag(out).frame_count == report["frames_read"]


def test_the_page_on_the_live_robot(ros: RosRig, tmp_path: Path) -> None:
    """`pico-studio serve --source ros`: frames reach the timeline, the status line says
    live, then stale once the scans stop; a reset closes the old connection."""
    import argparse

    from pico_studio.cli.serve_cmd import build_app

    config = tmp_path / "robot.yaml"
    config.write_text(f"sources:\n  ros:\n    master_uri: {ros.uri}\n    stale_timeout: 0.5\n")
    args = argparse.Namespace(
        map=None, sim_config=None, config=str(config), behaviour="stop", source="ros", host="127.0.0.1",
        port=_free_port(), seed=None, export_dir=str(tmp_path), paused=True,
    )
    app = build_app(args, verbose=False)
    studio = app.studio
    try:
        studio.source.wait_connected(DEADLINE)
        player = ros.start("rosbag", "play", "-q", "-l", "-d", "1", str(BAG))
        try:
            _wait("scans on the page's timeline", lambda: (studio.tick(0.05), len(studio.timeline) >= 10)[1])
            app.redraw()
            assert "live:" in app.status_md.content
            assert len(studio.timeline.latest.laser.ranges) == 1081
        finally:
            ros.stop(player)
        _wait("the page to show stale data", lambda: (studio.tick(0.05), studio.source.status().stale)[1])
        app.redraw()
        assert "stale" in app.status_md.content
        first = studio.source
        studio.reset()
        assert not first.ok() and studio.source is not first
    finally:
        app.stop()
        studio.source.close()


def test_master_going_away_is_reported_and_survived(ros: RosRig) -> None:
    master = ros.procs[0]
    ros.stop(master)
    source = ros.source
    _wait("the source to notice the master is gone", lambda: not source.status().master_up)
    assert not source.status().connected and source.ok()  # the loop goes on, like ros::ok()
    assert "no ROS master" in source.status().message
    for _ in range(5):  # the loop keeps running without errors
        source.advance(0.02)
        source.read_laser()
        source.read_odometry()
        source.send_base_reference(0.1, 0.0, 0.0)
        source.open_door()
    ros.procs[0] = ros.start_master()
    _wait("the source to re-register with the restarted master", lambda: source.status().connected)
    player = ros.start("rosbag", "play", "-q", "-d", "1", str(BAG))
    try:
        scans = _collect(source, 5)
    finally:
        ros.stop(player)
    assert all(len(s.ranges) == 1081 for s in scans)
