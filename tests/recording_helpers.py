"""Shared by the pose-correction tests: the Intel lab log replayed through a perceptor."""

from __future__ import annotations

from typing import Any

from pico_studio.core.perception import Perceptor
from pico_studio.evaluation.agreement import AgreementObserver
from pico_studio.session import Session
from pico_studio.sources.carmen import open_carmen
from pico_studio.sources.replay_run import frame_steps

INTEL = "tests/data/recordings/intel-corrected.log.gz"


def intel_agreement(params: Any, scans: int) -> float:
    """`local_map.agreement` of the first `scans` scans of the Intel corrected log perceived
    with `params` (PerceptionParams), every scan judged."""
    rep = open_carmen(INTEL)
    session = Session(rep, perceptor=Perceptor(params), history=1)
    obs = AgreementObserver(every=1)
    for i, dt in enumerate(frame_steps(rep)):
        if i >= scans:
            break
        obs.on_frame(session.tick(dt))
    s = obs.summary()
    assert s["scans"] == scans
    return float(s["agreement"])
