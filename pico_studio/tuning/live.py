"""A study running in background processes, seen from outside (the page's Tune tab):
the trials as rows, the best value so far, the top trials, and the config of any of them.

    live = LiveStudy.start(spec, workers=2)
    rows = live.rows()                  # every trial so far, oriented values (higher is better)
    best_so_far(rows); top(rows, 5); live.config_of(rows[3].number); live.stop()
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import optuna
from optuna.trial import TrialState

from pico_studio.config import Config
from pico_studio.tuning.study import StudySpec, open_study, prepare
from pico_studio.tuning.workers import Workers


@dataclass(frozen=True)
class TrialRow:
    number: int
    state: str  # "COMPLETE" | "FAIL" | "RUNNING" | ...
    value: float | None  # the first objective, oriented (higher is better); None unless complete
    params: dict[str, Any]
    error: str | None = None
    feasible: bool = True  # within --max-ms


def trial_rows(study: optuna.Study, spec: StudySpec) -> list[TrialRow]:
    out = []
    for t in study.get_trials(deepcopy=False):
        value = spec.objective.oriented(t.values)[0] if t.state == TrialState.COMPLETE and t.values else None
        con = t.user_attrs.get("constraint")
        out.append(TrialRow(t.number, t.state.name, value, dict(t.params), t.user_attrs.get("error"),
                            feasible=con is None or all(c <= 0 for c in con)))
    return out


def best_so_far(rows: list[TrialRow]) -> list[float]:
    """After each trial (by number), the best feasible value yet (NaN before the first)."""
    best, out = -math.inf, []
    for r in sorted(rows, key=lambda r: r.number):
        if r.value is not None and r.feasible:
            best = max(best, r.value)
        out.append(best if best > -math.inf else math.nan)
    return out


def top(rows: list[TrialRow], k: int = 5) -> list[TrialRow]:
    done = [r for r in rows if r.value is not None and r.feasible]
    return sorted(done, key=lambda r: (-(r.value or 0.0), r.number))[:k]


class LiveStudy:
    """A study and the worker processes filling it."""

    def __init__(self, spec: StudySpec, workers: Workers | None):
        self.spec = spec
        self.workers = workers
        self.study, _ = open_study(spec, create=False)

    @classmethod
    def start(cls, spec: StudySpec, workers: int = 1) -> LiveStudy:
        prepare(spec)
        return cls(spec, Workers(spec, max(1, workers)))

    @property
    def running(self) -> bool:
        return self.workers is not None and not self.workers.done()

    @property
    def error(self) -> str | None:
        """Why a worker process ended early, if one did."""
        return self.workers.error() if self.workers is not None else None

    def rows(self) -> list[TrialRow]:
        return trial_rows(self.study, self.spec)

    def config_of(self, number: int) -> Config:
        """The config of trial `number` (the start config with its values)."""
        return self.spec.space.apply(self.spec.base, dict(self.study.trials[number].params))

    def stop(self) -> None:
        """End the workers (a trial they were running is marked failed, nothing else lost)."""
        if self.workers is not None:
            self.workers.stop()
            self.workers = None
        for t in self.study.get_trials(deepcopy=False, states=(TrialState.RUNNING,)):
            self.study.tell(t.number, state=TrialState.FAIL, skip_if_finished=True)
