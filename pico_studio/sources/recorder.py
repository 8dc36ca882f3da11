"""Record a run as a ROS 1 bag, the robot's own topics, so that ROS tools and
`pico_studio.sources.bag` play it alike.

| what               | topic (`cfg.sources.topics`) | type                       |
|--------------------|------------------------------|----------------------------|
| laser scans        | laser                        | sensor_msgs/LaserScan      |
| odometry           | odometry                     | nav_msgs/Odometry (absolute pose, yaw as a quaternion) |
| base references    | base_reference               | geometry_msgs/Twist        |
| open-door requests | open_door                    | std_msgs/Empty             |
| true pose (sim)    | true_pose                    | geometry_msgs/PoseStamped in frame `map` |

Each message is stored at its own stamp (integer nanoseconds), so a replay meets the same
times. Odometry in `delta` form (the 2024 interface) is integrated into an absolute pose
first, as nav_msgs/Odometry holds a pose.
"""

from __future__ import annotations

import math
from pathlib import Path
from types import TracebackType
from typing import Any

import numpy as np
from rosbags.rosbag1 import Writer, WriterError
from rosbags.typesys import Stores, get_typestore

from pico_studio.config.sources_params import TopicParams
from pico_studio.core.geometry import compose
from pico_studio.core.io import BaseReference, Frame, LaserData, OdometryData
from pico_studio.errors import SourceError

_TS = get_typestore(Stores.ROS1_NOETIC)
_T = _TS.types

LASER_FRAME = "pico/laser"
ODOM_FRAME = "odom"
BASE_FRAME = "pico/base_link"
MAP_FRAME = "map"


class BagRecorder:
    """Writes a ROS 1 bag; use as a context manager or call `close()`."""

    def __init__(
        self,
        path: str | Path,
        topics: TopicParams | None = None,
        *,
        compression: str = "none",
        overwrite: bool = False,
    ):
        self.path = Path(path)
        self.topics = topics or TopicParams()
        if self.path.exists():
            if not overwrite:
                raise SourceError("exists already; not overwriting a recording", file=self.path)
            self.path.unlink()
        if not self.path.parent.is_dir():
            raise SourceError("its folder does not exist", file=self.path)
        self._writer = Writer(self.path)
        if compression != "none":
            formats = {"lz4": Writer.CompressionFormat.LZ4, "bz2": Writer.CompressionFormat.BZ2}
            if compression not in formats:
                raise SourceError(f"unknown compression {compression!r}; use none, lz4 or bz2",
                                  field="sources.recorder.compression")
            self._writer.set_compression(formats[compression])
        try:
            self._writer.open()
        except (OSError, WriterError) as e:
            raise SourceError(f"cannot be written ({e})", file=self.path) from None
        self._connections: dict[str, Any] = {}
        self._seq: dict[str, int] = {}
        self._pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
        self.counts: dict[str, int] = {}
        self.closed = False

    # --- what a run records --------------------------------------------------------------

    def record(self, frame: Frame, command: Any = None) -> None:
        """One tick of a session: the new laser and odometry readings, the command sent
        (anything with vx, vy, va and optionally open_door) and the true pose if known."""
        if frame.laser is not None:
            self.record_laser(frame.laser)
        if frame.odometry is not None:
            self.record_odometry(frame.odometry)
        pose = frame.truth.get("pose") if frame.truth else None
        if pose is not None:
            self.record_true_pose(frame.time, tuple(float(v) for v in pose))  # type: ignore[arg-type]
        if command is not None:
            self.record_base_reference(BaseReference(command.vx, command.vy, command.va, frame.time))
            if getattr(command, "open_door", False):
                self.record_open_door(frame.time)

    def record_laser(self, scan: LaserData) -> None:
        t = scan.timestamp
        msg = _T["sensor_msgs/msg/LaserScan"](
            header=self._header(self.topics.laser, t, LASER_FRAME),
            angle_min=scan.angle_min, angle_max=scan.angle_max,
            angle_increment=scan.angle_increment,
            time_increment=0.0, scan_time=0.0,
            range_min=scan.range_min, range_max=scan.range_max,
            ranges=np.asarray(scan.ranges, dtype=np.float32),
            intensities=np.zeros(0, dtype=np.float32),
        )
        self._write(self.topics.laser, "sensor_msgs/msg/LaserScan", t, msg)

    def record_odometry(self, odometry: OdometryData) -> None:
        if odometry.form == "delta":
            self._pose = compose(self._pose, (odometry.x, odometry.y, odometry.a))
        else:
            self._pose = (odometry.x, odometry.y, odometry.a)
        t = odometry.timestamp
        covariance = np.zeros(36, dtype=np.float64)
        msg = _T["nav_msgs/msg/Odometry"](
            header=self._header(self.topics.odometry, t, ODOM_FRAME),
            child_frame_id=BASE_FRAME,
            pose=_T["geometry_msgs/msg/PoseWithCovariance"](pose=_pose_msg(self._pose), covariance=covariance),
            twist=_T["geometry_msgs/msg/TwistWithCovariance"](
                twist=_twist_msg(0.0, 0.0, 0.0), covariance=covariance.copy()
            ),
        )
        self._write(self.topics.odometry, "nav_msgs/msg/Odometry", t, msg)

    def record_base_reference(self, ref: BaseReference) -> None:
        msg = _twist_msg(ref.vx, ref.vy, ref.va)
        self._write(self.topics.base_reference, "geometry_msgs/msg/Twist", ref.timestamp, msg)

    def record_open_door(self, t: float) -> None:
        self._write(self.topics.open_door, "std_msgs/msg/Empty", t, _T["std_msgs/msg/Empty"]())

    def record_true_pose(self, t: float, pose: tuple[float, float, float]) -> None:
        msg = _T["geometry_msgs/msg/PoseStamped"](
            header=self._header(self.topics.true_pose, t, MAP_FRAME), pose=_pose_msg(pose)
        )
        self._write(self.topics.true_pose, "geometry_msgs/msg/PoseStamped", t, msg)

    def close(self) -> None:
        if not self.closed:
            self._writer.close()
            self.closed = True

    def __enter__(self) -> BagRecorder:
        return self

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        self.close()

    # --- helpers -------------------------------------------------------------------------

    def _write(self, topic: str, msgtype: str, t: float, msg: Any) -> None:
        if self.closed:
            raise SourceError("the recording is closed", file=self.path)
        if not math.isfinite(t) or t < 0:
            raise SourceError(f"cannot record a message at time {t!r} (needs a time >= 0)", file=self.path, field=topic)
        conn = self._connections.get(topic)
        if conn is None:
            conn = self._writer.add_connection(topic, msgtype, typestore=_TS, callerid="/pico_studio")
            self._connections[topic] = conn
        self._writer.write(conn, _to_ns(t), _TS.serialize_ros1(msg, msgtype))
        self.counts[topic] = self.counts.get(topic, 0) + 1

    def _header(self, topic: str, t: float, frame_id: str) -> Any:
        seq = self._seq.get(topic, 0)
        self._seq[topic] = seq + 1
        ns = _to_ns(t)
        stamp = _T["builtin_interfaces/msg/Time"](sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)
        return _T["std_msgs/msg/Header"](seq=seq, stamp=stamp, frame_id=frame_id)


def _to_ns(t: float) -> int:
    return round(t * 1e9)


def _pose_msg(pose: tuple[float, float, float]) -> Any:
    x, y, a = pose
    return _T["geometry_msgs/msg/Pose"](
        position=_T["geometry_msgs/msg/Point"](x=float(x), y=float(y), z=0.0),
        orientation=_T["geometry_msgs/msg/Quaternion"](
            x=0.0, y=0.0, z=math.sin(a / 2.0), w=math.cos(a / 2.0)
        ),
    )


def _twist_msg(vx: float, vy: float, va: float) -> Any:
    return _T["geometry_msgs/msg/Twist"](
        linear=_T["geometry_msgs/msg/Vector3"](x=float(vx), y=float(vy), z=0.0),
        angular=_T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=float(va)),
    )
