"""The evaluation a trial runs, in one place: scenario sets, metrics and the runner of the
evaluation package (`pico_studio.evaluation`). A trial is `evaluate_scenarios(set, cfg)`;
its value is the mean of a metric over the scenarios that report it."""

from __future__ import annotations

from pico_studio.evaluation.metrics import DEFAULT_OBJECTIVE, METRICS, Metric
from pico_studio.evaluation.runner import (
           ScenarioResult,
           SetResult,
           evaluate_scenario,
           evaluate_scenarios,
)
from pico_studio.evaluation.scenarios import Scenario, ScenarioSet, load_scenarios

__all__ = ["DEFAULT_OBJECTIVE", "METRICS", "Metric", "Scenario", "ScenarioResult", "ScenarioSet", "SetResult",
           "evaluate_scenario", "evaluate_scenarios", "load_scenarios"]
