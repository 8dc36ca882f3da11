"""Truth door visibility: a door is visible when the scan's beams hit the wall at each of its
jambs over at least `jamb_min_seen`, not when one point of a jamb is in view."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from sim_helpers import box_map

from pico_studio.config.sim_params import SimParams
from pico_studio.json_map import load_json_map
from pico_studio.sim import Simulator


def _params(**truth: float) -> SimParams:
    p = SimParams()
    return dataclasses.replace(p, truth=dataclasses.replace(p.truth, **truth))


def _mids(doors: np.ndarray) -> set[tuple[float, float]]:
    return {tuple(np.round((d[:2] + d[2:]) / 2, 2)) for d in doors}


def test_a_jamb_at_the_fans_edge_is_seen_too_little() -> None:
    m = load_json_map("examples/maps/hospital_2019.json")
    pose = (1.2, 3.0, 0.0)  # the door below, (1.25, 2.1): its left jamb at the -2 rad fan edge
    truth = Simulator(m, initial_pose=pose).truth
    o = truth.door_openings()
    k = int(np.argmin(np.hypot(*(((o[:, :2] + o[:, 2:]) / 2) - (1.25, 2.1)).T)))
    seen = sorted([float(truth.jamb_seen_length(o[k : k + 1, :2])[0]), float(truth.jamb_seen_length(o[k : k + 1, 2:])[0])])
    assert 0.0 < seen[0] < 0.15 < seen[1]  # one jamb barely, the other well seen
    assert (1.25, 2.1) not in _mids(truth.visible_doors())
    lenient = Simulator(m, _params(jamb_min_seen=seen[0] / 2), initial_pose=pose).truth
    assert (1.25, 2.1) in _mids(lenient.visible_doors())


def test_jamb_seen_length_is_what_the_beams_hit_near_the_jamb() -> None:
    # a 6 x 4 box; the robot in the middle facing +x sees the right wall whole
    sim = Simulator(box_map(6.0, 4.0), initial_pose=(3.0, 2.0, 0.0))
    reach = sim.params.truth.jamb_reach
    # a "jamb" in the middle of the right wall: beams hit it over reach either side
    assert sim.truth.jamb_seen_length(np.array([[6.0, 2.0]]))[0] == pytest.approx(2 * reach, abs=0.03)
    # behind the robot (the left wall is outside the +-2 rad fan): nothing
    assert sim.truth.jamb_seen_length(np.array([[0.0, 2.0]]))[0] == 0.0
    # a point away from every wall has no jamb wall
    assert sim.truth.jamb_seen_length(np.array([[5.0, 2.0]]))[0] == 0.0
