"""A recording replayed through the robot interface, with random access for a UI timeline.

Bags and CARMEN logs are small (minutes of scans), so a reader decodes the whole file once
into a `Replay`: its scans, odometry readings, recorded base references and (when the file
knows it) the true pose, each sorted by time. A cursor (`now()`) moves through them:

* `advance(dt)` moves the cursor `dt` seconds on (the emc loop's sleep);
* `read_laser()` / `read_odometry()` return the newest reading at or before the cursor that
  was not returned before, else None — a loop slower than the laser drops scans, as the
  real robot's would;
* `seek(index)` / `seek_time(t)` jump anywhere; `frame(index)` reads a frame without moving.

A *frame* of the timeline is one scan with the odometry and truth known at its time.

Damaged stamps: a scan or odometry reading stamped NaN or infinite, or an hour or more away
from both its neighbours in the file (a damaged header stamp: 1e9 s in a 7 s recording
would make a loop stepping 0.05 s run 2e10 steps to reach it), is dropped with a warning
naming its index in the file.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pico_studio.core.io import BaseReference, Frame, LaserData, OdometryData
from pico_studio.errors import SourceError

Pose = tuple[float, float, float]

# Cursor and recorded stamps are compared with this slack, so that a loop stepping in
# float seconds (0.05 + 0.05 + ...) still meets a stamp stored in integer nanoseconds.
TIME_SLACK = 1e-6
STAMP_OUTLIER_S = 3600.0  # a stamp this far from both neighbours in the file is damaged


@dataclass(frozen=True)
class TimedPose:
    time: float
    pose: Pose


@dataclass
class Recording:
    """What a reader decoded from a file: everything sorted by time, plus what it skipped."""

    name: str
    scans: list[LaserData]
    odometry: list[OdometryData] = field(default_factory=list)
    base_references: list[BaseReference] = field(default_factory=list)
    truth: list[TimedPose] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    info: dict[str, object] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.scans = _drop_damaged_stamps(self.scans, [s.timestamp for s in self.scans], "scan", self)
        self.odometry = _drop_damaged_stamps(
            self.odometry, [o.timestamp for o in self.odometry], "odometry reading", self
        )
        self.scans.sort(key=lambda s: s.timestamp)
        self.odometry.sort(key=lambda o: o.timestamp)
        self.base_references.sort(key=lambda b: b.timestamp)
        self.truth.sort(key=lambda p: p.time)


def _drop_damaged_stamps(items: list, stamps: list[float], what: str, rec: Recording) -> list:
    """`items` (in file order) without those whose stamp is not finite or lies more than
    `STAMP_OUTLIER_S` from both neighbours; each dropped one is a warning."""
    t = np.asarray(stamps, dtype=float)
    if len(t) == 0:
        return items
    bad = ~np.isfinite(t)
    if len(t) >= 3:
        finite = np.where(bad, np.nan, t)
        with np.errstate(invalid="ignore"):
            gap_prev = np.abs(np.diff(finite, prepend=np.nan))
            gap_next = np.abs(np.diff(finite, append=np.nan))
        far_prev = np.nan_to_num(gap_prev, nan=np.inf) > STAMP_OUTLIER_S
        far_next = np.nan_to_num(gap_next, nan=np.inf) > STAMP_OUTLIER_S
        bad |= far_prev & far_next
    if not bad.any():
        return items
    idx = np.flatnonzero(bad)
    listed = ", ".join(f"{i} ({t[i]:g} s)" for i in idx[:10])
    more = f" and {len(idx) - 10} more" if len(idx) > 10 else ""
    rec.warnings.append(
        f"{rec.name}: {what}s {listed}{more}: stamp not finite or more than "
        f"{STAMP_OUTLIER_S:g} s from both neighbours (damaged); skipped"
    )
    return [x for x, b in zip(items, bad.tolist(), strict=True) if not b]


class Replay:
    """A `RobotIO` over a `Recording`, plus `advance(dt)` and timeline access."""

    def __init__(self, recording: Recording):
        if not recording.scans:
            raise SourceError(
                "holds no usable laser scan" + _first_warnings(recording.warnings),
                file=recording.name,
            )
        self.recording = recording
        self.name = recording.name
        self._scan_t = np.array([s.timestamp for s in recording.scans])
        self._odom_t = np.array([o.timestamp for o in recording.odometry])
        self._truth_t = np.array([p.time for p in recording.truth])
        self._ref_t = np.array([b.timestamp for b in recording.base_references])
        self.last_base_reference: BaseReference | None = None
        self.door_requests = 0
        self.scans_dropped = 0
        self.seek(0)

    # --- RobotIO -------------------------------------------------------------------------

    def read_laser(self) -> LaserData | None:
        i = self._last_at(self._scan_t, self._cursor)
        if i < self._next_scan:
            return None
        self.scans_dropped += i - self._next_scan
        self._held = False
        self._next_scan = i + 1
        self._frame = i
        return self.recording.scans[i]

    def read_odometry(self) -> OdometryData | None:
        i = self._last_at(self._odom_t, self._cursor)
        if i < self._next_odom:
            return None
        self._next_odom = i + 1
        return self.recording.odometry[i]

    def send_base_reference(self, vx: float, vy: float, va: float) -> None:
        """A recording cannot be steered: the reference is kept for display only."""
        self.last_base_reference = BaseReference(vx, vy, va, self._cursor)

    def open_door(self) -> None:
        self.door_requests += 1

    def ok(self) -> bool:
        """True while frames are left to deliver."""
        return self._next_scan < len(self._scan_t)

    def now(self) -> float:
        return self._cursor

    def advance(self, dt: float) -> None:
        """Move the cursor `dt` seconds on — except right after opening or `seek`, while the
        frame sought has not been read: a loop that advances before it reads (the emc loop
        sleeps, then reads) must meet that frame first, not the one `dt` later."""
        if not dt >= 0.0:
            raise ValueError(f"advance(dt) needs dt >= 0, got {dt!r}")
        if self._held:
            self._held = False
            return
        self._cursor += dt

    # --- timeline ------------------------------------------------------------------------

    @property
    def frame_count(self) -> int:
        return len(self._scan_t)

    @property
    def frame_times(self) -> np.ndarray:
        return self._scan_t

    @property
    def time_span(self) -> tuple[float, float]:
        return float(self._scan_t[0]), float(self._scan_t[-1])

    @property
    def frame_index(self) -> int:
        """Index of the scan last returned by `read_laser` (-1 before the first)."""
        return self._frame

    @property
    def has_odometry(self) -> bool:
        return len(self._odom_t) > 0

    @property
    def has_truth(self) -> bool:
        return len(self._truth_t) > 0

    @property
    def warnings(self) -> list[str]:
        return self.recording.warnings

    def seek(self, index: int) -> None:
        """Put the cursor on scan `index`: the next `read_laser` returns it, and the next
        `read_odometry` the newest odometry at its time."""
        if not 0 <= index < self.frame_count:
            raise IndexError(f"frame {index} is outside 0..{self.frame_count - 1}")
        self._cursor = float(self._scan_t[index])
        self._next_scan = index
        self._next_odom = max(self._last_at(self._odom_t, self._cursor), 0)
        self._frame = index - 1
        self._held = True

    def seek_time(self, t: float) -> None:
        """Put the cursor at time `t`: the next reads return the newest readings at or before it."""
        if not np.isfinite(t):
            raise ValueError(f"seek_time(t) needs a finite time, got {t!r}")
        t0, t1 = self.time_span
        t = min(max(t, t0), t1)
        i = max(self._last_at(self._scan_t, t), 0)
        self.seek(i)
        self._cursor = t

    def frame(self, index: int) -> Frame:
        """Scan `index` with the newest odometry and truth at its time; the cursor stays."""
        scan = self.recording.scans[index]
        t = scan.timestamp
        j = self._last_at(self._odom_t, t)
        truth = self._truth_at(t)
        return Frame(
            laser=scan,
            odometry=self.recording.odometry[j] if j >= 0 else None,
            time=t,
            truth={"pose": truth} if truth is not None else {},
        )

    def truth_pose(self) -> Pose | None:
        """The recorded true pose at the current frame (CARMEN's corrected pose, the
        simulator's pose in a recording of a simulated run); None where the file has none."""
        t = self._scan_t[self._frame] if self._frame >= 0 else self._cursor
        return self._truth_at(float(t))

    def base_reference_at(self, t: float) -> BaseReference | None:
        """The recorded base reference in force at time `t` (None before the first)."""
        j = self._last_at(self._ref_t, t)
        return self.recording.base_references[j] if j >= 0 else None

    def summary(self) -> dict[str, object]:
        t0, t1 = self.time_span
        beams = sorted({len(s.ranges) for s in self.recording.scans})
        return {
            "file": self.name,
            "frames": self.frame_count,
            "duration_s": round(t1 - t0, 6),
            "beams": beams,
            "odometry_readings": len(self._odom_t),
            "base_references": len(self._ref_t),
            "truth_poses": len(self._truth_t),
            "warnings": list(self.recording.warnings),
            **self.recording.info,
        }

    # --- helpers -------------------------------------------------------------------------

    def _truth_at(self, t: float) -> Pose | None:
        j = self._last_at(self._truth_t, t)
        return self.recording.truth[j].pose if j >= 0 else None

    @staticmethod
    def _last_at(times: np.ndarray, t: float) -> int:
        """Index of the last stamp at or before `t` (with slack); -1 if none."""
        return int(np.searchsorted(times, t + TIME_SLACK, side="right")) - 1


def _first_warnings(warnings: list[str], n: int = 3) -> str:
    if not warnings:
        return ""
    more = f" (and {len(warnings) - n} more)" if len(warnings) > n else ""
    return ": " + "; ".join(warnings[:n]) + more
