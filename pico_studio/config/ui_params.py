"""Parameters of the web UI (`pico-studio serve`) and of the built-in wander that drives the
simulated robot when no other behaviour is chosen."""

from __future__ import annotations

from dataclasses import dataclass

from pico_studio.config.spec import param, section


@dataclass(frozen=True)
class WanderParams:
    speed: float = param(
        0.3, lo=0.0, hi=0.5, step=0.01, unit="m/s",
        help="Forward speed when the way ahead is clear",
    )
    turn_rate: float = param(
        0.8, lo=0.1, hi=1.2, step=0.05, unit="rad/s",
        help="Rotation speed when turning away from an obstacle",
    )
    stop_distance: float = param(
        0.5, lo=0.15, hi=2.0, step=0.01, unit="m",
        help="Closest range ahead at which the robot stops driving and turns in place", at_most="clear_distance",
    )
    clear_distance: float = param(
        0.8, lo=0.2, hi=3.0, step=0.01, unit="m",
        help="Range ahead needed before driving on again after a turn (hysteresis)",
    )
    front_half_angle: float = param(
        0.5, lo=0.1, hi=1.5, step=0.05, unit="rad",
        help="Half-width of the sector in front of the robot that must be clear",
    )
    steer_gain: float = param(
        0.6, lo=0.0, hi=3.0, step=0.05, unit="rad/s",
        help="Rotation per unit of left/right clearance imbalance while driving",
    )


@dataclass(frozen=True)
class UiParams:
    rate_hz: float = param(
        20.0, lo=1.0, hi=50.0, step=1.0, unit="Hz",
        help="Control and redraw rate of the live loop",
    )
    timeline_seconds: float = param(
        120.0, lo=1.0, hi=900.0, step=1.0, unit="s",
        help="How much history the timeline keeps (applies on reset)",
    )
    trail_length: int = param(
        400, lo=0, hi=5000, step=10, unit="frames",
        help="How many past robot positions the trail shows",
    )
    teleop_speed: float = param(
        0.3, lo=0.0, hi=0.5, step=0.01, unit="m/s",
        help="Speed of a teleop button or key press",
    )
    teleop_turn_rate: float = param(
        0.8, lo=0.0, hi=1.2, step=0.05, unit="rad/s",
        help="Rotation speed of a teleop button or key press",
    )
    teleop_hold: float = param(
        0.5, lo=0.05, hi=5.0, step=0.05, unit="s",
        help="How long one teleop press keeps driving before the robot stops by itself",
    )
    score_rate_hz: float = param(
        4.0, lo=0.0, hi=50.0, step=0.5, unit="Hz",
        help="How often live frames are scored against the simulator's truth (costs ~15 ms a frame; 0 = never)",
    )
    camera_fov: float = param(
        0.17, lo=0.02, hi=1.0, step=0.01, unit="rad",
        help="Field of view of the top-down camera (narrow = nearly orthographic)",
    )
    follow_span: float = param(
        8.0, lo=1.0, hi=100.0, step=0.5, unit="m",
        help="Width of the view around the robot when following it",
    )
    wander: WanderParams = section(
        WanderParams, "The built-in wall-avoiding wander (drives the robot until a behaviour is chosen)"
    )
