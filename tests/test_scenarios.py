"""Scenario sets: loading (bad input names the file and the field) and scoring one end to end."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pico_studio.cli import main
from pico_studio.config.tree import Config
from pico_studio.errors import ConfigError
from pico_studio.evaluation.runner import evaluate_scenario, evaluate_scenarios
from pico_studio.evaluation.scenarios import load_scenarios

ROOT = Path(__file__).resolve().parents[1]
SETS = ROOT / "pico_studio" / "data" / "scenarios"
MAPS = ROOT / "pico_studio" / "data" / "maps"


def write(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "set.yaml"
    p.write_text(text)
    return p


def test_the_shipped_sets_load_with_paths_resolved() -> None:
    builtin = load_scenarios(SETS / "builtin.yaml")
    names = [s.name for s in builtin]
    assert {"hospital_2019", "restaurant_2024", "emc_example", "escape_room_world_7", "hospital_2019_tour"} <= set(names)
    by = {s.name: s for s in builtin}
    assert by["restaurant_2024"].sim_config == str((MAPS / "restaurant_2024_sim.json").resolve())
    assert by["hospital_2019"].method == "poses" and by["hospital_2019_tour"].method == "behaviour"
    assert by["escape_room_world_7"].world == "escape:7"
    assert load_scenarios(SETS / "smoke.yaml").name == "smoke"
    furnished = load_scenarios(ROOT / "examples" / "scenarios" / "furnished_worlds.yaml")
    assert {s.world.partition(":")[0] for s in furnished if s.world} == {"hall", "cafe", "ward"}
    every = load_scenarios(ROOT / "examples" / "scenarios" / "perception_worlds.yaml")
    assert len(every) == 102 and {s.world.partition(":")[0] for s in every if s.world} == {
        "cafe", "hall", "ward", "escape", "rooms"}
    assert by["restaurant_2024"].map in {s.map for s in every}  # the drawn maps, found from the file's folder
    slant = load_scenarios(ROOT / "examples" / "scenarios" / "slant_worlds.yaml")
    assert [s.world for s in slant] == [f"slant:{k}" for k in range(12)]
    images = load_scenarios(ROOT / "examples" / "scenarios" / "heightmap_worlds.yaml")
    assert all(s.heightmap for s in images) and len(images) == 17
    assert {s.world.partition(":")[0] for s in images if s.world} == {
        "ward", "suite", "slant", "cafe", "hall", "escape", "rooms"}


def test_a_furnished_world_brings_its_people_and_is_scored_among_its_furniture(tmp_path: Path) -> None:
    """`world: cafe:SEED` (and hall, ward): the generated JSON map with its tables and the
    simulator config with its walking people, scored like a map; a scenario's own sim_config
    replaces the people."""
    from pico_studio.evaluation.worlds import make_world

    w = make_world("cafe:3")
    assert w.sim_config is not None and len(w.sim_config.objects) == 2 and len(w.map.objects) >= 4
    assert w.start == w.sim_config.initial_pose
    p = write(tmp_path, "scenarios:\n  - {name: ward, world: 'ward:3', poses: 4, seed: 1, localise: true}\n")
    r = evaluate_scenario(next(iter(load_scenarios(p))), Config())
    assert r.metrics["doors.recall"] > 0.5 and r.metrics["map_doors.precision"] == 1.0
    (tmp_path / "still.json").write_text(json.dumps({"initial_pose": list(w.start), "objects": []}))
    p = write(tmp_path, "scenarios:\n  - {name: cafe, world: 'cafe:3', sim_config: still.json, poses: 2}\n")
    from pico_studio.evaluation.runner import _world

    assert _world(next(iter(load_scenarios(p))), Config())[3].objects == ()


def test_a_map_or_world_seen_as_a_heightmap_is_scored_on_its_outlines(tmp_path: Path) -> None:
    """`heightmap: true` draws the map or world into an image and reads it back first (as a
    .png of it would load): walls become the outlines of dark blobs, 7.5 cm thick for a JSON
    map's lines, and the robot still localises on them (a point just behind a thin wall's near
    face once took the far face's label and pulled the pose 2 cm off: lost 0.69 of the frames
    on emc_example's image, 0.53 on hospital_2019's)."""
    from pico_studio.evaluation.runner import _world

    (tmp_path / "m.json").write_text((MAPS / "emc_example.json").read_text())
    p = write(tmp_path, "defaults: {poses: 4, seed: 1, localise: true}\nscenarios:\n"
              "  - {name: lines, map: m.json}\n  - {name: image, map: m.json, heightmap: true}\n"
              "  - {name: world, world: 'suite:4', heightmap: true, poses: 2}\n")
    lines, image, world = load_scenarios(p)
    assert image.heightmap and not lines.heightmap
    m_lines, m_image = _world(lines, Config())[0], _world(image, Config())[0]
    assert m_image.extra["heightmap"]["walls"] == "outlines" and "heightmap" not in m_lines.extra
    assert len(m_image.walls) > len(m_lines.walls)  # each line is now a band's two faces
    gmap, start, _, sim_config = _world(world, Config())
    assert gmap.extra["heightmap"]["walls"] == "outlines" and start is not None and sim_config is not None
    assert len(gmap.openings()) >= 4  # the world's doorways are openings of its image too
    r = evaluate_scenario(image, Config())
    assert r.metrics["localisation.lost_fraction"] <= 0.15  # found after its first scans, never lost again
    assert r.metrics["localisation.pose_error_m.max"] < 0.01
    assert r.metrics["walls.precision"] > 0.95


@pytest.mark.parametrize("body, field, words", [
    ("scenarios:\n  - name: a\n    map: m.json\n    pose: 3\n", "scenarios[0] (a).pose", "did you mean 'poses'"),
    ("scenarios:\n  - name: a\n    map: nowhere.json\n", "scenarios[0] (a).map", "no such file"),
    ("scenarios:\n  - name: a\n    poses: 3\n", "scenarios[0] (a)", "needs a map, a world"),
    ("scenarios:\n  - name: a\n    map: m.json\n    poses: -2\n", "scenarios[0] (a).poses", "at least 1"),
    ("scenarios:\n  - name: a\n    map: m.json\n    seconds: soon\n", "scenarios[0] (a).seconds", "must be a number"),
    ("scenarios:\n  - name: a\n    world: maze:3\n", "scenarios[0] (a).world", "unknown world"),
    ("scenarios:\n  - name: a\n    world: escape:x\n", "scenarios[0] (a).world", "integer seed"),
    ("scenarios:\n  - name: a\n    map: m.json\n    behaviour: hospitl\n", "scenarios[0] (a).behaviour", "did you mean 'hospital'"),
    ("scenarios:\n  - name: a\n    recording: tape:x.bag\n", "scenarios[0] (a).recording", "bag:FILE or carmen:FILE"),
    ("scenario:\n  - name: a\n", "scenario", "did you mean 'scenarios'"),
    ("scenarios: []\n", "scenarios", "non-empty list"),
    ("scenarios:\n  - map: m.json\n", "scenarios[0].name", "needs a name"),
    ("scenarios:\n  - {name: a, map: m.json}\n  - {name: a, map: m.json}\n", "scenarios[1].name", "duplicate"),
    ("scenarios:\n  - {name: a, map: m.json, heightmap: yes please}\n", "scenarios[0] (a).heightmap", "true or false"),
    ("scenarios:\n  - {name: a, recording: 'carmen:m.json', heightmap: true}\n", "scenarios[0] (a).heightmap",
     "only a map or a world"),
])
def test_bad_scenario_sets_name_the_file_and_the_field(tmp_path: Path, body: str, field: str, words: str) -> None:
    (tmp_path / "m.json").write_text((MAPS / "emc_example.json").read_text())
    p = write(tmp_path, body)
    with pytest.raises(ConfigError) as e:
        load_scenarios(p)
    assert e.value.file == str(p) and e.value.field == field and words in str(e.value)


def test_eval_scores_the_smoke_set_end_to_end(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["eval", "--scenarios", str(SETS / "smoke.yaml"), "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert set(r["scenarios"]) == {"hospital_poses", "restaurant_drive", "escape_world"}
    poses = r["scenarios"]["hospital_poses"]
    assert poses["summary"]["poses"] == 3 and poses["frames"] == 30
    assert 0.0 <= poses["metrics"]["perception_score"] <= 1.0
    assert poses["summary"]["localisation"]["pose_error_m"]["median"] < 0.05
    drive = r["scenarios"]["restaurant_drive"]["metrics"]
    assert "localisation.pose_error_m.max" in drive and "walls.f1" in drive
    escape = r["scenarios"]["escape_world"]
    assert escape["summary"]["behaviour"] == "escape-room" and "behaviour.success" in escape["metrics"]
    # the set's figures are the mean over the scenarios that have them
    both = [r["scenarios"][n]["metrics"]["walls.f1"] for n in ("hospital_poses", "restaurant_drive")]
    assert r["metrics"]["walls.f1"] == pytest.approx(sum(both) / 2)
    assert r["objective"] == "perception_score" and "perception_score" in r["metrics"]


def test_eval_scenarios_bad_input_is_one_line(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    p = write(tmp_path, "scenarios:\n  - name: a\n    mapp: x.json\n")
    assert main(["eval", "--scenarios", str(p), "--json"]) == 2
    err = capsys.readouterr().err
    assert str(p) in err and "scenarios[0] (a).mapp" in err and "did you mean 'map'" in err
    assert main(["eval", "--scenarios", str(SETS / "smoke.yaml"), "--only", "nope"]) == 2
    assert "no scenario 'nope'" in capsys.readouterr().err


def test_scenarios_in_worker_processes_give_the_same_figures(tmp_path: Path) -> None:
    p = write(tmp_path, f"defaults: {{seed: 2, frames: 5}}\nscenarios:\n"
                        f"  - {{name: a, map: {MAPS / 'emc_example.json'}, poses: 2}}\n"
                        f"  - {{name: b, map: {MAPS / 'hospital_2019.json'}, poses: 2}}\n")
    ss = load_scenarios(p)
    one = evaluate_scenarios(ss, Config())
    two = evaluate_scenarios(ss, Config(), workers=2)
    strip = {"perceptor.ms_per_scan"}  # a time, not a figure
    for name in ("a", "b"):
        a = {k: v for k, v in one.per_scenario[name].metrics.items() if k not in strip}
        b = {k: v for k, v in two.per_scenario[name].metrics.items() if k not in strip}
        assert a == b
    assert one.frames == two.frames == 20
    assert evaluate_scenario(ss.scenarios[0], Config()).metrics["walls.f1"] == one.per_scenario["a"].metrics["walls.f1"]


def test_a_recording_scenario_replays_through_the_perceptor(tmp_path: Path) -> None:
    log = ROOT / "tests" / "data" / "recordings" / "intel-corrected.log.gz"
    p = write(tmp_path, f"scenarios:\n  - {{name: intel, recording: 'carmen:{log}', seconds: 30}}\n")
    s = load_scenarios(p).scenarios[0]
    assert s.method == "recording" and s.recording == f"carmen:{log.resolve()}"
    r = evaluate_scenario(s, Config())
    assert r.frames == r.summary["frames_read"] > 5 and r.summary["perceptor"]["frames_perceived"] == r.frames
    assert r.summary["perceptor"]["truth_path_m"] >= 0.0
    assert r.metrics == {}  # no map truth: counts only, nothing scored
