"""Re-judging a kept run with another config: series per frame, totals, the background worker
(a thread in this process, or two worker processes: the same answers)."""

from __future__ import annotations

import dataclasses
import math
import os
import signal
import threading

import numpy as np
import pytest

from pico_studio.config import Config, to_dict, with_value
from pico_studio.core.behaviours.wander import Wander
from pico_studio.core.perception import Perceptor
from pico_studio.errors import ConfigError
from pico_studio.evaluation.rejudge import (
    SERIES,
    KeptRun,
    Rejudger,
    record_replay,
    record_sim,
    rejudge,
)
from pico_studio.evaluation.rejudge_worker import ProcessRejudger, WorkerDied
from pico_studio.evaluation.run_score import TruthScorer
from pico_studio.json_map import load_json_map
from pico_studio.session import Session
from pico_studio.sim import Simulator
from pico_studio.sources import open_source

CFG = Config()
START = (3.5, 0.6, math.pi / 2)
COARSE = with_value(CFG, "perception.scan.min_length", 1.5)


@pytest.fixture(scope="module")
def run(request) -> KeptRun:  # noqa: ANN001
    gmap = load_json_map(request.config.rootpath / "pico_studio/data/maps/hospital_2019.json")
    sim = Simulator(gmap, CFG.sim, seed=1, initial_pose=START)
    return record_sim(sim, CFG, Wander(CFG.ui.wander), seconds=4.0, localise=True)


def test_the_same_config_judges_the_kept_frames_as_the_live_run_was_judged(maps_dir, run) -> None:
    gmap = load_json_map(maps_dir / "hospital_2019.json")
    sim = Simulator(gmap, CFG.sim, seed=1, initial_pose=START)
    live = TruthScorer(sim)
    Session(sim, perceptor=Perceptor(CFG.perception), behaviour=Wander(CFG.ui.wander), observers=[live]).run(4.0)
    judged = rejudge(run.__class__(run.frames, run.truth, run.vertices), CFG)  # no map: perception only
    s = live.summary()
    assert len(judged.times) == run.scans == s["frames"] == 80
    assert judged.totals["walls.precision"] == s["wall_precision"]
    assert judged.totals["doors.recall"] == s["door_recall"]
    assert judged.totals["corners.recall"] == s["corner_recall"]


def test_series_cover_every_scan_and_a_coarser_config_loses_walls(run) -> None:
    a, b = rejudge(run, CFG), rejudge(run, COARSE)
    n = run.scans
    for name in ("walls.precision", "walls.recall", "doors.recall", "count.walls", "count.doors",
                 "localisation.quality", "localisation.lost", "localisation.error_m", "ms.total"):
        assert len(a.series[name]) == n, name
        assert name in SERIES or name.startswith("ms."), name
    assert np.all(np.diff(a.times) > 0) and len(a.features) == n
    assert a.totals["localisation.pose_error_m.median"] < 0.1
    assert b.totals["walls.recall"] < a.totals["walls.recall"] - 0.05
    assert np.nanmean(b.series["count.walls"]) < np.nanmean(a.series["count.walls"])
    # the sensor stream is the same: the times and frames judged are too
    np.testing.assert_array_equal(a.times, b.times)
    np.testing.assert_array_equal(a.frame_index, b.frame_index)


def test_an_invalid_config_is_refused_naming_the_field_and_nothing_is_judged(run) -> None:
    bad = dataclasses.replace(CFG, perception=dataclasses.replace(
        CFG.perception, scan=dataclasses.replace(CFG.perception.scan, min_length=-1.0)))
    with pytest.raises(ConfigError, match=r"perception\.scan\.min_length"):
        rejudge(run, bad)
    for kind in (Rejudger, ProcessRejudger):
        results: list = []
        worker = kind(run, on_result=results.append)
        try:
            with pytest.raises(ConfigError, match=r"perception\.scan\.min_length"):
                worker.submit(bad)
            assert worker.generation == 0 and worker.wait(timeout=0.2) is None and results == [], kind
        finally:
            worker.close()


def assert_same_judgement(got, want) -> None:  # noqa: ANN001
    """Two re-judges of one run with one config: every figure equal (timings aside)."""
    np.testing.assert_array_equal(got.times, want.times)
    np.testing.assert_array_equal(got.frame_index, want.frame_index)
    assert sorted(got.series) == sorted(want.series)
    for name, col in want.series.items():
        if not name.startswith("ms."):
            np.testing.assert_array_equal(got.series[name], col, err_msg=name)
    timing = ("perceptor.ms_per_scan",)
    assert {k: v for k, v in got.totals.items() if k not in timing} == {
        k: v for k, v in want.totals.items() if k not in timing}
    assert got.notes == want.notes and len(got.features) == len(want.features) == len(want.times)
    for a, b in zip(got.features, want.features, strict=True):
        assert sorted(a) == sorted(b) and all(np.array_equal(a[k], b[k]) for k in a)


def test_worker_processes_judge_exactly_as_this_process_does(run, recordings_dir) -> None:
    # localised on the map (the scorer process localises beside the perceiving one), coarse too
    worker = ProcessRejudger(run)
    try:
        for cfg in (CFG, COARSE):
            judged = worker.wait(worker.submit(cfg), timeout=120)
            # the config judged, as a tree (a plugin area's class is rebuilt as plugins come and go)
            assert judged is not None and judged.complete and to_dict(judged.config) == to_dict(cfg)
            assert_same_judgement(judged, rejudge(run, cfg))
    finally:
        worker.close()
    # a recording with true poses: the agreement series, judged from the scans sent across
    replay = open_source(f"carmen:{recordings_dir / 'intel-corrected.log.gz'}", CFG.sources)
    recording = record_replay(replay, seconds=2.0)
    assert_same_judgement(rejudge(recording, CFG, workers=2), rejudge(recording, CFG))


@pytest.mark.parametrize("kind", [Rejudger, ProcessRejudger])
def test_a_change_mid_rejudge_cancels_it_and_old_and_new_never_mix(run, kind) -> None:  # noqa: ANN001
    results: list = []
    progress: list[tuple[int, int, int]] = []
    started = threading.Event()

    def on_progress(gen: int, done: int, total: int) -> None:
        progress.append((gen, done, total))
        started.set()

    worker = kind(run, on_result=results.append, on_progress=on_progress)
    worker.progress_every = 1
    try:
        g1 = worker.submit(CFG)
        assert started.wait(60)
        g2 = worker.submit(COARSE)  # arrives while the first is under way
        judged = worker.wait(g2, timeout=120)
        assert judged is not None and judged.generation == g2 > g1
        # the first was overtaken mid-run: only the second is delivered, whole and its own
        assert [r.generation for r in results] == [g2]
        direct = rejudge(run, COARSE)
        assert judged.totals == {**direct.totals, "perceptor.ms_per_scan": judged.totals["perceptor.ms_per_scan"]}
        for name, col in direct.series.items():
            if not name.startswith("ms."):
                np.testing.assert_array_equal(judged.series[name], col)
        assert progress and progress[-1] == (g2, len(run.frames), len(run.frames))
        assert all(gen in (g1, g2) for gen, _, _ in progress)
    finally:
        worker.close()


def test_a_worker_process_that_dies_is_reported_and_the_next_change_re_judges(run) -> None:
    errors: list[tuple[int, Exception]] = []
    died = threading.Event()

    def on_error(gen: int, e: Exception) -> None:
        errors.append((gen, e))
        died.set()

    def kill(gen: int, done: int, total: int) -> None:
        if not died.is_set() and worker.pids is not None:
            os.kill(worker.pids[0], signal.SIGKILL)  # the perceiving process, mid-re-judge

    worker = ProcessRejudger(run, on_error=on_error, on_progress=kill)
    worker.progress_every = 1
    try:
        g1 = worker.submit(CFG)
        assert died.wait(60)
        gen, e = errors[0]
        assert gen == g1 and isinstance(e, WorkerDied) and "exit code -9" in str(e)
        assert worker.pids is None and not worker.running
        worker.on_progress = None
        judged = worker.wait(worker.submit(COARSE), timeout=120)  # new processes, the run sent again
        assert judged is not None and judged.generation == g1 + 1
        assert_same_judgement(judged, rejudge(run, COARSE))
        assert len(errors) == 1
    finally:
        worker.close()


def test_a_recording_without_truth_gives_counts_and_says_why_scores_are_absent(recordings_dir) -> None:
    replay = open_source(f"bag:{recordings_dir / 'pico_real_2019-05-07.bag'}", CFG.sources)
    run = record_replay(replay, seconds=3.0)
    judged = rejudge(run, CFG)
    assert len(judged.times) == run.scans > 20
    assert "walls.precision" not in judged.series and "walls.precision" not in judged.totals
    assert judged.totals["count.walls"] > 0 and len(judged.series["count.walls"]) == run.scans
    assert any("no simulator truth" in n for n in judged.notes)


def test_a_recording_with_true_poses_gets_the_agreement_and_the_pose_error(recordings_dir) -> None:
    replay = open_source(f"carmen:{recordings_dir / 'intel-corrected.log.gz'}", CFG.sources)
    run = record_replay(replay, seconds=4.0)
    judged = rejudge(run, CFG)
    agreement = judged.series["local_map.agreement"]
    assert len(agreement) == run.scans and np.nanmin(agreement) >= 0.0 and np.nanmax(agreement) <= 1.0
    assert 0.0 <= judged.totals["local_map.agreement"] <= 1.0
    assert "walls.precision" not in judged.totals


def test_partial_results_grow_frame_by_frame_and_end_in_the_whole_run(run) -> None:
    seen: list = []
    whole = rejudge(run, CFG, partial=seen.append, partial_seconds=0.0)
    assert whole.complete and len(seen) >= run.scans - 1
    lengths = [len(j.times) for j in seen]
    assert lengths == sorted(lengths) and not any(j.complete or j.totals for j in seen)
    last = seen[-1]
    np.testing.assert_array_equal(last.series["count.walls"], whole.series["count.walls"][: len(last.times)])


def test_a_plugin_stage_selected_by_the_config_is_judged_in_the_workers_too(run) -> None:
    from plugin_helpers import EXAMPLE, unload_all

    from pico_studio import plugins
    from pico_studio.config import merge_yaml

    unload_all()
    try:
        plugins.load_plugin(str(EXAMPLE))  # loaded here after the test's imports: the workers load it too
        cfg = merge_yaml(Config(), (EXAMPLE.parent / "use_my_stages.yaml").read_text(encoding="utf-8")).config
        assert cfg.perception.scan.segmenter == "chord_split"
        assert_same_judgement(rejudge(run, cfg, workers=2), rejudge(run, cfg))
    finally:
        unload_all()


def test_a_timeline_that_grows_and_slides_on_sends_only_its_new_frames(maps_dir) -> None:
    from pico_studio.evaluation.rejudge import RunKeeper

    gmap = load_json_map(maps_dir / "hospital_2019.json")
    sim = Simulator(gmap, CFG.sim, seed=2, initial_pose=START)
    keeper = RunKeeper(sim, max_frames=50)  # the page's timeline, shorter
    session = Session(sim, behaviour=Wander(CFG.ui.wander), observers=[keeper])
    worker = ProcessRejudger(KeptRun([]))
    try:
        first = []
        for seconds, frames in ((1.5, 30), (1.0, 50), (1.5, 50)):  # grown, then slid on: 30 gone
            session.run(seconds)
            run = keeper.kept(gmap)
            first.append(run.frames[0].time)
            assert len(run.frames) == frames
            worker.set_run(run)
            judged = worker.wait(worker.submit(COARSE), timeout=120)
            assert judged is not None and len(judged.times) == run.scans
            assert_same_judgement(judged, rejudge(run, COARSE))
        assert first[0] == first[1] < first[2] and worker.sent == {"whole": 1, "extend": 2}
    finally:
        worker.close()
