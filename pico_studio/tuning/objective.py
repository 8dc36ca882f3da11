"""What a study optimises: one metric (the default perception score) or several (a Pareto
front), and the optional `--max-ms` constraint on perceptor CPU per scan.

Metrics are the evaluation's flat dotted names (`pico_studio.evaluation.metrics.METRICS`);
each says whether higher is better, so the study's directions follow from the names. In the
report and `--json`, values are *oriented*: higher is better (a lower-is-better metric is
negated), so "best > default" always reads as an improvement.
"""

from __future__ import annotations

import difflib
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from pico_studio.errors import ConfigError
from pico_studio.tuning.backend import METRICS, ScenarioSet, scenario_has_truth

DEFAULT_OBJECTIVE = "perception_score"
MS_METRIC = "perceptor.ms_per_scan"
CONSTRAINT_ATTR = "constraint"


@dataclass(frozen=True)
class Objective:
    metrics: tuple[str, ...]
    max_ms: float | None = None

    @property
    def directions(self) -> list[str]:
        return ["maximize" if METRICS[m].higher_is_better else "minimize" for m in self.metrics]

    def values(self, metrics: dict[str, float]) -> list[float]:
        """The raw values Optuna is told, in the order of `self.metrics`."""
        return [float(metrics[m]) for m in self.metrics]

    def oriented(self, values: Sequence[float]) -> list[float]:
        """Values with higher = better (lower-is-better metrics negated)."""
        return [v if METRICS[m].higher_is_better else -v for m, v in zip(self.metrics, values, strict=True)]

    def constraint(self, metrics: dict[str, float]) -> list[float] | None:
        """Optuna's constraint values (feasible when <= 0), or None without `--max-ms`."""
        if self.max_ms is None:
            return None
        return [float(metrics[MS_METRIC]) - self.max_ms]

    def describe(self) -> str:
        text = ", ".join(f"{m} ({'higher' if METRICS[m].higher_is_better else 'lower'} is better)"
                         for m in self.metrics)
        return text + (f", at most {self.max_ms:g} ms per scan" if self.max_ms is not None else "")


def constraints_func(trial: Any) -> Sequence[float]:
    """For Optuna's samplers: the constraint stored with the trial (module level, so it
    pickles into worker processes)."""
    return tuple(trial.user_attrs.get(CONSTRAINT_ATTR, (0.0,)))


def parse_objective(text: str | None, max_ms: float | None = None) -> Objective:
    names = tuple(n.strip() for n in (text or DEFAULT_OBJECTIVE).split(",") if n.strip())
    if not names:
        raise ConfigError("needs at least one metric", field="--objective")
    for n in names:
        if n not in METRICS:
            close = difflib.get_close_matches(n, list(METRICS), n=1, cutoff=0.5)
            hint = f"; did you mean '{close[0]}'?" if close else f"; known: {', '.join(sorted(METRICS))}"
            raise ConfigError(f"unknown metric '{n}'{hint}", field="--objective")
    if len(set(names)) != len(names):
        raise ConfigError("names a metric twice", field="--objective")
    if max_ms is not None and not (max_ms > 0):
        raise ConfigError(f"must be a positive number of ms, got {max_ms}", field="--max-ms")
    return Objective(names, max_ms)


def check_truth(objective: Objective, *sets: ScenarioSet | None) -> None:
    """Refuse a truth metric on a scenario that has no ground truth (a recording without it)."""
    truth_metrics = [m for m in objective.metrics if METRICS[m].needs_truth]
    if not truth_metrics:
        return
    for ss in sets:
        for s in ss.scenarios if ss is not None else ():
            if not scenario_has_truth(s):
                raise ConfigError(f"scenario '{s.name}' has no ground truth for {truth_metrics[0]}",
                                  file=ss.path, field=f"{s.name}")
