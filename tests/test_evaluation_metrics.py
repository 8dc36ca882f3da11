"""Flat metric names and the default objective, from the summaries the evaluation writes."""

from __future__ import annotations

import pytest

from pico_studio.evaluation.frame_score import FrameScore
from pico_studio.evaluation.metrics import DEFAULT_OBJECTIVE, METRICS, f1, flatten
from pico_studio.evaluation.run_score import PoseScore, RunScore

REQUIRED = ["walls.precision", "walls.recall", "walls.f1", "corners.precision", "corners.recall", "corners.f1",
            "corners.convexity", "doors.precision", "doors.recall", "doors.f1", "endpoint_error_m",
            "localisation.pose_error_m.median", "localisation.pose_error_m.max",
            "localisation.heading_error_rad.median", "localisation.lost_fraction", "perceptor.ms_per_scan",
            "perception_score"]


def test_every_named_metric_is_declared_with_a_direction() -> None:
    assert set(REQUIRED) <= set(METRICS) and DEFAULT_OBJECTIVE in METRICS
    assert METRICS["perception_score"].higher_is_better and not METRICS["endpoint_error_m"].higher_is_better
    assert not METRICS["perceptor.ms_per_scan"].needs_truth


def test_flatten_gives_f1_and_the_perception_score() -> None:
    run = RunScore([FrameScore(wall_len=10, wall_len_ok=8, truth_len=10, truth_len_ok=5, corners=4, corners_ok=3,
                               truth_corners=6, truth_corners_ok=3, corners_paired=3, convexity_ok=2, doors=2,
                               doors_ok=1, truth_doors=1, truth_doors_ok=1)])
    pose = PoseScore()
    pose.add((1.0, 0.0, 0.1), (1.0, 0.5, 0.0), False)
    pose.add(None, (0.0, 0.0, 0.0), True)
    flat = flatten({**run.summary(), "localisation": pose.summary()})
    assert flat["walls.f1"] == pytest.approx(f1(0.8, 0.5)) == pytest.approx(2 * 0.4 / 1.3)
    assert flat["corners.f1"] == pytest.approx(f1(0.75, 0.5)) and flat["doors.f1"] == pytest.approx(f1(0.5, 1.0))
    expected = (f1(0.8, 0.5) + f1(0.75, 0.5) + f1(0.5, 1.0) + 2 / 3) / 4
    assert flat["perception_score"] == pytest.approx(expected)
    assert flat["localisation.pose_error_m.median"] == pytest.approx(0.5)
    assert flat["localisation.lost_fraction"] == pytest.approx(0.5)
    assert flatten({"perceptor": run.summary()})["walls.precision"] == pytest.approx(0.8)  # a run's report
    assert f1(0.0, 0.0) == 0.0 and flatten({}) == {}


def test_a_behaviour_outcome_becomes_metrics() -> None:
    flat = flatten({"behaviour": "escape-room", "state": "done", "escaped": True, "collisions": 1, "sim_seconds": 40.0})
    assert flat == {"behaviour.success": 1.0, "behaviour.collisions": 1.0, "behaviour.sim_seconds": 40.0}
    assert flatten({"behaviour": "escape-room", "state": "done", "escaped": False})["behaviour.success"] == 0.0
    assert flatten({"behaviour": "room-finder", "state": "done", "rooms_right": False})["behaviour.success"] == 0.0
