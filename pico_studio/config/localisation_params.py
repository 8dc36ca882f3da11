"""Parameters of localisation: the robot's pose in the global map and the combined map.

Sections follow the pipeline: the prior (where the robot starts), the distance field of the
global map, the scan matcher, the search used for initialisation and recovery, the tracker's
lost/found hysteresis, and the combined map's matched/unmatched/seen tagging.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pico_studio.config.spec import param, section


@dataclass(frozen=True)
class PriorParams:
    source: str = param(
        "start_area", choices=("start_area", "pose"),
        help="Where the robot starts: the map's start_area polygon, or the pose below",
    )
    x: float = param(0.0, lo=-1000.0, hi=1000.0, step=0.01, unit="m",
                     help="Initial x in the map (when source is 'pose')")
    y: float = param(0.0, lo=-1000.0, hi=1000.0, step=0.01, unit="m",
                     help="Initial y in the map (when source is 'pose')")
    a: float = param(0.0, lo=-math.pi, hi=math.pi, step=0.01, unit="rad",
                     help="Initial heading in the map (when source is 'pose' and heading_known)")
    position_uncertainty: float = param(
        0.5, lo=0.0, hi=5.0, step=0.05, unit="m",
        help="Half-width of the square searched around a given pose (a start area uses its own extent)",
    )
    heading_known: bool = param(False, help="Whether the configured heading (a) is known; a sim config's pose always gives it")
    heading_uncertainty: float = param(
        0.35, lo=0.0, hi=math.pi, step=0.01, unit="rad",
        help="Half-range searched around a known initial heading",
    )


@dataclass(frozen=True)
class FieldParams:
    resolution: float = param(0.02, lo=0.005, hi=0.2, step=0.005, unit="m",
                              help="Cell size of the global map's distance field")
    margin: float = param(2.0, lo=0.0, hi=20.0, step=0.5, unit="m",
                          help="Extra border around the map's bounds covered by the field")
    doors_as_walls: bool = param(True, help="Treat the map's door polygons as walls (closed doors)")
    objects_as_walls: bool = param(True, help="Treat cabinets/tables as walls the laser sees")


@dataclass(frozen=True)
class MatcherParams:
    beam_stride: int = param(3, lo=1, hi=50, step=1, unit="beams",
                             help="Use every k-th laser point for scan matching")
    iterations: int = param(12, lo=1, hi=100, step=1, unit="",
                            help="Gauss-Newton iterations per correction")
    outlier_distance: float = param(0.3, lo=0.02, hi=2.0, step=0.01, unit="m",
                                    help="Points further than this from the map are ignored while matching")
    final_outlier_distance: float = param(0.1, lo=0.01, hi=1.0, step=0.01, unit="m",
                                          help="Outlier distance the matcher shrinks to in its last iterations")
    huber: float = param(0.03, lo=0.001, hi=0.5, step=0.001, unit="m",
                         help="Residual above which a point's weight falls off (Huber loss)")
    inlier_distance: float = param(0.06, lo=0.005, hi=0.5, step=0.005, unit="m",
                                   help="A beam is explained when its point lies this close to the map")
    max_range: float = param(8.0, lo=0.5, hi=60.0, step=0.5, unit="m",
                             help="Points further than this from the robot are not used")
    ray_beams: int = param(120, lo=10, hi=2000, step=10, unit="beams",
                           help="Beams checked for passing through map walls (evenly subsampled)")
    ray_step: float = param(0.05, lo=0.01, hi=0.5, step=0.01, unit="m",
                            help="Sample spacing along a beam when checking it for passing through walls")
    ray_clearance: float = param(0.03, lo=0.0, hi=1.0, step=0.005, unit="m",
                                 help="A beam's last stretch before its end point is not checked (its own wall, within the range noise)")


@dataclass(frozen=True)
class SearchParams:
    position_step: float = param(0.1, lo=0.02, hi=1.0, step=0.01, unit="m",
                                 help="Grid step of the pose search in x and y")
    heading_step: float = param(0.05, lo=0.005, hi=0.5, step=0.005, unit="rad",
                                help="Grid step of the pose search in heading")
    points: int = param(90, lo=10, hi=1000, step=10, unit="",
                        help="Laser points scored per candidate pose (evenly subsampled)")
    truncation: float = param(0.3, lo=0.02, hi=2.0, step=0.01, unit="m",
                              help="Distance above which a point scores as a plain miss")
    candidates: int = param(6, lo=1, hi=50, step=1, unit="",
                            help="Best distinct candidates refined by the matcher")
    separation: float = param(3.0, lo=0.0, hi=10.0, step=0.5, unit="grid steps",
                              help="Candidates closer than this (in position and heading) to a better one are skipped")
    lost_radius: float = param(1.0, lo=0.1, hi=20.0, step=0.1, unit="m",
                               help="Half-width searched around the estimate when first lost")
    lost_growth: float = param(0.5, lo=0.0, hi=10.0, step=0.1, unit="m",
                               help="How much the lost search widens per search without success")
    max_cells: int = param(1000000, lo=1000, hi=100000000, step=1000, unit="poses",
                           help="Most candidate poses per search; a wider search uses coarser steps")
    every_steps: int = param(4, lo=1, hi=100, step=1, unit="steps",
                             help="While lost, search once every this many steps (times the failed searches so far)")
    max_every_steps: int = param(40, lo=1, hi=10000, step=1, unit="steps",
                                 help="Longest wait between two searches while lost (caps the back-off)")


@dataclass(frozen=True)
class TrackerParams:
    quality_lost: float = param(0.45, lo=0.0, hi=1.0, step=0.01, unit="",
                                help="Quality (fraction of beams explained) below which a step is bad",
                                at_most="quality_found")
    quality_found: float = param(0.65, lo=0.0, hi=1.0, step=0.01, unit="",
                                 help="Quality at or above which a step is good (clears lost; a searched pose is believed)",
                                 at_most="quality_confirm")
    quality_confirm: float = param(
        0.85, lo=0.0, hi=1.0, step=0.01, unit="",
        help="Quality a pose found only by a widened search needs (far from the estimate: more alike places)",
    )
    max_through_walls: float = param(
        0.05, lo=0.0, hi=1.0, step=0.01, unit="",
        help="A good step also has at most this fraction of beams passing through map walls",
    )
    min_constraint: float = param(0.03, lo=0.0, hi=0.5, step=0.005, unit="",
                                  help="A good step also needs walls pinning x and y down this well (0 corridor .. 0.5 corner)")
    lost_after: int = param(2, lo=1, hi=100, step=1, unit="steps",
                            help="Consecutive bad steps before the lost flag is raised")
    found_after: int = param(3, lo=1, hi=100, step=1, unit="steps",
                             help="Consecutive good steps before the lost flag is cleared")
    confirm_distance: float = param(
        0.5, lo=0.0, hi=10.0, step=0.05, unit="m",
        help="A pose found only by a widened search must keep explaining the scans while the robot travels this far",
    )
    max_correction: float = param(0.1, lo=0.01, hi=5.0, step=0.01, unit="m",
                                  help="A correction moving the pose further than this in one step is rejected")
    max_correction_angle: float = param(0.1, lo=0.01, hi=math.pi, step=0.01, unit="rad",
                                        help="A correction turning the pose more than this in one step is rejected")


@dataclass(frozen=True)
class CombinedParams:
    match_distance: float = param(0.1, lo=0.01, hi=1.0, step=0.01, unit="m",
                                  help="A local wall's sample is on the map when this close to a map wall")
    match_fraction: float = param(0.7, lo=0.0, hi=1.0, step=0.05, unit="",
                                  help="Fraction of a local wall's samples on the map for it to count as matched")
    sample_spacing: float = param(0.05, lo=0.01, hi=1.0, step=0.01, unit="m",
                                  help="Spacing of the samples taken along a local wall")
    seen_hits: int = param(5, lo=1, hi=1000, step=1, unit="beams",
                           help="Explained beams on a map wall before it counts as seen")
    door_confirm_distance: float = param(
        0.3, lo=0.0, hi=2.0, step=0.05, unit="m",
        help="Once localised, a door (or possible door) whose middle lies this close to the middle of one "
        "of the map's door openings (map.openings), and runs along it, is confirmed by the map",
    )
    door_confirm_angle: float = param(
        0.35, lo=0.0, hi=1.57, step=0.05, unit="rad",
        help="...and differs from the opening's direction by at most this",
    )


@dataclass(frozen=True)
class LocalisationParams:
    enabled: bool = param(True, help="Localise the robot in the global map (needs a global map)")
    prior: PriorParams = section(PriorParams, "Initial pose: start area or a given pose")
    field: FieldParams = section(FieldParams, "Distance field of the global map")
    matcher: MatcherParams = section(MatcherParams, "Scan-to-map alignment (Gauss-Newton)")
    search: SearchParams = section(SearchParams, "Pose search for initialisation and recovery")
    tracker: TrackerParams = section(TrackerParams, "Tracking quality and the lost flag")
    combined: CombinedParams = section(CombinedParams, "Combined map tagging")
