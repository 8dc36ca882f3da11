"""The one loop's frames and its observers: recorder, progress, truth and pose scorers,
judges, and re-judging kept frames through the same loop (`FramesReplay`)."""

from __future__ import annotations

import io
import math

import numpy as np
import pytest
from sim_helpers import box_map

from pico_studio.config.tree import Config
from pico_studio.core.behaviours.registry import Drive
from pico_studio.core.io import Command, Frame
from pico_studio.core.localisation import Localiser
from pico_studio.core.localisation.stage import LocalisingPerceptor
from pico_studio.core.perception import Perceptor
from pico_studio.evaluation.frame_score import score_frame
from pico_studio.evaluation.judges import CabinetsVisited, EscapeJudge, RoomsCounted
from pico_studio.evaluation.run_score import PoseErrorScorer, RunScore, TruthScorer
from pico_studio.evaluation.worlds import escape_world
from pico_studio.json_map import load_json_map
from pico_studio.progress import Progress, ProgressObserver
from pico_studio.session import FrameKeeper, RecorderObserver, Session, SessionFrame
from pico_studio.sim import Simulator
from pico_studio.sources.frames import FramesReplay

CFG = Config()


class ListRecorder:
    def __init__(self) -> None:
        self.rows: list[tuple[Frame, Command | None]] = []
        self.counts = {"rows": 0}

    def record(self, frame: Frame, command: Command | None) -> None:
        self.rows.append((frame, command))
        self.counts["rows"] += 1


def test_frames_stop_at_until_with_the_last_tick_shortened() -> None:
    sim = Simulator(box_map(), initial_pose=(5, 5, 0))
    got = list(Session(sim).frames(until=1.0, dt=0.3))
    assert [round(sf.frame.time, 9) for sf in got] == [0.3, 0.6, 0.9, 1.0]
    assert [sf.index for sf in got] == [0, 1, 2, 3]
    assert list(Session(sim).frames(until=1.0)) == []  # already there


def test_frames_stop_when_the_source_is_no_longer_ok() -> None:
    sim = Simulator(box_map(), initial_pose=(5, 5, 0))
    session = Session(sim)
    n = 0
    for sf in session.frames():  # no `until`: as long as the source runs
        n += 1
        if sf.index == 6:
            sim.close()
    assert n == 7 and not sim.ok()


def test_recorder_is_an_observer_and_can_be_switched_on_and_off() -> None:
    sim = Simulator(box_map(), initial_pose=(5, 5, 0))
    rec, keep = ListRecorder(), FrameKeeper()
    session = Session(sim, behaviour=Drive(0.1, 0, 0), recorder=rec, observers=[keep])
    session.run(0.5, 0.05)
    assert len(rec.rows) == len(keep.frames) == 10 and rec.rows[0][1] == Command(0.1, 0.0, 0.0)
    assert session.recorder is rec
    session.recorder = None
    session.run(0.5, 0.05)
    assert len(rec.rows) == 10 and len(keep.frames) == 20
    assert session.summaries()["keep"] == {"frames": 20}
    assert RecorderObserver(rec).summary() == {"file": None, "messages": {"rows": 10}}


def test_progress_observer_follows_the_source_clock() -> None:
    sim = Simulator(box_map(), initial_pose=(5, 5, 0))
    progress = Progress(2.0, "sim", "s", stream=io.StringIO())
    watch = ProgressObserver(progress, sim.now())
    Session(sim, observers=[watch]).run(1.5, 0.05)
    assert progress.done == pytest.approx(1.5) and watch.summary()["frames"] == 30
    counting = ProgressObserver(Progress(10, "n", stream=io.StringIO()), count=True)
    Session(sim, observers=[counting]).run(0.25, 0.05)
    assert counting.progress.done == 5


def test_truth_scorer_scores_every_new_world_model_like_score_frame() -> None:
    sim = Simulator(box_map(), initial_pose=(3, 4, 0.3))
    keep = FrameKeeper()
    scorer = TruthScorer(sim)
    halves = TruthScorer(sim, every=2)

    class Check:  # scoring each frame by hand, at the same moment
        def __init__(self) -> None:
            self.run = RunScore()

        def on_frame(self, sf: SessionFrame) -> None:
            self.run.add(score_frame(sf.world_model, sim.truth, true_zero=scorer.true_zero or _zero(sf, sim),
                                     true_vertices=scorer.vertices))

        def summary(self) -> dict:
            return self.run.summary()

    check = Check()
    Session(sim, perceptor=Perceptor(CFG.perception), behaviour=Drive(0.2, 0, 0.2),
            observers=[scorer, halves, check, keep]).run(2.0, 0.05)
    s = scorer.summary()
    assert s["frames"] == 40 and halves.summary()["frames"] == 20
    assert s["wall_precision"] > 0.9 and s["wall_recall"] > 0.8 and s["ms_per_scan"] > 0
    assert s == pytest.approx(check.summary() | {"ms_per_scan": s["ms_per_scan"]})


def _zero(sf: SessionFrame, sim: Simulator):  # noqa: ANN202
    from pico_studio.evaluation.frame_score import true_zero_pose

    return true_zero_pose(sf.world_model, sim)


def _localising(gmap, start):  # noqa: ANN001, ANN202
    return LocalisingPerceptor(Perceptor(CFG.perception), Localiser(CFG.localisation, gmap, start))


def test_pose_error_scorer_and_re_judging_the_kept_frames_gives_the_same_figures(maps_dir) -> None:
    gmap = load_json_map(maps_dir / "hospital_2019.json")
    start = (3.5, 0.6, math.pi / 2)
    sim = Simulator(gmap, CFG.sim, seed=0, initial_pose=start)
    keep, live_error = FrameKeeper(), PoseErrorScorer()
    live = Session(sim, perceptor=_localising(gmap, start), behaviour=Drive(0.1, 0.0, 0.3),
                   observers=[keep, live_error])
    live.run(2.0, 0.05)
    s = live_error.summary()
    assert s["frames"] == 40 and s["pose_error_m"]["max"] < 0.05
    # the same sensor stream, judged again through the same loop with the same config
    replay = FramesReplay([sf.frame for sf in keep.frames])
    again_keep, again_error = FrameKeeper(), PoseErrorScorer()
    again = Session(replay, perceptor=_localising(gmap, start), behaviour=Drive(0.1, 0.0, 0.3),
                    observers=[again_keep, again_error])
    assert again.run(math.inf) == len(keep.frames) and not replay.ok()
    assert again_error.summary() == live_error.summary()
    for a, b in zip(keep.frames, again_keep.frames, strict=True):
        assert a.frame.time == b.frame.time and a.frame.truth == b.frame.truth and a.command == b.command
        np.testing.assert_array_equal(a.world_model.local_map.walls, b.world_model.local_map.walls)
        assert a.world_model.global_pose == b.world_model.global_pose
    assert replay.sent[0] == (0.1, 0.0, 0.3)


def test_escape_judge_watches_the_frames_truth() -> None:
    w = escape_world(3)
    f = w.map.finish_segments[0]
    mid = (f[:2] + f[2:]) / 2
    inner = mid - (mid - np.array([2.0, 2.0])) * 0.05
    judge = EscapeJudge(w.map, start=10.0, pose=tuple(inner))
    for t, xy in ((11.0, inner), (12.5, mid + (mid - inner))):
        frame = Frame(laser=None, odometry=None, time=t, truth={"pose": (*xy, 0.0)})
        judge.on_frame(SessionFrame(0, frame, None, None))
    assert judge.summary() == {"escaped": True, "escape_seconds": 2.5}


class Reported:
    """A behaviour's own report, as `result()` gives it."""

    def __init__(self, **result: object) -> None:
        self._result = result

    def result(self) -> dict[str, object]:
        return dict(self._result)


def test_cabinet_and_room_judges_read_the_behaviour_and_compare() -> None:
    b = Reported(cabinets_visited=[1, 4], rooms=[{"objects": 2, "edges": 5}, {"objects": 1, "edges": 4}])
    assert CabinetsVisited(b).summary() == {"cabinets_visited": [1, 4]}
    assert CabinetsVisited(b, expected=[1, 4]).summary()["cabinets_right"]
    assert not CabinetsVisited(b, expected=[4, 1]).summary()["cabinets_right"]
    assert RoomsCounted(b, expected=[1, 2]).summary()["rooms_right"]  # the same rooms, another start
    assert not RoomsCounted(b, expected=[2, 2]).summary()["rooms_right"]
    assert "rooms_right" not in RoomsCounted(b).summary()


def test_kept_truth_scores_the_replayed_frames_as_the_live_run_was_scored(maps_dir) -> None:
    from pico_studio.config import with_value
    from pico_studio.evaluation.kept_truth import TruthKeeper

    gmap = load_json_map(maps_dir / "hospital_2019.json")
    sim = Simulator(gmap, CFG.sim, seed=2, initial_pose=(3.5, 0.6, math.pi / 2))
    keep, keeper, live_score = FrameKeeper(), TruthKeeper(sim), TruthScorer(sim)
    Session(sim, perceptor=Perceptor(CFG.perception), behaviour=Drive(0.15, 0.0, 0.25),
            observers=[keep, keeper, live_score]).run(2.0, 0.05)

    def rejudge(perception) -> dict:  # noqa: ANN001
        replay = FramesReplay([sf.frame for sf in keep.frames])
        scorer = TruthScorer(lambda: keeper.at(replay.index), vertices=keeper.vertices)
        Session(replay, perceptor=Perceptor(perception), observers=[scorer]).run(math.inf)
        return scorer.summary()

    def figures(s: dict) -> dict:
        return {k: v for k, v in s.items() if k != "ms_per_scan"}

    live = figures(live_score.summary())
    assert live["frames"] == 40 and keeper.summary() == {"frames": 40}
    assert figures(rejudge(CFG.perception)) == live
    coarse = with_value(CFG, "perception.scan.min_length", 1.5).perception
    assert figures(rejudge(coarse))["wall_recall"] < live["wall_recall"] - 0.05
