"""`pico-studio tune` on a journal file: it improves, resumes, refuses, records failures."""

from __future__ import annotations

from pathlib import Path

import optuna
import pytest

from pico_studio.config import load_config
from pico_studio.tuning.study import JOURNAL
from tests.tune_helpers import bad_config, scenario_file, tune

MERGE2 = "perception.merge.confirm_hits,perception.merge.min_length"


def _study(out, name):
    from optuna.storages.journal import JournalFileBackend, JournalStorage

    return optuna.load_study(study_name=name, storage=JournalStorage(JournalFileBackend(str(out / JOURNAL))))


def test_a_short_study_improves_on_a_bad_start(tmp_path, capsys):
    sc = scenario_file(tmp_path)
    code, j, _ = tune(capsys, "--scenarios", str(sc), "--config", str(bad_config(tmp_path)), "--params", MERGE2,
                      "--trials", "10", "--out", str(tmp_path / "o"))
    assert code == 0
    assert set(j) == {"study", "trials", "complete", "default", "best", "holdout"}
    assert j["trials"] == 10 and j["complete"] == 10
    assert j["best"]["value"] > j["default"]["value"] + 0.2
    best = load_config(j["best"]["config"])  # the partial YAML loads back as the best trial
    assert best.perception.merge.confirm_hits == j["best"]["params"]["perception.merge.confirm_hits"]
    assert best.perception.merge.min_length == pytest.approx(j["best"]["params"]["perception.merge.min_length"])
    html = (tmp_path / "o" / "report.html").read_text()
    assert "Optimisation history" in html and "plotly" in html and "Parameter importances" in html


def test_the_journal_resumes_where_it_stopped(tmp_path, capsys):
    sc, out = scenario_file(tmp_path), tmp_path / "o"
    args = ["--scenarios", str(sc), "--params", MERGE2, "--out", str(out), "--study", "s"]
    assert tune(capsys, *args, "--trials", "3")[0] == 0
    first = [(t.number, t.params) for t in _study(out, "s").trials]
    _study(out, "s").ask()  # a trial left running, as by a run that was killed
    code, j, _ = tune(capsys, *args, "--trials", "6")
    assert code == 0 and j["trials"] == 6
    trials = _study(out, "s").trials
    assert [(t.number, t.params) for t in trials[:3]] == first
    assert trials[3].state == optuna.trial.TrialState.FAIL  # the interrupted one, not lost
    assert [t.number for t in trials] == list(range(6))
    assert sum(bool(t.user_attrs.get("start")) for t in trials) == 1  # one start trial only


def test_a_study_of_another_search_space_is_refused_and_kept(tmp_path, capsys):
    sc, out = scenario_file(tmp_path), tmp_path / "o"
    assert tune(capsys, "--scenarios", str(sc), "--params", MERGE2, "--out", str(out), "--trials", "2")[0] == 0
    before = (out / JOURNAL).read_bytes()
    code, _, err = tune(capsys, "--scenarios", str(sc), "--params", "perception.identify.*", "--out", str(out),
                        "--trials", "4")
    assert code == 2
    assert err.count("\n") == 1 and "another search space" in err and "--study" in err
    assert (out / JOURNAL).read_bytes() == before


def test_door_widths_searched_together_spend_no_trial_on_an_invalid_pair(tmp_path, capsys):
    # door_min_width is declared below door_max_width: the space samples it so (it failed
    # about half the trials when each was drawn from its own range)
    code, j, _ = tune(capsys, "--scenarios", str(scenario_file(tmp_path)), "--trials", "8", "--seed", "3",
                      "--params", "perception.identify.door_min_width,perception.identify.door_max_width",
                      "--out", str(tmp_path / "o"))
    assert code == 0 and j["trials"] == 8 and j["complete"] == 8
    for t in _study(tmp_path / "o", "tiny-1").trials:
        assert t.params["perception.identify.door_min_width"] < t.params["perception.identify.door_max_width"]


@pytest.mark.parametrize(("args", "names"), [
    (["--objective", "walls.f2"], "walls.f2"),
    (["--params", "perception.nope.*"], "perception.nope.*"),
    (["--storage", "postgresql://nobody@127.0.0.1:1/none"], "127.0.0.1:1"),
    (["--holdout", "0.5"], "--holdout"),  # one scenario: nothing to hold out
])
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, args, names):
    code, _, err = tune(capsys, "--scenarios", str(scenario_file(tmp_path)), "--trials", "2",
                        "--out", str(tmp_path / "o"), *args)
    assert code == 2
    assert err.count("\n") == 1 and names in err and "Traceback" not in err


def test_max_ms_constraint_and_pareto(tmp_path, capsys):
    sc = scenario_file(tmp_path)
    code, j, _ = tune(capsys, "--scenarios", str(sc), "--params", MERGE2, "--trials", "3", "--max-ms", "1e-9",
                      "--out", str(tmp_path / "a"))
    assert code == 0 and j["complete"] == 3 and j["best"]["value"] is None  # nothing is that fast
    code, j, _ = tune(capsys, "--scenarios", str(sc), "--params", MERGE2, "--trials", "3", "--max-ms", "1e6",
                      "--out", str(tmp_path / "a2"))
    assert code == 0 and j["best"]["value"] is not None  # everything is that fast
    code, j, _ = tune(capsys, "--scenarios", str(sc), "--params", MERGE2, "--trials", "4",
                      "--objective", "perception_score,endpoint_error_m", "--out", str(tmp_path / "b"))
    assert code == 0 and len(j["best"]["value"]) == 2
    assert j["best"]["value"][1] <= 0  # an error is lower-is-better: oriented, it is negated


def test_holdout_scores_default_and_best(tmp_path, capsys):
    sc = scenario_file(tmp_path, names=("hospital_2019", "restaurant_2024"))
    code, j, _ = tune(capsys, "--scenarios", str(sc), "--config", str(bad_config(tmp_path)), "--params", MERGE2,
                      "--trials", "6", "--holdout", "0.5", "--out", str(tmp_path / "o"))
    assert code == 0
    assert j["holdout"]["default"] is not None and j["holdout"]["best"] is not None


def test_local_workers_share_the_journal(tmp_path, capsys):
    code, j, _ = tune(capsys, "--scenarios", str(scenario_file(tmp_path)), "--params", MERGE2, "--trials", "6",
                      "--workers", "2", "--out", str(tmp_path / "o"))
    assert code == 0 and j["trials"] == 6
    trials = _study(tmp_path / "o", "tiny-1").trials
    assert [t.number for t in trials] == list(range(6))
    assert len({t.user_attrs["worker"].split("/")[0] for t in trials}) == 2  # two processes took part


def test_a_truth_metric_on_a_recording_without_truth_is_refused(tmp_path, capsys):
    bag = Path(__file__).parent / "data" / "recordings" / "pico_real_2019-05-07.bag"
    code, _, err = tune(capsys, "--source", f"bag:{bag}", "--trials", "2", "--out", str(tmp_path / "o"))
    assert code == 2
    assert err.count("\n") == 1 and "pico_real_2019-05-07" in err and "no ground truth for perception_score" in err
    assert not (tmp_path / "o").exists()  # refused before anything was written


def test_a_metric_no_scenario_reports_is_refused(tmp_path, capsys):
    judged = tmp_path / "judged.yaml"  # judged by its outcome: no perceptor scores
    judged.write_text('scenarios:\n  - {name: esc, world: "escape:7", behaviour: escape-room, seconds: 2}\n')
    code, _, err = tune(capsys, "--scenarios", str(judged), "--trials", "2", "--out", str(tmp_path / "o"))
    assert code == 2 and err.count("\n") == 1 and "reports perception_score" in err
