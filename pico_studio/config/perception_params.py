"""Parameters of the perceptor, one section per stage (seeds 000-003, DESIGN.md "The perceptor").

Every threshold the stages use is declared here once, with its default, range, step, unit and
meaning; the stages receive their own section (`perceive(..., cfg.perception)`).
"""

from __future__ import annotations

from dataclasses import dataclass

from pico_studio.config.plugin_params import (
    PERCEPTION_PLUGINS,
    LiveChoices,
    PluginSections,
    plugin_area,
)
from pico_studio.config.spec import param, section

# The built-in segmenters of core/perception/segment.py's registry, by name (config is the
# ground floor and cannot import it; tests/test_perception_segmenters.py checks the two agree).
# Live lists: core's registries add a plugin's name, so YAML and sliders accept it.
SEGMENTER_NAMES = LiveChoices(("split_merge", "angle", "ransac"))
DOOR_DETECTOR_NAMES = LiveChoices(("builtin",))
PERCEPTOR_NAMES = LiveChoices(("builtin",))


@dataclass(frozen=True)
class LocateParams:
    jump_distance: float = param(
        1.0, lo=0.01, hi=100.0, step=0.01, unit="m",
        help="An odometry step longer than this is a jump: warned about and re-anchored",
    )
    jump_angle: float = param(
        1.0, lo=0.01, hi=3.14159, step=0.01, unit="rad",
        help="An odometry step turning more than this is a jump: warned about and re-anchored",
    )
    laser_motion_without_odometry: bool = param(
        True, help="Without odometry, move the pose by the motion estimated from the laser",
    )
    jump_speed: float = param(
        2.0, lo=0.0, hi=50.0, step=0.1, unit="m/s",
        help="The jump distance grows by this per second between odometry readings (slow logs)",
    )
    jump_turn_rate: float = param(
        3.0, lo=0.0, hi=50.0, step=0.1, unit="rad/s",
        help="The jump angle grows by this per second between odometry readings",
    )


@dataclass(frozen=True)
class ProximityParams:
    radius: float = param(
        0.35, lo=0.05, hi=3.0, step=0.01, unit="m",
        help="Radius of the close-proximity circle around the robot",
    )
    footprint_length: float = param(
        0.2, lo=0.0, hi=2.0, step=0.01, unit="m",
        help="Robot footprint along x (centred on the laser): points inside it are the robot itself",
    )
    footprint_width: float = param(
        0.4, lo=0.0, hi=2.0, step=0.01, unit="m",
        help="Robot footprint along y (centred on the laser): points inside it are the robot itself",
    )


@dataclass(frozen=True)
class ScanParams:
    min_range: float = param(
        0.05, lo=0.0, hi=5.0, step=0.01, unit="m",
        help="Ranges below this (or below the laser's range_min) are dropped",
    )
    max_range: float = param(
        10.0, lo=0.5, hi=100.0, step=0.5, unit="m",
        help="Ranges above this (or above the laser's range_max) are dropped",
    )
    min_spacing: float = param(
        0.025, lo=0.0, hi=0.5, step=0.005, unit="m",
        help="Resampling: consecutive kept points are at least this far apart along the scan",
    )
    break_distance: float = param(
        0.12, lo=0.01, hi=2.0, step=0.01, unit="m",
        help="Consecutive points farther apart than this (plus break_slope x range) start a new cluster",
    )
    break_slope: float = param(
        0.02, lo=0.0, hi=1.0, step=0.01, unit="m/m",
        help="Extra allowed gap per metre of range, for the sparser points far away",
    )
    segmenter: str = param(
        "split_merge", choices=SEGMENTER_NAMES,
        help="Line segmenter: split-and-merge (seed 003), angle clustering (seed 001), RANSAC (seed 002)",
    )
    min_points: int = param(
        5, lo=2, hi=200, step=1, help="A wall needs at least this many (resampled) points",
    )
    min_points_per_m: float = param(
        0.0, lo=0.0, hi=20.0, step=0.1, unit="1/m",
        help="...plus this many per metre of the wall's range (its midpoint's distance): far, sparse "
        "pieces need more support (0: the same minimum everywhere)",
    )
    min_length: float = param(
        0.1, lo=0.0, hi=5.0, step=0.01, unit="m", help="Shorter walls are dropped",
    )
    weighted_fit: bool = param(
        False, help="Refit walls by range-weighted least squares (Pfister et al. 2003): far points, "
        "noisier, count less; off: every point counts the same",
    )
    range_sigma0: float = param(
        0.01, lo=0.0001, hi=0.5, step=0.001, unit="m",
        help="Laser range noise at the robot (sigma = range_sigma0 + range_sigma_per_m x range): "
        "the weights of the weighted fit and the walls' line covariance",
    )
    range_sigma_per_m: float = param(
        0.005, lo=0.0, hi=0.2, step=0.001, unit="m/m", help="...growing by this per metre of range",
    )
    max_rms: float = param(
        0.03, lo=0.001, hi=0.5, step=0.001, unit="m",
        help="A wall whose points are further (rms) from its fitted line is dropped",
    )
    merge_angle: float = param(
        0.12, lo=0.0, hi=1.0, step=0.01, unit="rad",
        help="Neighbouring segments of one cluster closer than this in angle are merged",
    )
    seen_margin: float = param(
        0.04, lo=0.0, hi=1.0, step=0.01, unit="m",
        help="A wall's end was seen when a point just past it lies this far behind the wall's line",
    )
    seen_points: int = param(
        4, lo=1, hi=50, step=1, help="How many points past a wall's end are checked for that",
    )
    grazing_factor: float = param(
        0.0, lo=0.0, hi=20.0, step=0.1,
        help="A wall seen at a grazing angle spreads its points: consecutive points break a cluster only "
        "beyond this many times the spacing the surface's incidence angle predicts (0: off)",
    )
    grazing_max_break: float = param(
        0.5, lo=0.0, hi=5.0, step=0.01, unit="m",
        help="...but always beyond this; and a break to a point on the wall's extended line keeps the end "
        "floating only when shorter than this (a door in line is wider)",
    )
    grazing_line_distance: float = param(
        0.03, lo=0.0, hi=1.0, step=0.005, unit="m",
        help="A cluster end whose next point past the break lies this close to the end's extended line "
        "is the same wall going on at a grazing angle: the end stays floating (not seen)",
    )


@dataclass(frozen=True)
class SplitMergeParams:
    split_distance: float = param(
        0.04, lo=0.005, hi=0.5, step=0.005, unit="m",
        help="Split a segment at its farthest point when that is farther than this from the chord",
    )


@dataclass(frozen=True)
class AngleClusterParams:
    lookahead: int = param(
        6, lo=1, hi=30, step=1, help="The direction of point i is taken towards point i + lookahead",
    )
    angle_tolerance: float = param(
        0.35, lo=0.01, hi=1.5, step=0.01, unit="rad",
        help="Start a new wall when the next direction differs this much from the cluster's average",
    )


@dataclass(frozen=True)
class RansacParams:
    iterations: int = param(
        40, lo=1, hi=1000, step=1, help="Line hypotheses (point pairs) drawn per cluster",
    )
    inlier_distance: float = param(
        0.03, lo=0.001, hi=0.5, step=0.001, unit="m", help="Points closer to a line are its inliers",
    )
    max_gap_points: int = param(
        2, lo=0, hi=50, step=1, help="Outliers tolerated inside one wall's run of inliers",
    )
    seed: int = param(0, lo=0, hi=2**31 - 1, step=1, help="Random seed, so a scan always gives the same walls")


@dataclass(frozen=True)
class CornerParams:
    spike_gap: float = param(
        0.3, lo=0.01, hi=5.0, step=0.01, unit="m",
        help="Spike method: consecutive points farther apart than this mark the nearer one a corner",
    )
    spike_max_range: float = param(
        2.0, lo=0.1, hi=20.0, step=0.1, unit="m",
        help="Spike method: only points closer than this (rules out false positives far away)",
    )
    vector_step: float = param(
        0.15, lo=0.02, hi=2.0, step=0.01, unit="m",
        help="Vector method: the angle at a point is taken to the points this far before and after it",
    )
    vector_tolerance: float = param(
        0.35, lo=0.01, hi=1.5, step=0.01, unit="rad",
        help="Vector method: an angle within this of 90 deg (inner) or 270 deg (outer) is a corner",
    )


@dataclass(frozen=True)
class MergeParams:
    angle: float = param(
        0.15, lo=0.0, hi=1.0, step=0.01, unit="rad",
        help="Walls whose directions differ less than this may be merged",
    )
    distance: float = param(
        0.08, lo=0.0, hi=1.0, step=0.01, unit="m",
        help="...and whose end points lie closer than this to the other's line",
    )
    gap: float = param(
        0.15, lo=0.0, hi=2.0, step=0.01, unit="m",
        help="...and whose extents along the line overlap or leave a gap below this",
    )
    connect_radius: float = param(
        0.12, lo=0.0, hi=2.0, step=0.01, unit="m",
        help="End points of two walls closer than this (to the lines' crossing) are connected into a corner",
    )
    connect_min_angle: float = param(
        0.5, lo=0.0, hi=1.57, step=0.01, unit="rad",
        help="Only walls at least this far from parallel are connected into a corner",
    )
    min_length: float = param(
        0.06, lo=0.0, hi=2.0, step=0.01, unit="m",
        help="Local walls shorter than this (e.g. squeezed between two corners) are dropped",
    )
    max_weight: float = param(
        10.0, lo=1.0, hi=1000.0, step=1.0,
        help="Weight of the previous estimate of a wall or corner against one new scan, at most",
    )
    confirm_hits: int = param(
        1, lo=1, hi=100, step=1, help="A wall is shown once it was seen in this many scans",
    )
    unconnected_hits: int = param(
        2, lo=1, hi=1000, step=1,
        help="A wall connected to nothing is only kept once seen in this many scans",
    )
    tentative_life: int = param(
        5, lo=1, hi=1000, step=1,
        help="A wall not yet kept is dropped after this many scans without being seen again",
    )
    miss_limit: int = param(
        6, lo=1, hi=1000, step=1,
        help="A wall is dropped when the laser passed through it in this many scans in a row",
    )
    see_through: float = param(
        0.15, lo=0.01, hi=2.0, step=0.01, unit="m",
        help="The laser passes through a wall when its range exceeds the wall's distance by this",
    )
    trim_step: float = param(
        0.05, lo=0.0, hi=1.0, step=0.01, unit="m",
        help="A wall's end the laser passed through (two points this far apart, then one on the wall) is cut "
        "back to where it met the wall: a smear merged on to a wall's end (0: never)",
    )
    forget_scans: int = param(
        0, lo=0, hi=1000000, step=10,
        help="A wall not seen for this many scans is dropped (0: never): keeps the local map local, so "
        "pose drift over a long run leaves no ghosts",
    )
    forget_seconds: float = param(
        20.0, lo=0.0, hi=3600.0, step=1.0, unit="s",
        help="A wall not seen for this long (scan stamps) is dropped (0: never): as forget_scans, but the "
        "same at any scan rate (a 1 Hz log and a 20 Hz robot drift alike per second, not per scan)",
    )
    keep_radius: float = param(
        12.0, lo=0.5, hi=100.0, step=0.5, unit="m",
        help="Walls entirely farther than this from the robot are dropped",
    )
    max_walls: int = param(
        300, lo=10, hi=100000, step=10, help="At most this many walls; the least seen go first",
    )


@dataclass(frozen=True)
class IdentifyParams:
    door_detector: str = param(
        "builtin", choices=DOOR_DETECTOR_NAMES,
        help="Door detector: the built-in one, or a plugin's (pico_studio.plugins.door_detector)",
    )
    door_min_width: float = param(
        0.5, lo=0.1, hi=5.0, step=0.01, unit="m", help="A door is at least this wide", below="door_max_width",
    )
    door_max_width: float = param(
        1.3, lo=0.1, hi=5.0, step=0.01, unit="m", help="A door is at most this wide", at_most="wide_door_max_width",
    )
    wide_door_max_width: float = param(
        1.5, lo=0.1, hi=5.0, step=0.01, unit="m",
        help="...or this wide between two building walls in one line (end_face_min_length long, or a door "
        "frame's length ending in a whole cap or in a concave corner, or a stub between a whole cap and a "
        "building wall it T-joins), both jambs seen: a wide doorway; or from a building wall's end to a door "
        "frame's wall coming back along its line, or to a building wall's face when seen free beside the end; "
        "beside a table's front none",
    )
    door_angle: float = param(
        0.3, lo=0.0, hi=1.0, step=0.01, unit="rad",
        help="A door continues its wall's direction within this",
    )
    door_offset: float = param(
        0.25, lo=0.0, hi=1.0, step=0.01, unit="m",
        help="...and its far point lies within this of that wall's line (about a wall's thickness)",
    )
    door_wall_min_length: float = param(
        0.5, lo=0.0, hi=5.0, step=0.05, unit="m",
        help="The wall a door continues is this long, or joins one this long at its far end "
        "(a cabinet's side is no door frame)",
    )
    door_offset_short: float = param(
        0.05, lo=0.0, hi=1.0, step=0.01, unit="m",
        help="A door continuing a wall shorter than door_wall_min_length must stay this close to its line",
    )
    facing_distance: float = param(
        1.3, lo=0.1, hi=5.0, step=0.01, unit="m",
        help="A loose end facing a wall: the wall is hit within this along the loose wall's direction",
    )
    jamb_cap_max: float = param(
        0.35, lo=0.0, hi=5.0, step=0.01, unit="m",
        help="A door jamb is a wall's end: the wall joined there (its end cap) is at most this long (a wall's "
        "thickness); a corner with a longer wall is a block's corner (a table against a wall), no jamb",
    )
    door_cap_noise: float = param(
        0.02, lo=0.0, hi=0.2, step=0.005, unit="m",
        help="An end cap's direction is measured over its few cm: a cap standing across a door's line may lean "
        "by door_angle plus atan(this / its length) (about twice the laser's range noise)",
    )
    door_depth: float = param(
        0.8, lo=0.0, hi=10.0, step=0.05, unit="m",
        help="A door is an opening you can see through: a beam (or the local map) through the gap "
        "must reach at least this far past the gap line, else the gap is a bay (e.g. between two tables); "
        "short of the shallowest room (a 1 m side room's back wall must not make its mouth a bay)",
    )
    end_face_depth: float = param(
        0.9, lo=0.0, hi=10.0, step=0.05, unit="m",
        help="...for a T-opening (a wall's end facing a wall's face) this far: the pocket beside a table "
        "standing against a wall (0.8 m deep) is no opening; a room behind a T-opening is deeper",
    )
    end_face_room_wall: float = param(
        2.2, lo=0.0, hi=20.0, step=0.05, unit="m",
        help="...but a T-opening from the end of a wall at least this long whose far end is a concave corner (a "
        "room's wall, longer than a bed's side) stands whatever stands behind it (a cabinet 0.8 m inside the "
        "room): the pocket's side is a piece of furniture's",
    )
    door_backed_share: float = param(
        0.5, lo=0.0, hi=1.0, step=0.05,
        help="A gap is backed (no door) when at least this share of the informative rays through it end "
        "in its shadow (within door_depth behind it, between its jambs)",
    )
    door_min_free_rays: int = param(
        1, lo=0, hi=5, step=1,
        help="A door between two jambs is an opening you were seen to look through: at least this many of the "
        "five rays through the gap end more than door_occlusion beyond its line, or never (a bay seen edge-on, "
        "its rays all ending on a side right by the line, is no door)",
    )
    door_occlusion: float = param(
        0.1, lo=0.0, hi=2.0, step=0.01, unit="m",
        help="A ray stopping this far before the gap was blocked in front of it: it says nothing about the gap",
    )
    line_jamb_run: float = param(
        0.3, lo=0.0, hi=5.0, step=0.05, unit="m",
        help="A building wall's end with no jamb in the local map is a door when the scan shows its line running on "
        "past a door's width (door_min_width..door_max_width) in at least three points spanning this, within "
        "door_offset_short of the line, and a ray seen through the gap: a doorway far along a corridor's wall, the "
        "wall past it seen at a grazing angle too sparsely for a wall (the lone jambs are end_face_doors'; 0: off)",
    )
    end_face_doors: bool = param(
        True, help="A convex wall end facing another wall's face across a door's width is a door (a T-opening)",
    )
    end_face_min_length: float = param(
        1.5, lo=0.0, hi=20.0, step=0.05, unit="m",
        help="...when the wall whose end it is is at least this long: a building's wall, not the side of a "
        "table or a cabinet (a passage between furniture and a wall is no door); such a wall turning at a "
        "convex corner is a door jamb too (a thin wall's corner; a table's front is shorter)",
    )
    end_face_reach: float = param(
        0.5, lo=0.0, hi=5.0, step=0.05, unit="m",
        help="...also onto a building's wall seen in part, or from a building wall's end onto any piece seen "
        "only through the gap (both ends floating): its line, up to this past its floating end (it runs on out "
        "of view), unless the scan looks past that point (0: off; a piece seen through the gap still within "
        "door_occlusion)",
    )
    end_face_evidence_scans: int = param(
        3, lo=0, hi=50, step=1,
        help="...also from a door frame's length seen shorter than end_face_min_length (its far end running on "
        "out of view), facing a building wall's face, once this many scans saw free rays through the gap "
        "(a scan that finds it blocked or backed, or looks past the wall's far end, bans it; 0: off)",
    )
    end_face_continuation: float = param(
        0.3, lo=0.0, hi=5.0, step=0.05, unit="m",
        help="...a scan looks past that wall's far end when its beam reaches beyond the point this far on "
        "along the wall's line: the wall ends there (a table's side)",
    )
    door_run_on: float = param(
        0.5, lo=0.0, hi=5.0, step=0.05, unit="m",
        help="A T-opening seen steeply, its rays landing on the face behind it: a passage when that face is "
        "seen running on at least this far past the gap's line into the view's edge, its end floating (a "
        "pocket's side ends at its back in a corner), the scan's beam there ending on it; it supports a short "
        "wall's T-opening (0: off)",
    )
    end_face_evidence_max: int = param(
        32, lo=1, hi=1000, step=1, help="...remembering at most this many such gaps",
    )
    door_memory_scans: int = param(
        3, lo=0, hi=100, step=1,
        help="A door found in at least this many scans in a row, from places door_memory_spread apart, is "
        "remembered: found no more (seen edge-on, its back or far jamb hidden) it stays a door while its ends "
        "stay on the local map's walls, nothing closes it and neither end is a corridor's mouth's corner "
        "(0: no memory)",
    )
    door_memory_spread: float = param(
        1.0, lo=0.0, hi=20.0, step=0.1, unit="m",
        help="...found from places at least this far apart (from one place, a robot turning on the spot, a "
        "door is one judgement made again and again)",
    )
    door_memory_reach: float = param(
        0.1, lo=0.01, hi=1.0, step=0.01, unit="m",
        help="A remembered door's ends lie this close to the local map's walls; a wall this close to its middle "
        "or a beam ending this close to it closes it",
    )
    bay_doors: bool = param(
        True, help="A gap of a door's shape that the jamb rules refuse (a block's corner or face: a bay between "
        "two tables, or a side room's mouth in thin walls) is a possible door, for the map to prove once localised",
    )
    bay_deep_rays: int = param(
        1, lo=0, hi=5, step=1,
        help="A bay is a door when at least this many of the five rays through it reach door_depth past its "
        "line, or never end: free space behind it (a side room, a hallway), not the pocket between two tables "
        "by a wall; and it opens a building's walls (bay_jamb_span; in a wall's line or across a passage) "
        "(0: a bay is only ever a possible door)",
    )
    bay_run_on: float = param(
        0.35, lo=0.0, hi=5.0, step=0.05, unit="m",
        help="...or, seen steeply, a side of the bay runs on at least this far past its line into the view's edge, "
        "its end floating: longer than a wall's end cap, a side room's side, not a cap (else the side must "
        "run door_depth deep; a T-opening, guarded by less, asks door_run_on; 0: off)",
    )
    bay_jamb_span: float = param(
        2.0, lo=0.0, hi=20.0, step=0.05, unit="m",
        help="...and each of its jambs' connected walls spans at least this (their bounding box's diagonal), or "
        "turns at a room's concave corner: a "
        "building's walls run on, a table with its sides spans no more than its own diagonal (0.7 x 1.6 m: "
        "1.75 m; the passage between a table's corner and a partition's end is seen through too; 0: any)",
    )
    bay_line_offset: float = param(
        0.1, lo=0.0, hi=1.0, step=0.01, unit="m",
        help="...a bay in a wall's line: the wall in line at a jamb passes within this of the other jamb (one "
        "line, a side room's mouth; a bed's side pointing past a wall's cap is parallel but beside it)",
    )
    object_max_size: float = param(
        1.0, lo=0.0, hi=10.0, step=0.05, unit="m",
        help="Connected local walls spanning at most this (bounding-box diagonal), their free ends seen past "
        "and turning at no concave corner (unless they close a loop), are an object (a cabinet, a person), "
        "not a building: no door jamb",
    )
    object_min_depth: float = param(
        0.25, lo=0.0, hi=5.0, step=0.01, unit="m",
        help="...when they span at least this across their main direction too (a piece of a thick wall "
        "with its end cap is long and thin)",
    )


@dataclass(frozen=True)
class EntranceParams:
    parallel_tolerance: float = param(
        0.2, lo=0.0, hi=1.0, step=0.01, unit="rad",
        help="Segments are parallel (or perpendicular) within this",
    )
    min_gap: float = param(
        0.5, lo=0.05, hi=5.0, step=0.01, unit="m",
        help="An end point this far from the next segment's start is an entrance",
    )
    max_gap: float = param(
        2.0, lo=0.1, hi=10.0, step=0.1, unit="m", help="...up to this wide",
    )
    hallway_min_width: float = param(
        0.4, lo=0.1, hi=5.0, step=0.01, unit="m", help="Two parallel segments this far apart are a hallway",
    )
    hallway_max_width: float = param(
        2.0, lo=0.1, hi=10.0, step=0.1, unit="m", help="...up to this far apart",
    )
    median_scans: int = param(
        5, lo=1, hi=100, step=1, help="The entrance is the median over this many scans",
    )


@dataclass(frozen=True)
class RoomParams:
    side_angle: float = param(
        -1.5708, lo=-3.14159, hi=3.14159, step=0.01, unit="rad",
        help="Bearing of the side beam watched for rooms (-pi/2: right-hand)",
    )
    jump_min: float = param(
        0.75, lo=0.0, hi=10.0, step=0.05, unit="m",
        help="A jump of the side range of at least this between scans marks a room",
    )
    jump_max: float = param(
        2.0, lo=0.0, hi=20.0, step=0.05, unit="m", help="...and at most this",
    )
    edge_jump: float = param(
        0.1, lo=0.01, hi=2.0, step=0.01, unit="m",
        help="Inside a room, a range jump above this between beams is an object edge",
    )
    edge_skip: int = param(
        5, lo=0, hi=100, step=1, help="Jumps within this many beams after an edge are the same edge",
    )
    content_half_angle: float = param(
        0.6, lo=0.05, hi=3.14159, step=0.05, unit="rad",
        help="Room content is counted over beams within this of the side bearing",
    )


@dataclass(frozen=True)
class LaserMotionParams:
    match_radius: float = param(
        0.3, lo=0.01, hi=5.0, step=0.01, unit="m",
        help="Corners of two scans closer than this (after the predicted motion) are the same corner",
    )
    iterations: int = param(
        2, lo=1, hi=20, step=1, help="Re-match and re-estimate this many times",
    )


@dataclass(frozen=True)
class ObjectParams:
    enabled: bool = param(True, help="Track small free-standing clusters as objects; keep moving ones out of the map")
    max_size: float = param(
        1.0, lo=0.05, hi=5.0, step=0.05, unit="m",
        help="A cluster whose points span at most this, with both ends seen past, is an object candidate",
    )
    min_points: int = param(3, lo=1, hi=100, step=1, help="...with at least this many points")
    partly_hidden: bool = param(
        True, help="...or seen past at one end only (a box coming out from behind a table), tracked by that end",
    )
    match_radius: float = param(
        0.4, lo=0.01, hi=5.0, step=0.01, unit="m",
        help="A candidate within this of a track's last centroid is that track again",
    )
    min_motion: float = param(
        0.15, lo=0.01, hi=5.0, step=0.01, unit="m",
        help="A track that moved this far from where it was first seen is a dynamic obstacle",
    )
    confirm_scans: int = param(
        8, lo=1, hi=1000, step=1,
        help="An object is merged into the local map only once seen in this many scans without moving",
    )
    settle_scans: int = param(
        40, lo=0, hi=1000, step=1,
        help="A dynamic obstacle seen partly hidden that stays put this many scans is a static object again "
             "(a wall piece whose seen end jumped as more came into view; 0: dynamic for good)",
    )
    forget_scans: int = param(
        20, lo=1, hi=10000, step=1, help="A track not seen for this many scans is forgotten",
    )


@dataclass(frozen=True)
class ScanMatchParams:
    enabled: bool = param(
        True, help="Before merging, correct the pose by matching the scan to the local map (point to line)",
    )
    max_points: int = param(
        200, lo=10, hi=5000, step=10, help="At most this many scan points are matched (evenly spread)",
    )
    iterations: int = param(
        8, lo=1, hi=50, step=1, help="Gauss-Newton iterations (re-associating each time)",
    )
    gate: float = param(
        0.4, lo=0.02, hi=3.0, step=0.01, unit="m",
        help="A point farther than this from every local wall is not matched (shrinks to inlier_distance)",
    )
    inlier_distance: float = param(
        0.05, lo=0.005, hi=1.0, step=0.005, unit="m",
        help="A point this close to a local wall is explained by it (the quality figure)",
    )
    min_matches: int = param(
        30, lo=3, hi=1000, step=1, help="Fewer matched points than this: the pose is not corrected",
    )
    min_quality: float = param(
        0.15, lo=0.0, hi=1.0, step=0.01,
        help="A correction is kept when at least this share of the matched points are inliers after it",
    )
    good_quality: float = param(
        0.8, lo=0.0, hi=1.01, step=0.01,
        help="When the fit from the odometry pose explains less than this share of the scan, the "
        "heading is searched and the fit tried again from there",
    )
    min_gain: float = param(
        0.05, lo=0.0, hi=1.0, step=0.01,
        help="A correction is kept only when it explains this much more of the scan than the "
        "odometry pose did (good odometry is left alone)",
    )
    max_correction: float = param(
        1.0, lo=0.0, hi=10.0, step=0.01, unit="m",
        help="A correction moving the pose farther than this is distrusted (kept as odometry)",
    )
    max_correction_angle: float = param(
        0.7, lo=0.0, hi=3.14159, step=0.01, unit="rad",
        help="A correction turning the pose more than this is distrusted",
    )
    point_sigma: float = param(
        0.03, lo=0.001, hi=1.0, step=0.001, unit="m",
        help="Noise of one scan point against its wall: weighs the points against the odometry",
    )
    odometry_sigma: float = param(
        0.01, lo=0.0001, hi=10.0, step=0.001, unit="m",
        help="Position noise of odometry over one step, plus odometry_sigma_per_m per metre moved",
    )
    odometry_sigma_per_m: float = param(
        0.2, lo=0.0, hi=10.0, step=0.01, unit="m/m", help="Odometry position noise per metre moved",
    )
    odometry_sigma_angle: float = param(
        0.005, lo=0.0001, hi=3.0, step=0.001, unit="rad",
        help="Heading noise of odometry over one step, plus odometry_sigma_per_rad per radian turned",
    )
    odometry_sigma_per_rad: float = param(
        0.2, lo=0.0, hi=10.0, step=0.01, unit="rad/rad", help="Odometry heading noise per radian turned",
    )
    search_angle: float = param(
        0.6, lo=0.0, hi=3.14159, step=0.01, unit="rad",
        help="Before refining, headings within this of the odometry's are tried (the best start wins)",
    )
    search_points: int = param(
        50, lo=3, hi=5000, step=1, help="...judged on at most this many of the matched points (evenly spread)",
    )
    search_step: float = param(
        0.03, lo=0.001, hi=1.0, step=0.001, unit="rad", help="...in steps of this",
    )
    min_wall_hits: int = param(
        1, lo=1, hi=100, step=1, help="Only local walls seen in at least this many scans are matched against",
    )
    odometry_sigma_angle_per_m: float = param(
        0.05, lo=0.0, hi=10.0, step=0.01, unit="rad/m", help="Odometry heading noise per metre moved",
    )
    neighbour_distance: float = param(
        0.3, lo=0.01, hi=5.0, step=0.01, unit="m",
        help="A scan point's direction is taken from its neighbours within this (farther: a break)",
    )
    normal_angle: float = param(
        0.5, lo=0.01, hi=1.5708, step=0.01, unit="rad",
        help="A point is matched only to walls within this of the scan's direction at the point",
    )
    min_information: float = param(
        5.0, lo=0.0, hi=1e6, step=1.0,
        help="A direction (of x, y, heading) the walls know less than this many times better than odometry "
        "(an eigenvalue of the odometry-whitened information) is degenerate, e.g. along a corridor: held to odometry",
    )
    min_conditioning: float = param(
        0.05, lo=0.0, hi=1.0, step=0.005,
        help="The weaker position direction is degenerate (held to odometry) when its information is below "
        "this share of the stronger one's: along a corridor, a door jamb's few points must not slide the pose",
    )
    min_evidence: float = param(
        11.3, lo=0.0, hi=1e6, step=0.1,
        help="A correction is kept only when it lowers the matching objective (walls' robust cost over "
        "point_sigma^2 plus the odometry prior) by at least this: a likelihood-ratio test (11.3: chi-square, "
        "3 dof, 1 %); smaller corrections are matching noise, and applying them random-walks pose and map",
    )
    max_sigmas: float = param(
        20.0, lo=0.0, hi=100.0, step=0.1,
        help="A correction farther than this many odometry noise sigmas (Mahalanobis) is implausible: kept as odometry",
    )


@dataclass(frozen=True)
class PerceptionParams:
    perceptor: str = param(
        "builtin", choices=PERCEPTOR_NAMES,
        help="The whole perceptor: these stages (builtin), or a plugin's (pico_studio.plugins.perceptor)",
    )
    locate: LocateParams = section(LocateParams, "Init / Locate: zero pose and pose from odometry")
    proximity: ProximityParams = section(ProximityParams, "Close proximity circle and footprint")
    scan: ScanParams = section(ScanParams, "Scan: filtering, resampling, clustering, segmenting")
    split_merge: SplitMergeParams = section(SplitMergeParams, "Split-and-merge segmenter (seed 003)")
    angle: AngleClusterParams = section(AngleClusterParams, "Angle-clustering segmenter (seed 001)")
    ransac: RansacParams = section(RansacParams, "RANSAC segmenter (seed 002)")
    corners: CornerParams = section(CornerParams, "Spike and vector corner detectors (seed 002)")
    merge: MergeParams = section(MergeParams, "Merging scans into the local map (seed 001)")
    identify: IdentifyParams = section(IdentifyParams, "Convex/concave corners, doors, possible doors")
    entrance: EntranceParams = section(EntranceParams, "Entrance and hallway detection (seed 003)")
    rooms: RoomParams = section(RoomParams, "Side rooms and their content (seed 000)")
    laser_motion: LaserMotionParams = section(LaserMotionParams, "Motion from matched corners (seed 002)")
    objects: ObjectParams = section(ObjectParams, "Objects and people: small free-standing clusters, tracked")
    scan_match: ScanMatchParams = section(ScanMatchParams, "Pose correction: scan to local map, point to line")
    plugins: PluginSections = plugin_area(PERCEPTION_PLUGINS, "Parameters of the loaded perception plugins")
