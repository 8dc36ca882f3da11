"""The live robot over ROS 1 (`--source ros`), with rospy from Debian's packages.

Subscribes to the laser (sensor_msgs/LaserScan) and odometry (nav_msgs/Odometry) topics,
publishes base references (geometry_msgs/Twist) and open-door requests (std_msgs/Empty);
topic names and the master URI come from `cfg.sources`. rospy is imported only here and
only when the source is opened, so the rest of pico_studio never needs ROS.

Safety and failures, as the robot's user needs them:

* **Stale data**: no scan for `stale_timeout` seconds (or none yet) makes `status().stale`
  true; while stale every base reference is sent as zero, and a zero is sent once when the
  data goes stale, so a behaviour acting on old scans cannot drive the robot.
* **The master goes away**: a monitor thread asks the master for its pid every
  `master_check_interval`; while it does not answer `status()` says so (`ok()` stays
  true, as `ros::ok()` does: the loop goes on, stale, base at zero); nothing raises. Connections to publishers survive a master's death, so scans may
  keep coming. When it answers again, the node registers its topics anew (a restarted
  master knows nothing of them): publishers that register later reach it again.
* **No master at start**: `rospy.init_node` would block until one appears, so it runs in
  the monitor thread once the master answers; until then `status()` says "waiting".
"""

from __future__ import annotations

import logging
import os
import sys
import threading
import time
import urllib.parse
import xmlrpc.client
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from pico_studio.config.sources_params import SourcesParams
from pico_studio.core.io import LaserData, OdometryData
from pico_studio.errors import SourceError
from pico_studio.sources.convert import beam_layout_problem, yaw_from_quaternion

DEBIAN_ROS_PATH = "/usr/lib/python3/dist-packages"
_INSTALL_HINT = (
    "install Debian's ROS 1 packages (apt-get install python3-rospy python3-sensor-msgs "
    "python3-nav-msgs python3-geometry-msgs python3-std-msgs) and make them importable from "
    f"this Python: a file ros.pth holding the line {DEBIAN_ROS_PATH} in the venv's "
    "site-packages (see the README, 'The real robot')"
)
_MAX_WARNINGS = 50


def import_rospy() -> Any:
    """rospy, from this environment or else from Debian's dist-packages (appended last, so
    the venv's numpy and yaml still win); a `SourceError` saying how to get it otherwise."""
    try:
        import rospy
    except ImportError:
        if Path(DEBIAN_ROS_PATH, "rospy").is_dir() and DEBIAN_ROS_PATH not in sys.path:
            sys.path.append(DEBIAN_ROS_PATH)
        try:
            import rospy
        except ImportError as e:
            raise SourceError(
                f"the live ROS 1 source needs rospy, which cannot be imported ({e}): {_INSTALL_HINT}",
                field="--source ros",
            ) from None
    return rospy


@dataclass(frozen=True)
class LiveStatus:
    connected: bool  # the node is registered with a master that answers
    master_up: bool
    stale: bool  # no scan within stale_timeout (or none yet): the base is held at zero
    last_scan_age: float | None  # seconds since the last scan arrived (wall clock)
    scans_received: int
    message: str  # one line for the UI


class LiveRosSource:
    """A `RobotIO` on the live robot. `advance(dt)` waits until `dt` of wall time passed."""

    def __init__(self, params: SourcesParams | None = None):
        self.params = params or SourcesParams()
        self._ros = self.params.ros
        self._topics = self.params.topics
        self._rospy = import_rospy()
        from geometry_msgs.msg import Twist
        from nav_msgs.msg import Odometry
        from sensor_msgs.msg import LaserScan
        from std_msgs.msg import Empty

        self._msg = {"scan": LaserScan, "odom": Odometry, "twist": Twist, "empty": Empty}
        self._lock = threading.Lock()
        self._scan: LaserData | None = None
        self._scan_seq = self._scan_read = 0
        self._scan_wall: float | None = None
        self._odom: OdometryData | None = None
        self._odom_seq = self._odom_read = 0
        self._handles: dict[str, Any] = {}
        self._connected = False
        self._master_up = False
        self._sent_nonzero = False
        self._closed = threading.Event()
        self._tick: float | None = None
        self.warnings: list[str] = []
        self.skipped_scans = 0
        self._monitor = threading.Thread(target=self._watch_master, name="pico-ros-master", daemon=True)
        self._monitor.start()

    # --- RobotIO -------------------------------------------------------------------------

    def read_laser(self) -> LaserData | None:
        with self._lock:
            if self._scan_seq == self._scan_read:
                return None
            self._scan_read = self._scan_seq
            return self._scan

    def read_odometry(self) -> OdometryData | None:
        with self._lock:
            if self._odom_seq == self._odom_read:
                return None
            self._odom_read = self._odom_seq
            return self._odom

    def send_base_reference(self, vx: float, vy: float, va: float) -> None:
        if self.status().stale:
            vx = vy = va = 0.0
        self._publish_twist(vx, vy, va)

    def open_door(self) -> None:
        pub = self._handles.get("door")
        if pub is not None and self._connected:
            pub.publish(self._msg["empty"]())

    def ok(self) -> bool:
        """True until `close()`, like `ros::ok()` under emc's `io.ok()`: a master that goes
        away is a state of the connection (`status()`), not the end of the program, so a
        loop keeps running — stale, with the base held at zero — until it comes back."""
        return not self._closed.is_set()

    def now(self) -> float:
        return time.time()

    def advance(self, dt: float) -> None:
        """Wait until `dt` seconds after the previous tick (paced, not drifting); stop the
        base if the data went stale meanwhile."""
        now = time.monotonic()
        target = (self._tick if self._tick is not None else now) + dt
        if target > now:
            time.sleep(target - now)
        self._tick = max(target, time.monotonic() - dt)  # fell far behind: catch up, don't burst
        if self._sent_nonzero and self.status().stale:
            self._publish_twist(0.0, 0.0, 0.0)

    # --- beyond RobotIO ------------------------------------------------------------------

    def status(self) -> LiveStatus:
        with self._lock:
            age = None if self._scan_wall is None else time.monotonic() - self._scan_wall
            received = self._scan_seq
        stale = age is None or age > self._ros.stale_timeout
        uri = self._ros.master_uri
        if not self._master_up:
            message = f"no ROS master at {uri}" + ("" if self._connected else " (waiting for it)")
        elif not self._connected:
            message = f"registering with the ROS master at {uri}"
        elif age is None:
            message = f"connected to {uri}; no scan on {self._topics.laser} yet: base stopped"
        elif stale:
            message = f"stale: no scan on {self._topics.laser} for {age:.1f} s: base stopped"
        else:
            message = f"live: {received} scans from {self._topics.laser}"
        return LiveStatus(self._connected and self._master_up, self._master_up, stale, age, received, message)

    def wait_connected(self, timeout: float) -> None:
        """Block until registered with the master, or raise `SourceError` after `timeout`."""
        deadline = time.monotonic() + timeout
        while not self.status().connected:
            if time.monotonic() > deadline:
                raise SourceError(
                    f"{self.status().message} after {timeout:g} s; is roscore running there, "
                    "and is ROS_HOSTNAME/ROS_IP set so the robot can reach this machine?",
                    field="sources.ros.master_uri",
                )
            time.sleep(0.05)

    def close(self) -> None:
        """Stop the base, unregister the topics, stop watching the master."""
        if self._closed.is_set():
            return
        if self._connected and self._master_up:
            self._publish_twist(0.0, 0.0, 0.0)
        self._closed.set()
        self._unregister()
        self._monitor.join(timeout=5.0)

    # --- callbacks (rospy's threads) -----------------------------------------------------

    def _on_scan(self, msg: Any) -> None:
        ranges = np.asarray(msg.ranges, dtype=float)
        a0, a1, inc = float(msg.angle_min), float(msg.angle_max), float(msg.angle_increment)
        problem = beam_layout_problem(len(ranges), a0, a1, inc, self.params.replay)
        if problem is not None:
            self.skipped_scans += 1
            if len(self.warnings) < _MAX_WARNINGS:
                self.warnings.append(f"{self._topics.laser}: scan {msg.header.seq}: {problem[0]}: {problem[1]}; skipped")
            return
        scan = LaserData(
            range_min=float(msg.range_min), range_max=float(msg.range_max),
            angle_min=a0, angle_max=a1, angle_increment=inc,
            timestamp=_stamp(msg), ranges=ranges,
        )
        with self._lock:
            self._scan = scan
            self._scan_seq += 1
            self._scan_wall = time.monotonic()

    def _on_odom(self, msg: Any) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        reading = OdometryData(float(p.x), float(p.y), yaw_from_quaternion(q.x, q.y, q.z, q.w), _stamp(msg))
        with self._lock:
            self._odom = reading
            self._odom_seq += 1

    # --- the master ----------------------------------------------------------------------

    def _watch_master(self) -> None:
        interval = self._ros.master_check_interval
        while not self._closed.is_set():
            up = _master_answers(self._ros.master_uri, timeout=max(interval, 0.5))
            if up and not self._connected:
                self._connect()
            elif up and not self._master_up:
                self._reregister()
            self._master_up = up
            self._closed.wait(interval)

    def _reregister(self) -> None:
        """Tell a restarted master (it forgot us) about our topics, keeping the connections
        that survived it: the same calls rospy makes at start, through the master's and our
        own node's XML-RPC API, so new publishers of the laser reach us again."""
        rospy, t = self._rospy, self._topics
        caller, api = rospy.get_caller_id(), rospy.get_node_uri()
        timeout = max(self._ros.master_check_interval, 0.5)
        master = xmlrpc.client.ServerProxy(self._ros.master_uri, transport=_TimeoutTransport(timeout))
        node = xmlrpc.client.ServerProxy(api, transport=_TimeoutTransport(timeout))
        try:
            for topic, kind in ((t.laser, "scan"), (t.odometry, "odom")):
                _, _, publishers = master.registerSubscriber(caller, topic, self._msg[kind]._type, api)
                node.publisherUpdate("/master", topic, publishers)
            for topic, kind in ((t.base_reference, "twist"), (t.open_door, "empty")):
                master.registerPublisher(caller, topic, self._msg[kind]._type, api)
        except (OSError, xmlrpc.client.Error) as e:
            if len(self.warnings) < _MAX_WARNINGS:
                self.warnings.append(f"re-registering with {self._ros.master_uri} failed ({e})")

    def _connect(self) -> None:
        rospy = self._rospy
        if rospy.core.is_initialized():
            have = os.environ.get("ROS_MASTER_URI", "")
            if have.rstrip("/") != self._ros.master_uri.rstrip("/"):
                self.warnings.append(
                    f"this process's ROS node already talks to {have}; "
                    f"sources.ros.master_uri {self._ros.master_uri} needs a new process"
                )
                return
        else:
            os.environ["ROS_MASTER_URI"] = self._ros.master_uri
            if _is_loopback(self._ros.master_uri) and not (
                os.environ.get("ROS_HOSTNAME") or os.environ.get("ROS_IP")
            ):
                # a local master: be reachable as 127.0.0.1 whatever the host name resolves to
                os.environ["ROS_IP"] = "127.0.0.1"
            # init_node re-configures Python's root logger from ROS's logging file (to a
            # ROS log file); pico_studio's own logging set-up is kept as it was
            root = logging.getLogger()
            handlers, level = root.handlers[:], root.level
            try:
                rospy.init_node(self._ros.node_name, anonymous=True, disable_signals=True)
            finally:
                root.handlers[:] = handlers
                root.setLevel(level)
        self._register()
        self._connected = True

    def _register(self) -> None:
        rospy, t = self._rospy, self._topics
        self._unregister()
        self._handles = {
            "scan": rospy.Subscriber(t.laser, self._msg["scan"], self._on_scan, queue_size=1),
            "odom": rospy.Subscriber(t.odometry, self._msg["odom"], self._on_odom, queue_size=1),
            "twist": rospy.Publisher(t.base_reference, self._msg["twist"], queue_size=1),
            "door": rospy.Publisher(t.open_door, self._msg["empty"], queue_size=1),
        }

    def _unregister(self) -> None:
        for handle in self._handles.values():
            try:
                handle.unregister()
            except Exception:  # noqa: BLE001 - the master may be gone; local clean-up still happens
                pass
        self._handles = {}

    def _publish_twist(self, vx: float, vy: float, va: float) -> None:
        pub = self._handles.get("twist")
        if pub is None or not self._connected:
            return
        msg = self._msg["twist"]()
        msg.linear.x, msg.linear.y, msg.angular.z = float(vx), float(vy), float(va)
        try:
            pub.publish(msg)
        except Exception as e:  # noqa: BLE001 - rospy raises when shutting down; never crash the loop
            if len(self.warnings) < _MAX_WARNINGS:
                self.warnings.append(f"{self._topics.base_reference}: not sent ({e})")
            return
        self._sent_nonzero = bool(vx or vy or va)


def _is_loopback(uri: str) -> bool:
    host = urllib.parse.urlparse(uri).hostname or ""
    return host == "localhost" or host.startswith("127.") or host == "::1"


def _stamp(msg: Any) -> float:
    stamp = msg.header.stamp
    return stamp.to_sec() if (stamp.secs or stamp.nsecs) else time.time()


class _TimeoutTransport(xmlrpc.client.Transport):
    def __init__(self, timeout: float):
        super().__init__()
        self._timeout = timeout

    def make_connection(self, host: Any) -> Any:
        conn = super().make_connection(host)
        conn.timeout = self._timeout
        return conn


def _master_answers(uri: str, timeout: float) -> bool:
    """Whether a ROS master answers getPid at `uri` within `timeout` seconds."""
    try:
        proxy = xmlrpc.client.ServerProxy(uri, transport=_TimeoutTransport(timeout))
        code, _, _ = proxy.getPid("/pico_studio_probe")
        return code == 1
    except (OSError, xmlrpc.client.Error, ValueError):
        return False
