"""Parameters of the data sources: ROS topic names, the live robot connection, CARMEN logs.

Topic names are configuration because the PICO robots and years differ (older robots used
`/pico/base/reference` for the base); the defaults are the ones of the 2019-era PICO.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pico_studio.config.spec import param, section


@dataclass(frozen=True)
class TopicParams:
    laser: str = param("/pico/laser", help="sensor_msgs/LaserScan topic of the robot's laser")
    odometry: str = param("/pico/odom", help="nav_msgs/Odometry topic of the wheel odometry")
    base_reference: str = param(
        "/pico/cmd_vel", help="geometry_msgs/Twist topic the base references are sent on"
    )
    open_door: str = param("/pico/open_door", help="std_msgs/Empty topic of open-door requests")
    true_pose: str = param(
        "/pico/true_pose",
        help="geometry_msgs/PoseStamped topic holding the simulator's true pose in recordings",
    )

    def check(self) -> list[tuple[str, str]]:
        names = {"laser": self.laser, "odometry": self.odometry,
                 "base_reference": self.base_reference, "open_door": self.open_door,
                 "true_pose": self.true_pose}
        problems = [(k, f"must be a ROS topic name starting with '/', got {v!r}")
                    for k, v in names.items() if not v.startswith("/") or " " in v]
        seen: dict[str, str] = {}
        for k, v in names.items():
            if v in seen:
                problems.append((k, f"is the same topic as {seen[v]} ({v})"))
            seen.setdefault(v, k)
        return problems


@dataclass(frozen=True)
class LiveRosParams:
    master_uri: str = param(
        "http://localhost:11311",
        help="ROS_MASTER_URI of the robot's ROS 1 master (the robot's address when on its network)",
    )
    node_name: str = param("pico_studio", help="Name of pico_studio's ROS node")
    stale_timeout: float = param(
        0.5, lo=0.05, hi=10.0, step=0.05, unit="s",
        help="No scan for this long = stale data: reported, and the base is stopped",
    )
    connect_timeout: float = param(
        10.0, lo=0.1, hi=600.0, step=0.1, unit="s",
        help="How long `pico-studio run --source ros` waits for the master before giving up",
    )
    master_check_interval: float = param(
        1.0, lo=0.1, hi=30.0, step=0.1, unit="s",
        help="How often the master is checked (and re-registered with once it is back)",
    )

    def check(self) -> list[tuple[str, str]]:
        if not self.master_uri.startswith(("http://", "https://")):
            return [("master_uri", f"must look like http://HOST:PORT, got {self.master_uri!r}")]
        return []


@dataclass(frozen=True)
class ReplayParams:
    check_beam_layout: bool = param(
        True, help="Skip (with a warning) scans whose angle fields disagree with their beam count"
    )
    beam_count_tolerance: int = param(
        1, lo=0, hi=50, step=1, unit="beams",
        help="How far (angle_max - angle_min) / angle_increment + 1 may be off the beam count",
    )


@dataclass(frozen=True)
class CarmenParams:
    field_of_view: float = param(
        math.pi, lo=0.1, hi=2 * math.pi, step=0.01, unit="rad",
        help="Field of view of FLASER scans, centred on the robot's x axis (SICK: 180 degrees)",
    )
    range_max: float = param(
        50.0, lo=1.0, hi=200.0, step=1.0, unit="m",
        help="Longest valid range of a CARMEN scan; longer readings are no return",
    )
    range_min: float = param(
        0.0, lo=0.0, hi=1.0, step=0.01, unit="m", help="Shortest valid range of a CARMEN scan"
    )
    pose_is_truth: bool = param(
        True,
        help="The scan lines' pose is the corrected (SLAM) pose, offered as ground truth; "
        "off for raw logs, where it is only odometry",
    )


@dataclass(frozen=True)
class RecorderParams:
    compression: str = param(
        "none", choices=("none", "lz4", "bz2"),
        help="Chunk compression of recorded bags (lz4: ~fast, bz2: smallest; ROS tools read all three)",
    )


@dataclass(frozen=True)
class SourcesParams:
    topics: TopicParams = section(TopicParams, "ROS topic names (live robot and bags)")
    ros: LiveRosParams = section(LiveRosParams, "The live ROS 1 connection (--source ros)")
    replay: ReplayParams = section(ReplayParams, "Replay of recordings (bags and CARMEN logs)")
    carmen: CarmenParams = section(CarmenParams, "CARMEN log files (FLASER/ODOM lines)")
    recorder: RecorderParams = section(RecorderParams, "Recording runs as ROS 1 bags")
