"""The eval method among furniture and people: restaurant_2024 with its box standing and then
walking, and a generated cafe (`clutter_scenes.cafe_world`: T-openings, table rows, two people
crossing). End points are scored against every true vertex — the box's corners and the closed
door leaf's ends too (`truth.dynamic_vertices()`) — so a rightly seen box corner is no error."""

from __future__ import annotations

import json

from pico_studio.config import Config
from pico_studio.evaluation.runner import evaluate_map, evaluate_poses
from pico_studio.evaluation.worlds import make_world
from tests.clutter_scenes import cafe_world, ward_world


def test_restaurant_with_its_moving_box(maps_dir):
    r = evaluate_map(str(maps_dir / "restaurant_2024.json"), sim_config=str(maps_dir / "restaurant_2024_sim.json"),
                     poses=12, seed=1)
    assert r["endpoint_error_m"] <= 0.03  # 0.12 while the box's corners counted as errors
    assert r["convexity_accuracy"] >= 0.98
    false_doors = r["doors_detected"] * (1 - r["door_precision"])
    assert false_doors <= 1.01  # two of three doors were false (a table end and the box)
    assert r["map_door_precision"] == 1.0  # once localised, the map rejects what is left


def test_a_generated_cafe(tmp_path):
    """At most one false door in 12 poses: a table's top face, seen 1.1 m with its far end out of
    view, in line with a gap to a partition's face that runs on out of view past the line is a
    partition's T-opening seen steeply to `door_run_on` (none before it; over 27 cafes own
    precision 0.993 -> 0.970 for recall 0.873 -> 0.910); the map rejects it."""
    doc, sim = cafe_world(1)
    (tmp_path / "cafe.json").write_text(json.dumps(doc))
    (tmp_path / "cafe_sim.json").write_text(json.dumps(sim))
    r = evaluate_map(str(tmp_path / "cafe.json"), sim_config=str(tmp_path / "cafe_sim.json"), poses=12, seed=1)
    assert r["doors_visible"] >= 4
    false_doors = r["doors_detected"] * (1 - r["door_precision"])
    assert false_doors <= 1.01 and r["door_recall"] >= 0.8
    assert r["map_door_precision"] == 1.0
    assert r["endpoint_error_m"] <= 0.03 and r["convexity_accuracy"] >= 0.98


def test_a_generated_ward(tmp_path):
    """A hospital ward (`clutter_scenes.ward_world`): 2 m beds whose corners were door jambs
    towards the corridor wall's doors (2 false doors in 12 poses before the block-corner rule);
    once localised the map keeps every door and rejects what is left."""
    doc, sim = ward_world(3)
    (tmp_path / "ward.json").write_text(json.dumps(doc))
    (tmp_path / "ward_sim.json").write_text(json.dumps(sim))
    r = evaluate_map(str(tmp_path / "ward.json"), sim_config=str(tmp_path / "ward_sim.json"), poses=12, seed=1)
    assert r["doors_visible"] >= 10
    false_doors = r["doors_detected"] * (1 - r["door_precision"])
    assert false_doors <= 1.01 and r["door_recall"] >= 0.9
    assert r["map_door_precision"] == 1.0 and r["map_door_recall"] >= 0.9
    assert r["endpoint_error_m"] <= 0.03 and r["convexity_accuracy"] >= 0.98


def test_a_slanted_ward():
    """A ward drawn askew (`slant:0`: its walls meet at 76 degrees): the rules hold off the
    square, and the truth finds every doorway of its askew thick walls (before a wall's end
    pointed along its cap's normal, one doorway was no opening and the door found there false)."""
    w = make_world("slant:0")
    r = evaluate_poses(w.map, Config(), w.sim_config, seed=1, poses=12)
    assert r["doors_visible"] >= 8
    false_doors = r["doors_detected"] * (1 - r["door_precision"])
    assert false_doors <= 1.01 and r["door_recall"] >= 0.75
    assert r["map_door_precision"] == 1.0 and r["map_door_recall"] >= 0.85
    assert r["endpoint_error_m"] <= 0.03 and r["convexity_accuracy"] >= 0.98
