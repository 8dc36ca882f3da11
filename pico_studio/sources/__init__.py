"""Data sources beside the simulator: recordings (ROS 1 bags, CARMEN logs), the live robot
over ROS 1, and the bag recorder.

Every source is a `pico_studio.core.io.RobotIO` with `advance(dt)`; replays add a timeline
(`frame_count`, `time_span`, `seek`, `frame`) and `truth_pose()` where the file knows it.
Nothing here imports rospy unless the live source is opened.
"""

from __future__ import annotations

from pico_studio.sources.bag import open_bag, read_bag
from pico_studio.sources.carmen import open_carmen, read_carmen
from pico_studio.sources.open_source import SOURCE_HELP, SourceSpec, open_source, parse_source
from pico_studio.sources.replay import Recording, Replay, TimedPose

__all__ = [
    "SOURCE_HELP",
    "Recording",
    "Replay",
    "SourceSpec",
    "TimedPose",
    "open_bag",
    "open_carmen",
    "open_source",
    "parse_source",
    "read_bag",
    "read_carmen",
]
