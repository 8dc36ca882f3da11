"""The simulator: a `RobotIO` (emc IO shape) over a world, with ground truth beside it.

    sim = Simulator.from_files("examples/maps/hospital_2019.json", seed=1)
    sim.send_base_reference(0.3, 0.0, 0.0)
    sim.advance(0.05)                 # physics and sensors move on 50 ms of simulated time
    scan = sim.read_laser()           # the newest scan, or None if none arrived since last read
    odom = sim.read_odometry()
    sim.truth.pose                    # ground truth, never through the RobotIO methods

Time: `advance(dt)` (alias `step`) walks through the sensor and gain-redraw events inside
[now, now + dt] in order, moving the base, doors and objects between them, so readings carry
exact timestamps `k / rate` whatever dt the caller uses. Every random draw comes from one seed
(independent streams for laser noise and odometry), so one seed gives a bit-identical run.
With `realtime` the call sleeps until wall time catches up; by default it runs flat out.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from pico_studio.config.map_params import HeightmapParams
from pico_studio.config.sim_params import SimParams
from pico_studio.core.io import LaserData, OdometryData
from pico_studio.errors import MapError, SourceError
from pico_studio.json_map import GlobalMap, load_map
from pico_studio.sim.base import Base
from pico_studio.sim.laser import Laser
from pico_studio.sim.odometry import Odometry
from pico_studio.sim.sim_config import SimConfigFile, check_start_pose, load_sim_config
from pico_studio.sim.truth import GroundTruth
from pico_studio.sim.world import World

Pose = tuple[float, float, float]
_EPS_T = 1e-9  # events this close to the end of a step belong to it


def _legacy_start_center(m: GlobalMap) -> tuple[float, float] | None:
    """Centre of a `start` polygon (the form of `start_area` some team maps use), if it is a
    well-formed list of [i, j] point-index pairs; None otherwise."""
    raw = m.extra.get("start")
    try:
        poly = np.asarray(raw[0] if raw and isinstance(raw[0][0], list) else raw, dtype=np.int64)
        if poly.ndim != 2 or poly.shape[1] != 2 or poly.min() < 0 or poly.max() >= len(m.points):
            return None
    except (TypeError, ValueError, IndexError):
        return None
    c = m.points[np.unique(poly)].mean(axis=0)
    return (float(c[0]), float(c[1]))


class Simulator:
    def __init__(
        self,
        global_map: GlobalMap,
        params: SimParams | None = None,
        sim_config: SimConfigFile | None = None,
        *,
        seed: int | None = None,
        initial_pose: Pose | None = None,
    ):
        self.params = params = params if params is not None else SimParams()
        self.sim_config = sim_config if sim_config is not None else SimConfigFile()
        self.seed = params.seed if seed is None else int(seed)
        laser_seq, odom_seq = np.random.SeedSequence(self.seed).spawn(2)
        self.world = World(global_map, params, self.sim_config)
        speed_cap = None if self.sim_config.disable_speedcap is None else not self.sim_config.disable_speedcap
        start = self._start_pose(initial_pose)
        check_start_pose(start, global_map.bounds, self.sim_config, explicit=initial_pose is not None)
        self.base = Base(params.base, start, speed_cap=speed_cap)
        self._check_start_free(start, initial_pose)
        self.laser = Laser(params.laser, np.random.default_rng(laser_seq))
        self.odometry = Odometry(params.odometry, np.random.default_rng(odom_seq), uncertain=self.sim_config.uncertain_odom)
        self.truth = GroundTruth(self.world, self.base, self.laser, self.odometry, params.truth)
        self._t = 0.0
        self._laser_k = 0
        self._odom_k = 0
        self._gain_k = 1
        self._laser_period = 1.0 / self.laser.profile.rate_hz
        self._odom_period = 1.0 / params.odometry.rate_hz
        # the next event times (k * period)
        self._t_laser, self._t_odom, self._t_gain = 0.0, 0.0, params.odometry.gain_period
        self._new_laser: LaserData | None = None
        self._new_odom: OdometryData | None = None
        self._wall_start: float | None = None
        self.steps = 0
        self._closed = False
        self._due_laser: tuple[Pose, np.ndarray, float] | None = None
        self._emit_due(0.0)
        self._cast_due_scan()

    @classmethod
    def from_files(
        cls,
        map_path: str | Path,
        sim_config_path: str | Path | None = None,
        params: SimParams | None = None,
        *,
        seed: int | None = None,
        map_params: HeightmapParams | None = None,
    ) -> Simulator:
        """A simulator for a map file (JSON or heightmap, vectorised with `map_params`) and
        an optional official simulator config JSON."""
        sim_config = load_sim_config(sim_config_path) if sim_config_path is not None else None
        return cls(load_map(map_path, map_params), params, sim_config, seed=seed)

    # ----- start pose -----------------------------------------------------------------------
    def _start_pose(self, explicit: Pose | None) -> Pose:
        """The explicit pose, else the sim config's, else the centre of the start area facing
        +x (`start_area`, or the `start` polygon some team maps use), else the origin facing +x
        when the robot fits there inside the walls (the official simulator's default), else
        the free place farthest from everything (see `World.farthest_free_place`)."""
        if explicit is not None:
            return tuple(float(v) for v in explicit)  # type: ignore[return-value]
        if self.sim_config.initial_pose is not None:
            return self.sim_config.initial_pose
        center = self.world.map.start_center or _legacy_start_center(self.world.map)
        if center is not None:
            return (center[0], center[1], 0.0)
        origin = (0.0, 0.0, 0.0)  # where the official simulator puts the robot by default
        if self.world.enclosed(origin[:2]) and not Base(self.params.base, origin).collides(origin, self.world.segments()).any():
            return origin
        b = self.params.base
        clearance = math.hypot(b.footprint_length, b.footprint_width) / 2
        place = self.world.farthest_free_place(clearance)
        if place is None:
            raise MapError(
                f"no free place to start: no point inside the walls is {clearance:.2f} m from every obstacle",
                file=self.world.map.source,
                field="start_area",
            )
        return (place[0], place[1], 0.0)

    def _check_start_free(self, start: Pose, explicit: Pose | None) -> None:
        if not self.base.collides(start, self.world.segments()).any():
            return
        where = f"({start[0]:g}, {start[1]:g}, {start[2]:g})"
        if explicit is not None:
            raise SourceError(f"start pose {where} puts the robot inside a wall or obstacle", field="initial_pose")
        if self.sim_config.initial_pose is not None:
            raise SourceError(
                f"start pose {where} puts the robot inside a wall or obstacle",
                file=self.sim_config.source,
                field=self.sim_config.field_of_pose,
            )
        raise MapError(
            f"the centre of the start area {where} puts the robot inside a wall or obstacle",
            file=self.world.map.source,
            field="start_area",
        )

    # ----- RobotIO ----------------------------------------------------------------------------
    def read_laser(self) -> LaserData | None:
        scan, self._new_laser = self._new_laser, None
        return scan

    def read_odometry(self) -> OdometryData | None:
        odom, self._new_odom = self._new_odom, None
        return None if odom is None else self.odometry.deliver(odom)

    def send_base_reference(self, vx: float, vy: float, va: float) -> None:
        for name, v in (("vx", vx), ("vy", vy), ("va", va)):
            if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) or not math.isfinite(v):
                raise SourceError(f"base reference must be a finite number, got {v!r}", field=name)
        self.base.set_reference(float(vx), float(vy), float(va))

    def open_door(self) -> None:
        self.world.request_open_door(self.base.pose[:2])

    def ok(self) -> bool:
        """True until `close()`: a simulator never runs out by itself."""
        return not self._closed

    def close(self) -> None:
        self._closed = True

    def now(self) -> float:
        return self._t

    # ----- time -------------------------------------------------------------------------------
    def advance(self, dt: float) -> None:
        if isinstance(dt, bool) or not isinstance(dt, (int, float, np.floating, np.integer)) or not (
            math.isfinite(dt) and dt >= 0
        ):
            raise SourceError(f"must be a finite, non-negative number of seconds, got {dt!r}", field="dt")
        t_end = self._t + float(dt)
        while True:
            t_next = min(self._t_laser, self._t_odom, self._t_gain, t_end)
            self._integrate(t_next - self._t)
            self._t = t_next
            if t_next >= t_end - _EPS_T:
                break
            self._emit_due(t_next)
        self._t = t_end
        self._emit_due(t_end)
        self._cast_due_scan()
        self.steps += 1
        if self.params.realtime:
            self._pace()

    step = advance

    def _integrate(self, h: float) -> None:
        if h <= 0.0:
            return
        motion = self.base.move(h, self.world.segments(), self.world.kinds(), self._t, self.world.version)
        self.odometry.integrate(motion)
        self.world.update(h, self.base.pose[:2])

    def _emit_due(self, t: float) -> None:
        """Produce every reading whose time has come (at most one of each kind), stamped with
        its scheduled time k / rate (event times are k * period, never accumulated)."""
        due = t + _EPS_T
        if self._t_gain <= due:
            if self.odometry.uncertain:
                self.odometry.redraw_gains()
            while self._t_gain <= due:
                self._gain_k += 1
                self._t_gain = self._gain_k * self.params.odometry.gain_period
        if self._t_odom <= due:
            while self._t_odom <= due:
                self._odom_k += 1
                self._t_odom = self._odom_k * self._odom_period
            self._new_odom = self.odometry.snapshot((self._odom_k - 1) * self._odom_period)
        if self._t_laser <= due:
            while self._t_laser <= due:
                self._laser_k += 1
                self._t_laser = self._laser_k * self._laser_period
            # latch where and what the scan sees; it is cast once, at the end of the step
            # (a long step passes many scan times but delivers only the newest scan)
            self._due_laser = (self.base.pose, self.world.segments(), (self._laser_k - 1) * self._laser_period)

    def _cast_due_scan(self) -> None:
        if self._due_laser is not None:
            self._new_laser = self.laser.scan(*self._due_laser)
            self._due_laser = None

    def _pace(self) -> None:
        now = time.perf_counter()
        if self._wall_start is None:
            self._wall_start = now - self._t
        ahead = self._t - (now - self._wall_start)
        if ahead > 0:
            time.sleep(ahead)
