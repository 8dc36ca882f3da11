"""Identify (seed 001): corner properties, doors and possible doors in the local map.

Corners: two connected wall ends form a corner. Seen from the robot R it is *concave* when R
lies inside the wedge the two walls span at the corner C (u = A - C, v = B - C towards the
walls' far ends; R inside when r = R - C is a positive combination of u and v) — the robot
looks into it — and *convex* when the corner points at the robot. Each wall is judged from
where the robot last saw it (its free side): a corner of a room the robot has left stays
concave behind the wall it passed. A wall end on the inside of another wall (a T) is concave,
unless that end's wall was seen through the other's line (a slot between two cabinets' fused
fronts): then convex.
A free end the laser looked past (a jamb, a wall's end) is convex.

Doors: two convex points P, Q of different walls, the gap within [door_min_width,
door_max_width] (up to `wide_door_max_width` between two building walls in one line, each
at least `end_face_min_length` long, or a door frame's length ending in a whole cap or
turning at its far end into a wall in a concave corner, or a shorter stub between a whole cap
and a building wall it T-joins (a wall's end between a doorway and a junction): a wide
doorway; a table's front is shorter, its side no cap; or from a building wall's end — joined to
nothing or to a whole cap, no corner of walls — to a door frame's wall coming back along its
line, no block's face: a doorway's short end beside a junction seen in part) and no wall across it; the gap continues P's wall (Q ahead of P's end, within
`door_angle` of its direction and `door_offset` of its line), and Q's wall comes back along
that line towards P (the two walls in one line, seed 001; one or both may be seen in part,
shorter than a door frame's with its far end floating: a doorway seen through a nearer one,
`identify_kernels.door_pairs`) or stands across it (the end cap
of a thick wall seen from the side while the face beyond the gap is out of view). Possible doors (seed 001), with the same width range: a convex point and a loose
(floating) end, two loose ends, or a loose end whose wall, continued, hits another wall
within `facing_distance`.

Jambs among furniture (restaurant_2024's false doors, `tests/test_clutter_jambs.py`): a
jamb is a wall's end joined to nothing or to a *whole* end cap (no longer than
`jamb_cap_max`, its far end seen or joined: a side seen in part may run a table deep; and not
a step — the wall at its far end running the other way: a box standing against a wall), or a
building's wall (at least `end_face_min_length`) turning at a convex corner away from the
robot (a thin-walled room's mouth; a table's front is shorter; turning towards the robot the
corner hides the wall's own end, convex only as seen from behind) into a wall that is no
block's face (both its ends convex, no longer than `object_max_size`: a bed's foot, its 2 m
side as long as a building's wall); a
wall standing across a door's line is a jamb only as a cap (seen whole, or in part across a
long wall's line that is no block's face: a table's front seen whole, both ends free, shorter
than a building's wall) or a door frame's wall (at least `door_wall_min_length`, or a stub on
one, or seen in part with a whole cap at its end lying along the line, thinner than any object
(`object_min_depth`): a thick partition's end between two doorways, its face seen through one
only a few dm up): a box's or a person's lone face is not, nor any wall across a block face's line, nor a block's
face across a stub's line (a bed's foot a metre behind a thick wall's doorway, across its cap's line). A T-opening (a convex end facing a wall's face, "end_face") starts from a building's
wall — one at least `end_face_min_length` long (but not a block's front against a wall: its far
end turning at a convex corner into a side longer than `jamb_cap_max`, at most
`object_max_size`, that meets a wall in a concave corner, a table 1.4-1.6 m long, or into a side
seen in part, its other end floating; that is only ever a possible door "end_face", for the map
to prove), or a door frame's length ending in a whole
cap (a thick wall's end; a table's end is as wide as the table), or a door frame's length
whose far end turns into another wall in a concave corner (a room's wall) facing a building
wall's face (at least `end_face_min_length` long) — and never ends on a
block's face (both its ends convex and shorter than `end_face_min_length`: a table's or a
cabinet's front; or, longer than an end cap, turning in a convex corner into a short wall that
runs back to a wall in a concave corner: a table standing against a wall, `face_kernels.against_a_wall`),
nor meets a face within `jamb_cap_max` of its free end (a corner, not a face: a table's end),
unless that wall is a building's lying on the robot's side, only its end past the gap's line
(the room's side wall turning just past a doorway in the room's corner). From a corner whose
other wall (longer than `jamb_cap_max`) runs on beyond the gap's line, facing a face that runs
on into the robot's side, it is a corridor's mouth beside a room's wall running straight on,
no wall's end: only ever a possible door "end_face", for the map to prove
(`face_kernels._corridor_mouth`; a face ending at the line makes a passage's mouth, a door). The face may be a building's wall seen in part, its floating end within
`end_face_reach` short of the gap's line, when the scan does not look past the meeting point;
from a building wall's end, any piece floating at both ends (a face seen only through the gap,
the jamb hiding one side, the view's edge the other) met up to `end_face_reach` past its
floating end, unless the scan looks past that point (at least `door_occlusion`).
A T-opening wider than `door_max_width`, up to `wide_door_max_width`, is a door only from a
building wall's end (no glimpse, no short wall's) facing a building wall's face, seen through
`end_face_depth` deep and seen free beside its end: the scan's beams reach past the points half
and one gap's width from the end, away from the robot (`face_kernels._side_seen`; a corner of
walls there, its other wall edge-on and out of the local map, stops them — a passage beside a
room's corner, which the truth counts as no opening —, and seen from behind the wall's own line
they are hidden). Seen free so in `end_face_evidence_scans` scans (counted with the T-openings'
evidence) it is remembered: seen again from beside its wall, the side hidden, not closed, it is
still a door (suite:0's 1.33 m doorway beside a thick wall's end, a door only while the
robot stood past the end's line); a beam ending on the side (a corner's other wall) bans the
place. Else it is only ever a possible door "end_face", for the map to prove. So
is a T-opening from a wall whose far end is no concave corner, its face turning in a concave
corner into another wall less than `end_face_depth` past the gap's line, no ray through the gap
reaching that deep (`face_kernels._shallow_back`), no thing standing in the gap's shadow apart
from the jambs' walls, its end seen past (a cabinet beyond a doorway, its corner fused with the
wall's: `identify_kernels.standing_in_shadow`): seen steeply, the pocket beside a table
standing against a wall shows its back only there (a table 1.5-1.6 m long has a building wall's
length; a room's wall ending in the room's corner keeps its door beside a cabinet standing against
the doorway's side wall 0.44 m on). A T-opening whose gap the scan's beams find hidden (two of three, at a quarter, half and three
quarters of it, ending more than `door_occlusion` before it: a box standing in front) is none:
the local map's walls alone say nothing of what stands there now. A door between two jambs is a gap some ray was seen to pass
through (`door_min_free_rays`): a bay seen edge-on is none.

Bays (`bay_doors`): a gap of a door's shape between two convex corners that the jamb rules
refuse (a block's corner or face, its cap longer than a wall's thickness: a bay between two
tables by a wall; or backed, or never seen through), and a passage's mouth (two door frame's
walls side by side, the gap across both ends: a hallway's far end; or, one side seen down its
length at a few degrees and its end floating short, from the other side's seen free end across
to its line: `map_proven_kernels.hidden_mouths`), are possible doors of kind "bay". In thin
walls a side room's mouth between two 1 m wall pieces has exactly a table bay's shape: only the global map can tell them apart, and once localised the combined map makes a
bay a door where its walls have an opening there. A bay seen through to free space
(`bay_deep_rays` rays reaching `door_depth` past its line, the scan's: out of the laser's view
a wall the local map remembers deep behind it proves nothing; or, its back unseen, most rays
ending behind it on a side, a side of it running on `door_depth` past its line, its far end
no seen corner: a hallway seen at a slant — or `bay_run_on`, longer than a wall's end cap, its
far end floating into the view's edge: a side room seen steeply, a pocket's side ending at its
back in a corner; a ray ending on a small object says nothing, a box standing in a side room
being no pocket's back — nor any small group seen whole, however thin: a box seen as an L, a
person's two feet; nor a wall with a seen end standing in the gap's shadow, joined to neither
jamb's walls: a box seen in part)
is a door of kind "bay" when it opens a building's walls: both jambs' connected walls span at least `bay_jamb_span` (a table with its
sides spans no more than its diagonal), or turn at a concave corner where two walls longer
than `jamb_cap_max` meet end to end (`identify_kernels.inside_corners`): the robot sees a room's
inside, while a table seen from outside turns at convex corners only, and one standing a few
cm off a wall is T-joined to the wall's face, joined one way (a table against a wall, the wall
seen up to the table's side, is such a corner too: the rule's price; but no wall of a block
standing against a wall seen closed, `map_proven_kernels.block_sides`: its side, its front longer
than an end cap and its other side running back to the wall, the robot outside them — the
table's corner beside a partition's end in line with its side has every other shape of a wall's
opening) (a piece of wall between
two doors whose sides are unseen counts as the building's when its line runs on past both its ends in other walls a door's width
on, one of them a building's; or past one end, the other out of view (floating, or its line a door's width on outside the field of view: the piece of a room's wall between two cubicles' mouths), into a wall that is a
building's by its own shape: `end_face_min_length` long, or turning at a concave corner into a
wall longer than an object (`object_max_size`), a room's corner, not a table's side turning into
its back; or into a piece in
line past both its ends that is the building's), and the gap lies
in a wall's line (a wall a door frame's length in line at both jambs, each passing within
`bay_line_offset` of the other jamb: a side room's mouth) or across a passage (walls across it at both jambs, on the same side, none along it: a
hallway's far end). The passage between a table's corner and a partition's end is seen through
too, but fails one or the other (the table's walls span the table, and a table's face in line
with a wall has a seen corner at its other end; joined to a wall, it has a wall in line on one
side only).

Evidence over scans (`Identified.evidence`, handed back in by the perceptor): a T-opening
from a door frame's length seen shorter than `end_face_min_length` (or a whole end cap's side
seen shorter than a door frame's), its far end floating,
facing a building wall's face, is from one scan a partition hidden in part or a table's side
seen in part. A scan supports it when a ray through the gap reaches free space, `end_face_depth`
past its line or never ending (rays grazing past onto the face a few cm on show a pocket by a
wall as well as an opening) — or, seen steeply, when rays pass the gap and its face is seen
running on `door_run_on` past the line into the view's edge, no corner there (a pocket's
side ends at its back; from a viewpoint that hides the back a pocket beside a table passes
too: the trade `door_run_on` sets), seen so by this scan: its beam towards the face
`door_run_on` past the line ends on the face (the local map remembering the face run on is no
evidence: seen along the gap's line from afar the jamb's own wall hides that part, and with it
any back) —, and the beam in line with the wall, `end_face_continuation` past
its far end, does not look past that point (something in front hides the wall, the field of
view cuts it, or it is the wall itself: it may run on); it becomes a door after
`end_face_evidence_scans` such scans, and until then is a possible door of kind "end_face"
(once localised, the combined map promotes it where the map has an opening). A scan that
finds the gap blocked or backed, or looks past that point (the wall ends there: a table's
side), bans the place. A shorter wall's seen end so (no cap: a glimpse of a thick wall's side, or a
person's or a chair's side) is only ever a possible door "end_face", for the map to prove; so
is a lone end cap (`jamb_cap_max` long, joined to nothing: a partition's end seen face on)
whose normal towards the robot's side meets a building wall's face a door's width on.
A building wall's T-opening, a door from one scan, is remembered in the same records: seen
closed (backed, its rays ending on a back between the jambs within `end_face_depth`: a pocket
beside a table standing against a wall, seen from in front; a ray ending on a thing standing in
the room beyond says nothing of a back — an object's wall, or a wall with a seen end in the
gap's shadow, joined to neither jamb's walls, a cabinet half a metre in:
`identify_kernels.backed_beside_things`; but the end of a room's wall — at least
`end_face_room_wall` long, longer than a bed's side, its far end a concave corner — is never a
pocket's side: a cabinet 0.8 m inside the room behind its doorway backs no door) the place is
closed, and seen again
with nothing said by its rays (edge-on, the back forgotten) it is only a possible door, until
rays pass it deep; the same place is a middle within `door_occlusion` / 2. The bays keep
records of their own beside them (kind 1; the T-openings' are kind 0): a bay refused at a block
seen closed is banned for good, so when the local map has forgotten the block's far side (unseen
for `merge.forget_seconds`) and the open table reads as a room's wall turning into a passage,
the place stays a possible door. A T-opening's place seen closed (a pocket's back) says nothing
of a side room's mouth: the kinds never match each other's records.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pico_studio.config.perception_params import IdentifyParams
from pico_studio.core.perception.door_kernels import away_from, jamb_doors, loose_gaps
from pico_studio.core.perception.face_kernels import t_openings, tally
from pico_studio.core.perception.identify_kernels import (
    backed_beside_things,
    group_spans,
    in_line_spans,
    inside_corners,
    object_groups,
    small_objects,
)
from pico_studio.core.perception.junction_kernels import junctions
from pico_studio.core.perception.line_jambs import line_jamb_doors
from pico_studio.core.perception.map_proven import bays, lone_caps
from pico_studio.core.perception.map_proven_kernels import block_sides, deep_sides, wall_shaped
from pico_studio.core.world_model import CONCAVE, CONNECTED, CONVEX, FLOATING

POSSIBLE_DOOR_KINDS = ("convex_loose", "loose_loose", "loose_wall", "end_face", "bay", "jamb")
DOOR_KINDS = ("jambs", "end_face", "bay")
# the possible doors that a door's shape makes and only the global map can prove: once
# localised, the combined map makes them doors where it has an opening (combined.combine)
MAP_PROVEN_KINDS = ("end_face", "bay")
# a jamb whose other side is out of view (a building wall's end with nothing ahead; unless the
# scan shows its line running on in points past a door's width, a doorway seen at a grazing
# angle: then a door, line_jambs): once localised, the map's opening at that end is the door
# (combined.combine)
JAMB_KIND = "jamb"


@dataclass(frozen=True)
class Identified:
    endpoint_property: np.ndarray  # (W, 2) int
    corners: np.ndarray  # (C, 2)
    corner_convex: np.ndarray  # (C,)
    doors: np.ndarray  # (D, 4)
    possible_doors: np.ndarray  # (E, 4)
    possible_door_kind: list[str]
    door_kind: list[str]  # (D,) one of DOOR_KINDS
    object_wall: np.ndarray  # (W,) bool: the wall belongs to a small object (no building)
    evidence: np.ndarray = field(default_factory=lambda: np.zeros((0, 6)))  # (E, 6) T-openings' and bays' records: middle, unit gap direction, scans for (`face_kernels.tally`), kind (0 T-opening, 1 bay)


@dataclass(frozen=True)
class View:
    """What the laser sees now: beams (robot frame) and the robot's pose in the zero frame."""

    ranges: np.ndarray
    angles: np.ndarray
    valid: np.ndarray
    pose: tuple[float, float, float]
    # (n,) bool, the beams ending on an object being tracked (a walking person, a box that has
    # not settled): no wall's points (line_jambs); None: none known
    tracked: np.ndarray | None = None


def identify(
    walls: np.ndarray, connected: np.ndarray, seen_end: np.ndarray, robot_xy: tuple[float, float],
    params: IdentifyParams, view: View | None = None, evidence: np.ndarray | None = None,
    eyes: np.ndarray | None = None,
) -> Identified:
    """walls (W, 4) zero frame, connected (W, 2) wall index or -1, seen_end (W, 2) bool;
    `view`: the current scan and the robot's pose (zero frame), for looking through gaps;
    `evidence`: the previous scan's `Identified.evidence` (T-openings on a short wall, counted
    over scans); `eyes` (W, 2): where each wall was last seen from (`LocalMapState.viewpoint`; None:
    all from `robot_xy`, now), for judging its corners."""
    # each end floating or convex (seen), each junction a convex or concave corner as seen from
    # where its walls were last seen (the loop and its maths: junction_kernels.junctions)
    rx, ry = float(robot_xy[0]), float(robot_xy[1])
    n = len(walls)
    eyes = np.tile([rx, ry], (n, 1)) if eyes is None else eyes
    prop, corners, convex = junctions(np.ascontiguousarray(walls, dtype=float), np.ascontiguousarray(connected, dtype=np.int64),
                                      np.ascontiguousarray(seen_end, dtype=bool), np.ascontiguousarray(eyes, dtype=float),
                                      FLOATING, CONVEX, CONCAVE)
    objects = object_walls(walls, connected, prop, params.object_max_size, params.object_min_depth)
    ev = np.zeros((0, 6)) if evidence is None else evidence
    doors, door_kinds, possible, kinds, ev = _doors(walls, prop, connected, objects, (rx, ry), view, params, ev)
    return Identified(
        prop,
        corners,
        convex,
        doors,
        possible,
        kinds,
        door_kinds,
        objects,
        ev,
    )


def _split_records(evidence: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The T-openings' and the bays' records (each (E, 5), `face_kernels.tally`'s) from
    `Identified.evidence` (E, 6), the last column the kind; an (E, 5) array is all T-openings'."""
    ev = np.asarray(evidence, dtype=float)
    if ev.ndim != 2 or ev.shape[1] == 5 or len(ev) == 0:
        return np.ascontiguousarray(ev).reshape(-1, 5), _NO_RECORDS
    bay = ev[:, 5] == 1
    if not bay.any():
        return np.ascontiguousarray(ev[:, :5]), _NO_RECORDS
    return np.ascontiguousarray(ev[~bay, :5]), np.ascontiguousarray(ev[bay, :5])


def _records(t_ev: np.ndarray, bay_ev: np.ndarray) -> np.ndarray:
    """`Identified.evidence` (E, 6) from the T-openings' and the bays' records."""
    out = np.empty((len(t_ev) + len(bay_ev), 6))
    out[:len(t_ev), :5], out[:len(t_ev), 5] = t_ev, 0.0
    out[len(t_ev):, :5], out[len(t_ev):, 5] = bay_ev, 1.0
    return out


_NO_RECORDS = np.zeros((0, 5))


def object_walls(walls: np.ndarray, connected: np.ndarray, prop: np.ndarray, max_size: float,
                 min_depth: float) -> np.ndarray:
    """(W,) bool: walls of a connected group whose bounding box spans at most `max_size`
    (diagonal), at least `min_depth` across its main direction, and none of whose ends is
    floating (the laser saw past all its free ends): a table, a cabinet, a person seen as a
    few short connected walls. A piece of a building's wall seen in part has a floating end
    where the view stopped; a thick wall's end with its cap is thin; an open group turning at
    a concave corner is seen into a corner, no free-standing thing (a box a few cm off a wall
    beside a doorway, its side fused with the wall across the gap, leaves the jamb's piece of
    wall a jamb), while a closed loop is one however its far corners look through it."""
    n = len(walls)
    if n == 0 or max_size <= 0:
        return np.zeros(n, dtype=bool)
    # the groups of connected walls that are small with no floating end, no corner seen into
    # unless closed, and deep enough (the loops and the principal axis:
    # identify_kernels.object_groups, small_objects)
    return small_objects(np.ascontiguousarray(walls, dtype=float), np.ascontiguousarray(connected, dtype=np.int64),
                         np.ascontiguousarray(prop, dtype=np.int64), float(max_size), float(min_depth), FLOATING, CONCAVE)


def _doors(
    walls: np.ndarray, prop: np.ndarray, connected: np.ndarray, objects: np.ndarray, robot: tuple[float, float],
    view: View | None, params: IdentifyParams, evidence: np.ndarray,
) -> tuple[np.ndarray, list[str], np.ndarray, list[str], np.ndarray]:
    empty = np.zeros((0, 4))
    t_ev, bay_ev = _split_records(evidence)  # the T-openings' records, the bays' (`Identified.evidence`)
    if len(walls) < 2:
        return empty, [], empty, [], _records(t_ev, bay_ev)
    scan = _view_arrays(view)  # the current scan as the kernels take it
    # door-point candidates: (wall, end) with a convex or floating property, not on an object.
    # A jamb is a wall's end: joined to nothing there, or to an end cap no longer than a wall's
    # thickness (`jamb_cap_max`; a longer wall there makes a block's corner, a table against a
    # wall, unless the wall is a building's, `end_face_min_length`: a thin wall's corner) that is whole (its far end seen or joined: a side seen in part may run deep, a
    # table's between two tables standing in a row by a wall; a building wall's end joined to
    # such a piece is a jamb only opposite another building wall in its line, no T-opening's:
    # a doorway's frame corner seen at a slant comes out in fragments, a bed's side has no such
    # partner). The wall a door continues is
    # long (`door_wall_min_length`), or a short stub whose far end joins a long wall (a
    # cabinet's side is short and joins another short side; then the gap must continue it
    # closely: `door_offset_short`). The loop: identify_kernels.jamb_candidates.
    # the pairs (ia, ja), ia < ja, a door's width apart that may be a door or a possible door:
    # the gap continues one wall's line (the other point ahead of its end, within door_angle
    # and door_offset), and the other point's wall either comes back along that line or
    # stands across it (the end cap of a thick wall seen from the side, when the face beyond
    # the gap is out of view); the tests and their maths: identify_kernels.door_pairs
    # a door is an opening some ray was seen to pass (a possible door is the unknown case), best
    # aligned first, one per opening; the pipeline and its maths: door_kernels.jamb_doors
    wi, we, capped, long, partial, pts, out_dir, other, is_convex, lengths, jamb_gaps, maybe, maybe_convex = jamb_doors(
        np.ascontiguousarray(walls, dtype=float), np.ascontiguousarray(connected, dtype=np.int64),
        np.ascontiguousarray(prop, dtype=np.int64), np.ascontiguousarray(objects, dtype=bool), float(robot[0]),
        float(robot[1]), *scan, float(params.jamb_cap_max), float(params.door_wall_min_length),
        float(params.end_face_min_length), float(params.object_max_size), float(params.object_min_depth),
        float(params.door_min_width), float(params.door_max_width), float(params.wide_door_max_width), float(params.door_angle),
        float(params.door_offset), float(params.door_offset_short), int(params.door_min_free_rays), float(params.door_occlusion),
        float(params.door_depth), float(params.door_backed_share), float(params.door_cap_noise), FLOATING, CONVEX,
        CONCAVE)
    if len(wi) < 1:
        return empty, [], empty, [], _records(t_ev, bay_ev)
    doors: list[list[float]] = jamb_gaps.tolist()
    door_kinds: list[str] = ["jambs"] * len(doors)
    possible: list[np.ndarray] = list(maybe)
    kinds: list[str] = ["convex_loose" if c else "loose_loose" for c in maybe_convex.tolist()]
    # a wall's end facing another wall: the wall's continuation hits another wall's face. From
    # a convex end (the laser saw the end) within a door's width that is a door, a T-opening;
    # from a loose end a possible door
    if params.end_face_doors:
        # the convex ends that count: a building wall's end (a long wall, or a door frame's length ending in a whole
        # end cap of a wall's thickness (a thick wall's end seen with its cap; a table's end is
        # as wide as the table, a person's side too short); or a door frame's length whose far end turns into another wall in a concave corner (a
        # room's wall), when the face it meets is a building wall's (end_face_min_length long)
        # or a door frame's length seen short, its far end floating (it runs on out of view; a
        # table's side ends in a seen corner or a seen end), facing a building wall's face: from
        # one scan as likely a table's side, so a door only after `end_face_evidence_scans` scans
        # saw free rays through the gap; so too a whole end cap's side seen shorter than a door
        # frame's (the rest hidden: a thick wall's end; a person's or a chair's side has no cap)
        # or any shorter piece seen so (a thick wall's side glimpsed, its cap edge-on; or a
        # person's, a chair's side): never a door from the local map, a possible door for the
        # map to prove
        # then the ray from each such convex end to the face it meets, the gap's tests, the weak
        # ends' evidence over scans (end_face_evidence_scans) and the doors not found already
        # (the loops and their maths: face_kernels.t_openings, face_gaps, tally)
        found, maybe_t, t_ev, lone = t_openings(
            pts, out_dir, other, wi, we, is_convex & ~partial, long, capped, np.ascontiguousarray(walls, dtype=float),
            np.ascontiguousarray(connected, dtype=np.int64), np.ascontiguousarray(prop, dtype=np.int64),
            np.ascontiguousarray(objects, dtype=bool), lengths, np.array(doors, dtype=float).reshape(-1, 4),
            t_ev, float(robot[0]), float(robot[1]),
            *scan, float(params.door_min_width), float(params.door_max_width), float(params.wide_door_max_width),
            float(params.jamb_cap_max), float(params.end_face_min_length), float(params.object_max_size),
            float(params.door_angle), float(params.end_face_reach), float(params.door_occlusion),
            float(params.end_face_continuation), float(params.end_face_depth), float(params.door_backed_share),
            int(params.door_min_free_rays), int(params.end_face_evidence_scans), int(params.end_face_evidence_max),
            float(params.door_run_on), float(params.end_face_room_wall), FLOATING, CONVEX, CONCAVE)
        possible.extend(maybe_t)
        kinds.extend(["end_face"] * len(maybe_t))
        doors.extend(found.tolist())
        door_kinds.extend(["end_face"] * len(found))
        # a lone jamb whose wall the scan shows running on in points past a door's width, the
        # gap seen through: a doorway far along a corridor's wall seen at a grazing angle
        # (line_jambs.line_jamb_doors)
        if view is not None and len(lone):
            wall_beams = view.valid if view.tracked is None else view.valid & ~view.tracked
            in_line, used = line_jamb_doors(lone, walls, view.ranges, view.angles, view.valid, wall_beams, view.pose,
                                            params)
            doors.extend(in_line.tolist())
            door_kinds.extend(["jambs"] * len(in_line))
            lone = lone[~used]
        possible.extend(lone)
        kinds.extend(["jamb"] * len(lone))
    if params.bay_doors:
        # a bay seen through to free space (`bay_deep_rays` of its rays reaching `door_depth`
        # past its line; or, seen at a slant, its rays all ending on a side and none on a back,
        # a side running on that deep, or bay_run_on into the view's edge:
        # map_proven_kernels.deep_sides) is a door where it opens
        # a building's walls: a hallway's mouth, a side room's. The rest stay possible doors;
        # once localised the map proves them
        gaps, own_a, own_b = bays(walls, prop, connected, objects, np.array(doors), robot, params)
        through = np.zeros(len(gaps), dtype=bool)
        if params.bay_deep_rays > 0 and len(gaps):
            # ...and only an opening of a building's walls: the passage between a table's corner
            # and a partition's end is seen through as well, but the table's walls span no more
            # than the table (identify_kernels.group_spans; a piece of wall between two doors,
            # in one line with the building's walls past both its ends, or past one into a wall
            # of a building's own shape with its other end out of view, is theirs:
            # in_line_spans), and a table's corner by a wall has a wall in line on one side only
            # (map_proven_kernels.wall_shaped)
            w = np.ascontiguousarray(walls, dtype=float)
            c = np.ascontiguousarray(connected, dtype=np.int64)
            group, span = group_spans(w, c)
            p64 = np.ascontiguousarray(prop, dtype=np.int64)
            ob = np.ascontiguousarray(objects, dtype=bool)
            # a group turning at a concave corner is seen from a room's inside: a building's
            # walls (identify_kernels.inside_corners)
            inside = inside_corners(w, c, p64, group, ob, float(params.jamb_cap_max), CONCAVE)
            span = np.where(inside, np.maximum(span, params.bay_jamb_span), span)
            has_view, ranges, _, vx, vy, va, a0, inc = scan
            span = in_line_spans(w, group, span, ob, c, p64, float(params.bay_jamb_span),
                                 float(params.door_angle), float(params.door_offset_short),
                                 float(params.door_max_width), float(params.end_face_min_length),
                                 float(params.object_max_size), has_view,
                                 len(ranges), vx, vy, va, a0, inc, FLOATING, CONCAVE)
            # a ray ending on a thing standing there says nothing of the back: a small object's
            # walls, or any small group seen whole, however thin (a box seen as an L, a person's
            # two feet; the objects' depth keeps a thick wall's end from being one, for jambs)
            _, seen_whole = object_groups(w, c, p64, float(params.object_max_size), FLOATING, CONCAVE)
            things = ob | seen_whole
            rays, back = _deep_rays(gaps, own_a, own_b, walls, things, robot, scan, params, p64, group)
            side_on = deep_sides(gaps, w, c, p64, own_a, own_b,
                                 float(robot[0]), float(robot[1]), float(params.door_angle),
                                 float(params.door_depth), float(params.bay_run_on), CONVEX, FLOATING)
            # a block standing against a wall joins the building's walls, but its corner opens
            # none (map_proven_kernels.block_sides)
            blocky = block_sides(w, c, lengths, float(robot[0]), float(robot[1]), float(params.jamb_cap_max),
                                 float(params.door_angle))
            through = ((rays >= params.bay_deep_rays) | (~back & side_on)) & ~blocky[own_a] & ~blocky[own_b] \
                & (span[own_a] >= params.bay_jamb_span) & (span[own_b] >= params.bay_jamb_span) \
                & wall_shaped(gaps, w, c, p64, lengths, own_a, own_b, float(params.door_angle),
                              float(params.door_wall_min_length), float(params.bay_line_offset), CONCAVE, FLOATING,
                              np.ascontiguousarray(np.reshape(doors, (-1, 4)), dtype=float))
            # a bay seen at a block's corner stays refused when the block's far side is forgotten
            # (the local map drops a wall unseen for `merge.forget_seconds`; its front and near side,
            # still seen, make a side room's mouth): banned for good in the bays' own records (a
            # T-opening's place seen closed, a pocket's back, says nothing of a side room's mouth)
            refused = blocky[own_a] | blocky[own_b]
            if len(bay_ev) or refused.any():
                bay_ev, count = tally(bay_ev, np.ascontiguousarray(gaps, dtype=float), np.zeros(len(gaps), dtype=bool),
                                      refused, float(params.door_min_width), float(params.door_angle),
                                      int(params.end_face_evidence_max))
                through &= count >= 0
        doors.extend(gaps[through].tolist())
        door_kinds.extend(["bay"] * int(through.sum()))
        possible.extend(gaps[~through])
        kinds.extend(["bay"] * int((~through).sum()))
    if params.end_face_doors:
        for t_gap in lone_caps(walls, connected, objects, lengths, robot, params):
            possible.append(t_gap)
            kinds.append("end_face")
    # from a loose end, the wall it faces (door_kernels.loose_gaps)
    loose = np.flatnonzero(~is_convex)
    if len(loose):
        for gap in loose_gaps(np.ascontiguousarray(pts[loose]), np.ascontiguousarray(out_dir[loose]),
                              wi[loose].astype(np.int64), we[loose].astype(np.int64),
                              np.ascontiguousarray(walls, dtype=float), np.ascontiguousarray(connected, dtype=np.int64),
                              np.ascontiguousarray(objects, dtype=bool), float(params.door_min_width),
                              float(params.facing_distance)):
            possible.append(gap)
            kinds.append("loose_wall")
    d = np.array(doors).reshape(-1, 4)
    p = np.array(possible).reshape(-1, 4)
    if len(d) and len(p):  # a possible door where a door was found already is that door
        keep = away_from(np.ascontiguousarray(p, dtype=float), np.ascontiguousarray(d, dtype=float),
                         float(params.door_min_width) / 2)
        p = p[keep]
        kinds = [k for k, ok in zip(kinds, keep.tolist(), strict=True) if ok]
    return d, door_kinds, p, kinds, _records(t_ev, bay_ev)


def _deep_rays(gaps: np.ndarray, own_a: np.ndarray, own_b: np.ndarray, walls: np.ndarray, objects: np.ndarray,
               robot: tuple[float, float],
               scan: tuple[bool, np.ndarray, np.ndarray, float, float, float, float, float],
               params: IdentifyParams, prop: np.ndarray, group: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((K,) how many of each gap's five rays reached `door_depth` past its line, or never ended
    (identify_kernels.backed: a backed gap has none), (K,) bool: most of the rays ending behind
    it ended between its jambs within `door_depth`: its back seen). A ray ending on `objects`, or
    on a wall whose seen end stands in the gap's shadow apart from the jambs' walls (`group`:
    a box in a side room), says nothing (identify_kernels.backed_beside_things); so does a ray
    out of the laser's view reaching a remembered wall `door_depth` past the line (a bay is seen
    through by the scan, not by memory: the restaurant's table corner 1.3 m from a partition's
    end, the room behind remembered from the other side, a door while the robot drove away)."""
    if len(gaps) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=bool)
    _, _, deep, back = backed_beside_things(
        np.ascontiguousarray(gaps, dtype=float), np.ascontiguousarray(walls, dtype=float), own_a, own_b,
        float(robot[0]), float(robot[1]), *scan, np.zeros(len(gaps), dtype=bool),
        np.ascontiguousarray(objects, dtype=bool), float(params.door_occlusion), float(params.door_depth),
        float(params.jamb_cap_max), float(params.door_backed_share), prop, group, CONVEX,
        remembered_deep=False)
    return deep, back


def _view_arrays(view: View | None) -> tuple[bool, np.ndarray, np.ndarray, float, float, float, float, float]:
    """The current scan as the kernels take it: (in view at all, ranges, valid, the robot's
    pose x, y, a in the zero frame, first beam's angle, angle increment); none in view without
    a scan, with fewer than two beams or a zero or non-finite increment."""
    if view is None or len(view.ranges) < 2:
        return False, np.zeros(0), np.zeros(0, dtype=bool), 0.0, 0.0, 0.0, 0.0, 0.0
    a0 = float(view.angles[0])
    inc = (float(view.angles[-1]) - a0) / (len(view.angles) - 1)
    x, y, a = view.pose
    return (bool(inc != 0 and math.isfinite(inc)), np.ascontiguousarray(view.ranges, dtype=float),
            np.ascontiguousarray(view.valid, dtype=bool), float(x), float(y), float(a), a0, inc)


__all__ = ["CONNECTED", "DOOR_KINDS", "POSSIBLE_DOOR_KINDS", "Identified", "View", "identify", "object_walls"]
