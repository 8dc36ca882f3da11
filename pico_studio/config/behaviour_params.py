"""Parameters of the reference behaviours: every speed, distance, angle and timeout they use."""

from __future__ import annotations

from dataclasses import dataclass

from pico_studio.config.plugin_params import BEHAVIOUR_PLUGINS, PluginSections, plugin_area
from pico_studio.config.spec import param, section


@dataclass(frozen=True)
class CommonParams:
    rate: float = param(20.0, lo=1.0, hi=100.0, step=1.0, unit="Hz",
                        help="Control rate the behaviours are stepped at")
    stale_timeout: float = param(0.5, lo=0.05, hi=5.0, step=0.05, unit="s",
                                 help="Stop the base when no new laser/odometry arrived for this long")
    footprint_length: float = param(0.36, lo=0.05, hi=2.0, step=0.01, unit="m",
                                    help="Robot box length (along x) that clearances are measured from")
    footprint_width: float = param(0.16, lo=0.05, hi=2.0, step=0.01, unit="m",
                                   help="Robot box width (along y) that clearances are measured from")
    time_limit: float = param(600.0, lo=1.0, hi=3600.0, step=1.0, unit="s",
                              help="Give up (stop, final state 'gave up') after this long")


@dataclass(frozen=True)
class BubbleParams:
    radius: float = param(0.08, lo=0.01, hi=1.5, step=0.01, unit="m",
                          help="Anything closer than this to the robot's box triggers bubbleRobot")
    backoff_extra: float = param(0.15, lo=0.0, hi=1.0, step=0.01, unit="m",
                                 help="Back away this much further than the bubble before re-evaluating")
    speed: float = param(0.2, lo=0.02, hi=0.5, step=0.01, unit="m/s",
                         help="Speed of the back-away move")
    fov: float = param(2.0, lo=0.1, hi=3.1416, step=0.01, unit="rad",
                       help="Half-width of the laser fan (around straight ahead) the bubble watches")


@dataclass(frozen=True)
class EscapeRoomParams:
    entrance_source: str = param("laser", choices=("laser", "world_model"),
                                 help="Where the entrance comes from: the behaviour's own gap finder on the raw scan, or the perceptor's WorldModel.entrance")
    scan_step: float = param(0.5236, lo=0.1, hi=1.6, step=0.01, unit="rad",
                             help="Rotate this much (30 deg) between scans when no entrance is seen")
    scans_to_confirm: int = param(3, lo=1, hi=20, step=1, unit="scans",
                                  help="Median the entrance over this many scans before driving")
    gap_min: float = param(0.5, lo=0.2, hi=2.0, step=0.01, unit="m",
                           help="Narrowest opening taken for the entrance")
    gap_max: float = param(1.3, lo=0.3, hi=4.0, step=0.01, unit="m",
                           help="Widest opening taken for the entrance")
    max_range: float = param(9.5, lo=1.0, hi=60.0, step=0.1, unit="m",
                             help="Laser ranges beyond this are treated as no return (open space)")
    recheck_every: int = param(10, lo=1, hi=200, step=1, unit="steps",
                               help="Re-check the entrance every this many control steps while driving")
    recheck_radius: float = param(0.35, lo=0.05, hi=2.0, step=0.01, unit="m",
                                  help="A re-check confirms the entrance when it is seen within this of the estimate")
    lost_after: int = param(3, lo=1, hi=50, step=1, unit="checks",
                            help="Rescan the room after this many failed re-checks in a row")
    face_tolerance: float = param(0.12, lo=0.01, hi=1.0, step=0.01, unit="rad",
                                  help="Drive only when facing the entrance within this angle")
    drive_speed: float = param(0.4, lo=0.05, hi=0.5, step=0.01, unit="m/s",
                               help="Forward speed towards the entrance and through the hallway")
    turn_speed: float = param(0.9, lo=0.1, hi=1.2, step=0.05, unit="rad/s",
                              help="Rotation speed while scanning and facing")
    heading_gain: float = param(1.5, lo=0.0, hi=10.0, step=0.1, unit="1/s",
                                help="Steering gain on the heading error while driving")
    approach_offset: float = param(0.5, lo=0.0, hi=2.0, step=0.05, unit="m",
                                   help="Aim this far in front of the entrance's mouth, then turn into it")
    hallway_side: float = param(0.8, lo=0.3, hi=3.0, step=0.05, unit="m",
                                help="A side range below this means walls are beside the robot (in the hallway)")
    centre_gain: float = param(1.0, lo=0.0, hi=5.0, step=0.1, unit="1/s",
                               help="Sideways gain centring the robot between the hallway walls")
    free_range: float = param(2.0, lo=0.5, hi=10.0, step=0.1, unit="m",
                              help="Out when no laser point is closer than this")
    out_distance: float = param(1.0, lo=0.0, hi=5.0, step=0.1, unit="m",
                                help="Drive this far on once out, then stop")
    free_space_distance: float = param(1.0, lo=0.2, hi=5.0, step=0.1, unit="m",
                                       help="After a full turn without entrance, move this far into free space")
    max_full_turns: int = param(4, lo=1, hi=50, step=1, unit="turns",
                                help="Give up after this many full scans without an entrance")


@dataclass(frozen=True)
class RoomFinderParams:
    fast_speed: float = param(0.4, lo=0.05, hi=0.5, step=0.01, unit="m/s",
                              help="Driving speed along a wall")
    slow_speed: float = param(0.12, lo=0.02, hi=0.5, step=0.01, unit="m/s",
                              help="Driving speed in the last slow_distance before a wall")
    slow_distance: float = param(0.6, lo=0.1, hi=2.0, step=0.05, unit="m",
                                 help="Slow down this far before the stop distance")
    stop_distance: float = param(0.4, lo=0.2, hi=1.5, step=0.01, unit="m",
                                 help="Stop this far from the wall ahead")
    wall_distance: float = param(0.4, lo=0.2, hi=1.5, step=0.01, unit="m",
                                 help="Keep the right-hand wall at this distance")
    side_beam_angle: float = param(0.35, lo=0.05, hi=1.0, step=0.01, unit="rad",
                                   help="The two right beams are at -90 deg +- this angle")
    max_wall_angle: float = param(0.3, lo=0.05, hi=1.0, step=0.01, unit="rad",
                                  help="Two right beams whose wall is at a larger angle than this see no one wall")
    align_gain: float = param(1.5, lo=0.0, hi=10.0, step=0.1, unit="1/s",
                              help="Turn gain keeping the robot parallel to the right wall")
    distance_gain: float = param(1.0, lo=0.0, hi=10.0, step=0.1, unit="1/s",
                                 help="Sideways gain holding wall_distance")
    fast_turn: float = param(1.0, lo=0.1, hi=1.2, step=0.05, unit="rad/s",
                             help="Turning speed until the last slow_turn_angle")
    slow_turn: float = param(0.25, lo=0.02, hi=1.2, step=0.01, unit="rad/s",
                             help="Turning speed for the last slow_turn_angle")
    slow_turn_angle: float = param(0.0873, lo=0.0, hi=0.5, step=0.005, unit="rad",
                                   help="Turn the last this much (5 deg) slowly")
    turn_tolerance: float = param(0.01, lo=0.001, hi=0.2, step=0.001, unit="rad",
                                  help="A turn is done within this angle")
    room_jump_min: float = param(0.75, lo=0.1, hi=3.0, step=0.05, unit="m",
                                 help="A right-hand range jump at least this big is a side room")
    room_jump_max: float = param(2.0, lo=0.5, hi=5.0, step=0.05, unit="m",
                                 help="A right-hand range jump at most this big is a side room")
    room_width: float = param(1.0, lo=0.3, hi=3.0, step=0.05, unit="m",
                              help="Width of a side room's opening (one short panel)")
    edge_jump: float = param(0.1, lo=0.02, hi=1.0, step=0.01, unit="m",
                             help="A range jump between neighbouring beams this big is an object edge")
    edge_suppress: int = param(5, lo=0, hi=50, step=1, unit="beams",
                               help="Ignore further edges within this many beams of one found")
    content_fov: float = param(0.5, lo=0.1, hi=1.5, step=0.01, unit="rad",
                               help="Half-width of the fan looking into a room to count objects")
    scan_fov: float = param(1.5708, lo=0.5, hi=2.0, step=0.01, unit="rad",
                            help="Half-width of the initial scan for the nearest wall (90 deg: a 180 deg scan)")
    rescan_margin: float = param(0.2, lo=0.0, hi=1.0, step=0.01, unit="rad",
                                 help="Nearest point this close to the scan's edge: turn there and scan again")
    corners: int = param(4, lo=1, hi=16, step=1, unit="corners",
                         help="Stop after turning this many corners past the start corner (4: every wall once)")


@dataclass(frozen=True)
class HospitalParams:
    cell: float = param(0.05, lo=0.01, hi=0.5, step=0.01, unit="m",
                        help="Planner grid cell size")
    inflation: float = param(0.3, lo=0.05, hi=1.0, step=0.01, unit="m",
                             help="Grow obstacles by this much before planning (robot half-size + margin)")
    cost_margin: float = param(0.3, lo=0.0, hi=2.0, step=0.05, unit="m",
                               help="Prefer paths at least this much further than the inflation from walls")
    cost_weight: float = param(4.0, lo=0.0, hi=50.0, step=0.5, unit="",
                               help="Extra cost per cell inside the cost margin (keeps the plan mid-corridor)")
    front_distance: float = param(0.45, lo=0.2, hi=2.0, step=0.01, unit="m",
                                  help="Stop this far in front of a cabinet's front, facing it")
    lookahead: float = param(0.5, lo=0.1, hi=3.0, step=0.05, unit="m",
                             help="Pure-pursuit lookahead along the plan")
    speed: float = param(0.35, lo=0.05, hi=0.5, step=0.01, unit="m/s",
                         help="Cruise speed along the plan")
    turn_speed: float = param(0.9, lo=0.1, hi=1.2, step=0.05, unit="rad/s",
                              help="Maximum rotation speed")
    heading_gain: float = param(2.0, lo=0.0, hi=10.0, step=0.1, unit="1/s",
                                help="Rotation gain on the heading error")
    goal_tolerance: float = param(0.1, lo=0.02, hi=0.5, step=0.01, unit="m",
                                  help="A waypoint or cabinet spot is reached within this distance")
    face_tolerance: float = param(0.08, lo=0.01, hi=0.5, step=0.01, unit="rad",
                                  help="Facing the cabinet within this angle")
    blocked_distance: float = param(0.45, lo=0.1, hi=2.0, step=0.01, unit="m",
                                    help="An unmapped obstacle this close along the plan blocks it")
    path_clearance: float = param(0.22, lo=0.05, hi=1.0, step=0.01, unit="m",
                                  help="An unmapped point closer than this to the plan blocks it")
    blocked_wait: float = param(2.0, lo=0.0, hi=30.0, step=0.5, unit="s",
                                help="Wait this long for a blocker to move before replanning round it")
    obstacle_radius: float = param(0.1, lo=0.0, hi=2.0, step=0.01, unit="m",
                                   help="When replanning, block unmapped laser points by the inflation plus this")
    map_match: float = param(0.15, lo=0.02, hi=1.0, step=0.01, unit="m",
                             help="Laser points within this of a mapped wall/object/door are on the map")
    door_request_distance: float = param(0.9, lo=0.2, hi=2.0, step=0.05, unit="m",
                                         help="Request a door open when the plan meets one this close")
    arrive_pause: float = param(1.0, lo=0.0, hi=10.0, step=0.1, unit="s",
                                help="Stand still this long in front of each cabinet")
    max_replans: int = param(30, lo=1, hi=1000, step=1, unit="replans",
                             help="Give up on a target after this many replans")


@dataclass(frozen=True)
class BehaviourParams:
    common: CommonParams = section(CommonParams, "All behaviours: rate, stale data, time limit")
    bubble: BubbleParams = section(BubbleParams, "bubbleRobot: keep clear of anything too close")
    escape_room: EscapeRoomParams = section(EscapeRoomParams, "Escape room (seed 003)")
    room_finder: RoomFinderParams = section(RoomFinderParams, "Room finder (seed 000)")
    hospital: HospitalParams = section(HospitalParams, "Hospital tour: plan on the global map, visit cabinets")
    plugins: PluginSections = plugin_area(BEHAVIOUR_PLUGINS, "Parameters of the loaded behaviour plugins")
