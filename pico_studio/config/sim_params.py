"""Parameters of the simulator: laser profiles, base, odometry, doors, moving objects, clock.

The numbers of both laser profiles are parameters (the defaults are the robot's facts from
DESIGN.md); `laser.profile` chooses which one the simulated laser uses.
"""

from __future__ import annotations

from dataclasses import dataclass

from pico_studio.config.spec import param, section

NO_RETURN_CHOICES = ("zero", "inf", "range_max")


@dataclass(frozen=True)
class PicoSimLaserParams:
    beams: int = param(1000, lo=2, hi=10000, step=1, help="Number of beams of the simulated laser")
    angle_min: float = param(-2.0, lo=-3.14159, hi=0.0, step=0.01, unit="rad", help="Angle of the first beam")
    angle_max: float = param(2.0, lo=0.0, hi=3.14159, step=0.01, unit="rad", help="Angle of the last beam")
    range_min: float = param(0.01, lo=0.0, hi=1.0, step=0.001, unit="m", help="Shortest valid range")
    range_max: float = param(10.0, lo=0.5, hi=100.0, step=0.5, unit="m", help="Longest valid range")
    noise: float = param(0.01, lo=0.0, hi=0.5, step=0.001, unit="m", help="Half-width of the uniform range noise")
    rate_hz: float = param(20.0, lo=1.0, hi=100.0, step=1.0, unit="Hz", help="Scans per second")


@dataclass(frozen=True)
class HokuyoLaserParams:
    beams: int = param(1081, lo=2, hi=10000, step=1, help="Number of beams of the Hokuyo")
    angle_min: float = param(-2.35619, lo=-3.14159, hi=0.0, step=0.01, unit="rad", help="Angle of the first beam")
    angle_max: float = param(2.35619, lo=0.0, hi=3.14159, step=0.01, unit="rad", help="Angle of the last beam")
    range_min: float = param(0.023, lo=0.0, hi=1.0, step=0.001, unit="m", help="Shortest valid range")
    range_max: float = param(60.0, lo=0.5, hi=100.0, step=0.5, unit="m", help="Longest valid range")
    noise: float = param(0.01, lo=0.0, hi=0.5, step=0.001, unit="m", help="Half-width of the uniform range noise")
    rate_hz: float = param(36.0, lo=1.0, hi=100.0, step=1.0, unit="Hz", help="Scans per second")


@dataclass(frozen=True)
class LaserParams:
    profile: str = param(
        "pico-sim", choices=("pico-sim", "hokuyo"),
        help="Which laser the simulator carries: the official simulator's or the real Hokuyo",
    )
    no_return: str = param(
        "zero", choices=NO_RETURN_CHOICES,
        help="Range of a beam that hits nothing within range_max: zero (plus noise, as the "
        "official simulator), inf (ROS convention) or range_max",
    )
    pico_sim: PicoSimLaserParams = section(PicoSimLaserParams, "The official simulator's laser")
    hokuyo: HokuyoLaserParams = section(HokuyoLaserParams, "The real robot's Hokuyo laser")

    @property
    def active(self) -> PicoSimLaserParams | HokuyoLaserParams:
        return self.hokuyo if self.profile == "hokuyo" else self.pico_sim


@dataclass(frozen=True)
class BaseParams:
    speed_cap: bool = param(True, help="Clamp commands to max_v / max_va (the sim config's disable_speedcap turns it off)")
    max_v: float = param(0.5, lo=0.01, hi=5.0, step=0.01, unit="m/s", help="Speed cap on |vx| and |vy|")
    max_va: float = param(1.2, lo=0.01, hi=10.0, step=0.01, unit="rad/s", help="Speed cap on |va|")
    footprint_length: float = param(0.16, lo=0.01, hi=2.0, step=0.01, unit="m", help="Collision box size along x (forward)")
    footprint_width: float = param(0.36, lo=0.01, hi=2.0, step=0.01, unit="m", help="Collision box size along y (left)")
    max_substep: float = param(
        0.02, lo=0.001, hi=0.1, step=0.001, unit="m",
        help="Longest move between two collision checks near obstacles (keep below the footprint)",
    )


@dataclass(frozen=True)
class OdometryParams:
    rate_hz: float = param(50.0, lo=1.0, hi=1000.0, step=1.0, unit="Hz", help="Odometry readings per second")
    form: str = param(
        "absolute", choices=("absolute", "delta"),
        help="Readings as a pose in the odometry frame (PICO era) or the motion since the previous reading (2024)",
    )
    uncertain: bool = param(False, help="Integrate with wheel-gain errors (the sim config's uncertain_odom)")
    gain_error: float = param(0.002, lo=0.0, hi=0.2, step=0.001, help="Wheel gains are 1 +- U(gain_error)")
    gain_period: float = param(6.0, lo=0.1, hi=600.0, step=0.1, unit="s", help="The gains are re-drawn this often")
    offset_x: float = param(0.0, lo=-1000.0, hi=1000.0, step=0.1, unit="m", help="Odometry frame offset: x of the start pose")
    offset_y: float = param(0.0, lo=-1000.0, hi=1000.0, step=0.1, unit="m", help="Odometry frame offset: y of the start pose")
    offset_a: float = param(0.0, lo=-3.14159, hi=3.14159, step=0.01, unit="rad", help="Odometry frame offset: heading at the start")
    random_offset: bool = param(
        False, help="Draw the odometry start pose from the seed (x, y in +-100 m, any heading) instead of offset_*",
    )


@dataclass(frozen=True)
class DoorParams:
    open_distance: float = param(1.0, lo=0.1, hi=5.0, step=0.1, unit="m", help="A door opens when asked from at most this far in front of it")
    speed: float = param(0.3, lo=0.01, hi=5.0, step=0.01, unit="m/s", help="How fast an opened door slides away")


@dataclass(frozen=True)
class ObjectParams:
    pause_margin: float = param(
        0.3, lo=0.0, hi=5.0, step=0.05, unit="m",
        help="A moving object pauses while the robot is within its half-diagonal plus this margin",
    )
    arrive_tolerance: float = param(0.1, lo=0.001, hi=1.0, step=0.01, unit="m", help="An object has arrived this close to its target")


@dataclass(frozen=True)
class TruthParams:
    straight_tolerance: float = param(0.15, lo=0.0, hi=1.0, step=0.01, unit="rad", help="Walls meeting within this of a straight line form no corner")
    abut_tolerance: float = param(0.03, lo=0.0, hi=0.1, step=0.001, unit="m", help="A map vertex this close to another segment abuts it (a T-junction, touching polygons, a table a few cm off a wall: a gap the laser cannot resolve): that segment's walls count in its corner; a pixel more on a heightmap")
    visible_tolerance: float = param(0.05, lo=0.0, hi=1.0, step=0.01, unit="m", help="A point is unoccluded when the ray to it is blocked no nearer than this before it")
    min_wall_beams: int = param(2, lo=1, hi=100, step=1, help="A visible wall piece is hit by at least this many consecutive beams")
    jamb_min_seen: float = param(0.15, lo=0.0, hi=2.0, step=0.01, unit="m", help="A door is visible when beams of the scan hit each jamb's wall over at least this length")
    jamb_reach: float = param(0.5, lo=0.05, hi=5.0, step=0.05, unit="m", help="Only the part of a jamb's wall this close to the jamb counts as seeing it")


@dataclass(frozen=True)
class SimParams:
    seed: int = param(0, lo=0, hi=2**31 - 1, step=1, help="Seed of every random draw: one seed, one bit-identical run")
    realtime: bool = param(False, help="Pace advance() to wall-clock time (default: as fast as possible)")
    start_grid: float = param(0.05, lo=0.01, hi=1.0, step=0.01, unit="m", help="Grid spacing when searching a free start place")
    laser: LaserParams = section(LaserParams, "The simulated laser")
    base: BaseParams = section(BaseParams, "The holonomic base and its collision box")
    odometry: OdometryParams = section(OdometryParams, "Odometry: rate, form, offset, uncertainty")
    doors: DoorParams = section(DoorParams, "Sliding doors")
    objects: ObjectParams = section(ObjectParams, "Moving objects from the simulator config")
    truth: TruthParams = section(TruthParams, "Ground truth for scoring")
