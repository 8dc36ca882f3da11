"""Evidence over scans for a T-opening on a wall seen short: a wall's end (seen) facing a
building wall's face a door's width on, the wall seen only 0.8 m (shorter than
end_face_min_length), its far end floating. From one scan that is a partition hidden in part
or a table's side; it becomes a door once `end_face_evidence_scans` scans saw free rays
through the gap into free space (at least `door_depth` past its line) *and* did not look past
the wall's far end (hidden behind something nearer, or out of view: it may run on). A scan
looking past the far end, in line with the wall, shows the wall ends there: a table's side,
banned for good. Rays that only graze past the gap onto its face (a pocket by a wall, seen
along the gap's line) show no free space behind it. Until then the gap is a possible door of
kind "end_face", for the map to confirm once localised."""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np

from pico_studio.config import Config, load_config
from pico_studio.config.perception_params import IdentifyParams
from pico_studio.core.behaviours.registry import Drive
from pico_studio.core.geometry import transform_segments
from pico_studio.core.perception import Perceptor
from pico_studio.core.perception.identify import View, identify
from pico_studio.evaluation.frame_score import Tolerances, as_pose, doors_match, zero_to_map
from pico_studio.json_map import load_map
from pico_studio.session import Session
from pico_studio.sim import Simulator
from pico_studio.sim.sim_config import load_sim_config
from tests.clutter_scenes import laser_view
from tests.conftest import MAPS

PARAMS = load_config(None).perception.identify
ROBOT = (5.64, 1.28)
SIDE = [4.8, 2.0, 4.8, 1.2]  # its lower end seen, its upper end floating
FLOOR = [2.8, 0.2, 6.0, 0.2]
WALLS = np.array([SIDE, FLOOR])
FREE = np.full((2, 2), -1, dtype=np.int64)
SEEN = np.array([[False, True], [False, False]])
GAP = [4.8, 1.2, 4.8, 0.2]


def _view(beyond_far_end: float | None, fov: float = np.pi, robot: tuple[float, float] = ROBOT,
          floor: bool = False) -> View:
    """A scan reaching 8 m everywhere (free through the gap), except the beams towards the
    point on along the wall past its far end: they end `beyond_far_end` from it (negative:
    before it, something in front hides it; positive: past it, nothing there; None: as the
    rest). `fov`: half the field of view, about the robot's heading towards the gap; `floor`:
    beams pointing down end on the floor's line (y = 0.2) instead."""
    heading = float(np.arctan2(0.7 - robot[1], 4.8 - robot[0]))
    angles = np.linspace(-fov, fov, 721)
    ranges = np.full(721, 8.0)
    if floor:
        down = np.sin(angles + heading)
        ranges = np.where(down < -1e-6, (robot[1] - 0.2) / np.maximum(-down, 1e-6), ranges)
    if beyond_far_end is not None:
        target = np.array([4.8, 2.0 + PARAMS.end_face_continuation])
        bearing = float(np.arctan2(target[1] - robot[1], target[0] - robot[0])) - heading
        bearing = float(np.angle(np.exp(1j * bearing)))  # in (-pi, pi]
        near = np.abs(angles - bearing) < 0.05
        ranges[near] = float(np.hypot(*(target - np.asarray(robot)))) + beyond_far_end
    return View(ranges, angles, np.ones(721, dtype=bool), (robot[0], robot[1], heading))


def _scans(view: View, n: int, robot: tuple[float, float] = ROBOT) -> list[int]:
    """Doors found after each of `n` scans, the evidence handed from one to the next."""
    evidence, found = None, []
    for _ in range(n):
        out = identify(WALLS, FREE, SEEN, robot, PARAMS, view, evidence)
        evidence = out.evidence
        found.append(len(out.doors))
        if len(out.doors):
            assert out.door_kind == ["end_face"] and np.allclose(out.doors[0], GAP, atol=1e-6)
    return found


def test_a_t_opening_on_a_hidden_wall_becomes_a_door_after_enough_scans():
    k = PARAMS.end_face_evidence_scans
    assert k > 1
    assert _scans(_view(-1.0), k + 2) == [0] * (k - 1) + [1] * 3


def test_a_tables_side_seen_to_end_is_no_door():
    """The beam in line with the wall goes on 1 m past its far end: a table's side."""
    assert _scans(_view(1.0), 10) == [0] * 10


def test_a_far_end_out_of_view_does_not_ban_the_gap():
    """The wall runs out of the field of view: it may run on, and the rays through the gap
    reach free space behind it, so the scans count."""
    k = PARAMS.end_face_evidence_scans
    assert _scans(_view(None, fov=0.3), k + 2) == [0] * (k - 1) + [1] * 3


def _pocket_scans(walls: np.ndarray, connected: np.ndarray, seen: np.ndarray, robot: tuple[float, float],
                  n: int) -> tuple[list[int], list[str]]:
    """Doors found after each of `n` scans seen along the gap's line from above (every ray
    through the gap ends on the floor a few cm to dm past the line), and the last scan's
    possible door kinds."""
    evidence, found = None, []
    view = _view(-1.0, robot=robot, floor=True)
    for _ in range(n):
        out = identify(walls, connected, seen, robot, PARAMS, view, evidence)
        evidence = out.evidence
        found.append(len(out.doors))
    return found, out.possible_door_kind


def test_rays_grazing_into_a_pocket_are_no_evidence():
    """Seen along the gap's line from above, every ray through the gap ends on the floor (the
    face) a few cm to dm past the line: no free space shown behind it. Where the floor ends
    0.8 m past the line in a corner with the pocket's back (a table's front by a wall) it
    never becomes a door however long the far end stays hidden; it stays a possible door."""
    robot = (5.2, 3.0)
    back = [4.0, 0.2, 4.0, 1.4]
    walls = np.array([SIDE, [4.0, 0.2, 6.0, 0.2], back])
    connected = np.array([[-1, -1], [2, -1], [1, -1]], dtype=np.int64)
    seen = np.array([[False, True], [False, False], [False, False]])
    found, kinds = _pocket_scans(walls, connected, seen, robot, 10)
    assert found == [0] * 10
    assert "end_face" in kinds


def test_rays_grazing_onto_a_face_running_on_out_of_view_count():
    """The same view, the floor seen running on 2 m past the gap's line into the view's edge
    (no corner: nothing closes the space behind the gap; restaurant_2024's T-opening below its
    block seen from the right): once `end_face_evidence_scans` scans saw rays pass the gap, a
    door — with `door_run_on` 0 it never is."""
    robot = (5.2, 3.0)
    k = PARAMS.end_face_evidence_scans
    assert _pocket_scans(WALLS, FREE, SEEN, robot, k + 2)[0] == [0] * (k - 1) + [1] * 3
    off = replace(PARAMS, door_run_on=0.0)
    evidence = None
    for _ in range(k + 2):
        out = identify(WALLS, FREE, SEEN, robot, off, _view(-1.0, robot=robot, floor=True), evidence)
        evidence = out.evidence
        assert len(out.doors) == 0


def test_a_face_running_on_only_in_the_local_map_is_no_evidence():
    """The same gap seen from the same place, cast for real: the side runs on up out of sight
    (its far end floating in the local map), so past the rays through the gap, which land on the
    floor a few cm past its line, every beam towards the floor ends on the side. The floor
    running on 2 m past the line is the local map's memory, not this scan's: no evidence, a
    possible door however many scans (slant:3's pocket beside a table by the top wall, seen at a
    graze from 5.7 m, its face remembered running on: a door for 348 frames of a 120 s run).
    Seen from lower down, the floor `door_run_on` past the line in view through the gap (the
    rays through it still landing on the floor short of `end_face_depth`), the scans count."""
    solid = [[4.8, 4.0, 4.8, 1.2], FLOOR]  # the side running on up, out of sight
    k = PARAMS.end_face_evidence_scans

    def found(robot: tuple[float, float]) -> tuple[list[int], list[str]]:
        heading = float(np.arctan2(0.7 - robot[1], 4.8 - robot[0]))
        view, evidence, doors = laser_view(solid, robot, heading), None, []
        for _ in range(k + 2):
            out = identify(WALLS, FREE, SEEN, robot, PARAMS, view, evidence)
            evidence = out.evidence
            doors.append(len(out.doors))
        return doors, out.possible_door_kind

    hidden, kinds = found((5.2, 3.0))
    assert hidden == [0] * (k + 2) and "end_face" in kinds
    assert found((5.5, 2.0))[0] == [0] * (k - 1) + [1] * 3


def test_a_gap_waiting_for_evidence_is_a_possible_door():
    out = identify(WALLS, FREE, SEEN, ROBOT, PARAMS, _view(-1.0))
    assert len(out.doors) == 0
    k = out.possible_door_kind.index("end_face")
    assert np.allclose(out.possible_doors[k], GAP, atol=1e-6)


def test_one_scan_past_the_far_end_bans_the_gap():
    """Promoted, then a scan looks past the far end: no door again, however many scans hide it."""
    k = PARAMS.end_face_evidence_scans
    evidence = None
    for view in [_view(-1.0)] * k + [_view(1.0)] + [_view(-1.0)] * (k + 2):
        out = identify(WALLS, FREE, SEEN, ROBOT, PARAMS, view, evidence)
        evidence = out.evidence
    assert len(out.doors) == 0


def test_a_long_wall_needs_no_evidence():
    """The same wall seen 1.6 m (a building's, end_face_min_length): a door from the first scan."""
    walls = np.array([[4.8, 2.8, 4.8, 1.2], FLOOR])
    out = identify(walls, FREE, SEEN, ROBOT, PARAMS, _view(None))
    assert out.door_kind == ["end_face"]


def test_a_thick_walls_capped_end_seen_short_counts_as_well():
    """restaurant_2024's block end (x = 4.6..4.8) seen from below-left: its side only 0.32 m
    (shorter than a door frame's wall: the rest hidden), its lower end joined to a whole 0.19 m
    end cap (a thick wall's end; a table's end is as wide as the table) facing the floor 1 m
    down. After enough scans through the gap into free space it is a T-opening; the same short
    piece with no cap (a person's or a chair's side) never is, only a possible door for the map
    to prove (a glimpse of a thick wall's side looks the same)."""
    robot = (3.71, 0.94)
    side, cap = [4.6, 1.52, 4.6, 1.2], [4.6, 1.2, 4.79, 1.2]
    heading = float(np.arctan2(0.7 - robot[1], 4.6 - robot[0]))
    angles = np.linspace(-np.pi / 2, np.pi / 2, 361)
    ranges = np.full(361, 8.0)
    hidden = np.array([4.6, 1.52 + PARAMS.end_face_continuation])  # the side may run on: hidden
    bearing = float(np.arctan2(hidden[1] - robot[1], hidden[0] - robot[0])) - heading
    ranges[np.abs(angles - bearing) < 0.05] = 0.5
    view = View(ranges, angles, np.ones(361, dtype=bool), (robot[0], robot[1], heading))

    possible: list[str] = []

    def doors_after(walls: list[list[float]], connected: list[list[int]], seen: list[list[bool]], n: int) -> list[int]:
        evidence, found = None, []
        for _ in range(n):
            out = identify(np.array(walls), np.array(connected, dtype=np.int64), np.array(seen), robot, PARAMS,
                           view, evidence)
            evidence = out.evidence
            found.append(len(out.doors))
        possible[:] = out.possible_door_kind
        return found

    k = PARAMS.end_face_evidence_scans
    capped = doors_after([side, cap, FLOOR], [[-1, 1], [0, -1], [-1, -1]],
                         [[False, False], [False, True], [False, False]], k + 1)
    assert capped == [0] * (k - 1) + [1] * 2
    bare = doors_after([side, FLOOR], [[-1, -1], [-1, -1]], [[False, True], [False, False]], k + 1)
    assert bare == [0] * (k + 1) and "end_face" in possible



def _doors_seen_from(pose: tuple[float, float, float], params: IdentifyParams) -> np.ndarray:
    """restaurant_2024 simulated with its box: the robot at `pose` turns 0.4 rad/s for 20
    scans; its own doors at the last, in the map frame (placed by the true pose)."""
    cfg = Config()
    sim = Simulator(load_map(MAPS / "restaurant_2024.json"), cfg.sim, load_sim_config(MAPS / "restaurant_2024_sim.json"),
                    seed=1, initial_pose=pose)
    perceptor = Perceptor(replace(cfg.perception, identify=params))
    for sf in itertools.islice(Session(sim, perceptor=perceptor, behaviour=Drive(0.0, 0.0, 0.4)).frames(), 20):
        wm = sf.world_model
    return transform_segments(np.asarray(wm.doors, dtype=float).reshape(-1, 4), zero_to_map(wm, as_pose(sim.truth.pose)))


def test_restaurants_t_opening_below_its_block_seen_from_the_right():
    """From (5.5, 2.3) the block's right face (x = 4.8) is seen 1 m, its far end out of view,
    and the rays through the 1 m gap below it land on the floor wall 0.2-0.5 m past the gap's
    line, the floor seen running on 0.6 m past it behind the block: the T-opening is found
    (it never was before `door_run_on`)."""
    truth = np.array([[4.7, 1.2, 4.7, 0.2]])
    pose = (5.5, 2.3, -1.2)
    assert doors_match(_doors_seen_from(pose, PARAMS), truth, Tolerances()).any()
    assert not doors_match(_doors_seen_from(pose, replace(PARAMS, door_run_on=0.0)), truth, Tolerances()).any()
