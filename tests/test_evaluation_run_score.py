"""`RunScore` is a running sum: adding frames one by one gives the ratios of the totals."""

from __future__ import annotations

import numpy as np
import pytest

from pico_studio.evaluation.frame_score import FrameScore
from pico_studio.evaluation.run_score import RunScore, summarise


def test_running_sum_gives_the_ratio_of_the_totals() -> None:
    rng = np.random.default_rng(0)
    frames = [FrameScore(wall_len=rng.random(), wall_len_ok=rng.random() / 2, truth_len=rng.random(),
                         truth_len_ok=rng.random() / 3, doors=int(rng.integers(0, 3)), doors_ok=1,
                         pose_err_m=rng.random(), pose_err_rad=rng.random()) for _ in range(20)]
    run = RunScore()
    for f in frames:
        run.add(f)
    assert run.count == 20 and run.last is frames[-1]
    s = run.summary()
    assert s["wall_precision"] == pytest.approx(sum(f.wall_len_ok for f in frames) / sum(f.wall_len for f in frames))
    assert s["pose_error_m"] == pytest.approx(np.mean([f.pose_err_m for f in frames]))  # the mean error
    assert s == pytest.approx(RunScore(frames).summary())
    assert summarise(frames[0], 1)["wall_recall"] == pytest.approx(frames[0].truth_len_ok / frames[0].truth_len)
    empty = RunScore().summary()
    assert empty["frames"] == 0 and empty["wall_precision"] == 1.0 and empty["endpoint_error_m"] == 0.0
