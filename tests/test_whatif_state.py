"""The page's what-if state without a browser: the studio's run re-judged on a change, A/B."""

from __future__ import annotations

import pytest

from pico_studio.config import Config, with_value
from pico_studio.errors import ConfigError
from pico_studio.json_map import load_json_map
from pico_studio.ui.runtime import Studio
from pico_studio.ui.sources import DEFAULT_MAP, make_source_factory
from pico_studio.ui.whatif import WhatIf


@pytest.fixture
def studio():  # noqa: ANN201
    s = Studio(Config(), load_json_map(DEFAULT_MAP), make_source_factory("sim", None, 2), map_name=DEFAULT_MAP.name)
    w = WhatIf(s)
    w.attach()
    for _ in range(50):
        s.tick(0.05)
    s.playing = False
    yield s, w
    w.close()


def test_a_change_re_judges_the_kept_frames_and_a_b_compares_them(studio) -> None:
    s, w = studio
    w.changed()
    assert w.wait(120)
    b = w.b.judged
    assert b is not None and len(b.times) == len(s.timeline) == 50
    assert "walls.recall" in b.totals and len(b.series["walls.recall"]) == 50
    w.pin_a()
    w.set_b(with_value(s.cfg, "perception.scan.min_length", 1.5))
    assert w.wait(120) and w.comparable
    rows = {name: (a, b_, d) for name, a, b_, d in w.table()}
    assert rows["walls.recall"][2] < 0 and rows["count.walls"][2] < 0
    diff = w.diff_at(b.times[-1])
    assert diff is not None and len(diff.walls_lost) > 0
    placed = w.overlay(b.times[-1], s.robot_pose_in_map(s.timeline.latest))
    assert placed["walls_lost"].shape == diff.walls_lost.shape
    # swap: the studio runs A's config again, the coarse one is pinned
    w.swap()
    assert s.cfg == w.b.config and w.a is not None and w.a.config.perception.scan.min_length == 1.5
    w.drop_a()
    assert w.a is None and w.table() and all(a is None for _, a, _, _ in w.table())


def test_a_bad_config_is_refused_and_nothing_judged(studio) -> None:
    import dataclasses

    s, w = studio
    cfg = s.cfg
    bad = dataclasses.replace(cfg, ui=dataclasses.replace(cfg.ui, rate_hz=-5.0))
    with pytest.raises(ConfigError, match=r"ui\.rate_hz"):
        w._judge("b", bad)
    assert w.b.judged is None


def test_a_recording_is_judged_whole_and_says_why_scores_are_absent(recordings_dir) -> None:
    spec = f"bag:{recordings_dir / 'pico_real_2019-05-07.bag'}"
    s = Studio(Config(), None, make_source_factory(spec, None), map_name="")
    w = WhatIf(s)
    w.attach()
    try:
        for _ in range(5):
            s.tick(0.05)
        w.changed()
        assert w.wait(180)
        judged = w.b.judged
        assert judged is not None and len(judged.times) == s.source.frame_count  # the whole file
        assert "count.walls" in judged.series and "walls.precision" not in judged.series
        assert any("no simulator truth" in n for n in judged.notes)
        before = w.kept_run()
        s.reset()  # a seek restarts the replay: the run stays the one read
        assert w.kept_run() is before
    finally:
        w.close()


def test_a_worker_process_killed_is_reported_and_the_next_change_re_judges(studio) -> None:
    import os
    import signal
    import time

    s, w = studio
    w.changed()
    assert w.wait(120)
    before = w.b.judged
    pids = w._workers["b"].pids
    assert pids is not None and os.getpid() not in pids  # judged in other processes
    os.kill(pids[1], signal.SIGKILL)  # the scoring process
    deadline = time.monotonic() + 30
    while "stopped" not in w.error and time.monotonic() < deadline:
        time.sleep(0.02)
    assert "re-judging B failed" in w.error and "exit code -9" in w.error
    assert w.b.judged is before  # the last whole-run judge stays shown
    s.set_param("perception.scan.min_length", 1.5)
    w.changed()
    assert w.wait(120) and w.error == ""
    from pico_studio.config import to_dict

    assert w.b.judged is not None and to_dict(w.b.judged.config) == to_dict(s.cfg)
    assert len(w.b.judged.times) == 50
