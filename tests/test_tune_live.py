"""A study in background processes, as the page's Tune tab drives it."""

from __future__ import annotations

import math
import time

from pico_studio.config import load_config
from pico_studio.tuning.backend import load_scenarios
from pico_studio.tuning.live import LiveStudy, best_so_far, top
from pico_studio.tuning.objective import parse_objective
from pico_studio.tuning.space import search_space
from pico_studio.tuning.study import StudySpec, storage_url
from tests.tune_helpers import bad_config, scenario_file


def _wait(pred, timeout=300.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if pred():
            return True
        time.sleep(0.2)
    return False


def test_a_background_study_is_watched_and_stopped(tmp_path):
    cfg = load_config(bad_config(tmp_path))
    spec = StudySpec(storage_url(None, tmp_path / "o"), "live",
                     search_space(cfg, "perception.merge.confirm_hits,perception.merge.min_length"),
                     parse_objective(None), load_scenarios(scenario_file(tmp_path)), cfg, trials=200)
    live = LiveStudy.start(spec, workers=1)
    try:
        assert _wait(lambda: sum(r.value is not None for r in live.rows()) >= 4)
        assert live.running
    finally:
        live.stop()
    assert not live.running
    rows = live.rows()
    assert all(r.state != "RUNNING" for r in rows)  # a trial cut short is failed, not left hanging
    assert 4 <= len(rows) < 200
    curve = best_so_far(rows)
    assert math.isfinite(curve[0])  # the start trial comes first
    assert all(b >= a for a, b in zip(curve, curve[1:], strict=False))
    best = top(rows, 3)
    assert best[0].value == max(r.value for r in rows if r.value is not None)
    assert live.config_of(best[0].number).perception.merge.confirm_hits == best[0].params["perception.merge.confirm_hits"]
