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
from typing import Literal

from pico_studio.core.behaviours.registry import DEFAULT_SECONDS, behaviour_name
from pico_studio.errors import ConfigError
from pico_studio.tuning.backend import DEFAULT_OBJECTIVE, METRICS, Scenario, ScenarioSet

MS_METRIC = "perceptor.ms_per_scan"
CONSTRAINT_ATTR = "constraint"


@dataclass(frozen=True)
class Objective:
    metrics: tuple[str, ...]
    max_ms: float | None = None

    @property
    def directions(self) -> list[Literal["minimize", "maximize"]]:
        return ["maximize" if METRICS[m].higher_is_better else "minimize" for m in self.metrics]

    def values(self, metrics: dict[str, float]) -> list[float]:
        """The raw values Optuna is told, in the order of `self.metrics`."""
        missing = [m for m in self.metrics if m not in metrics]
        if missing:
            raise ValueError(f"no scenario of the set reported {missing[0]}")
        return [float(metrics[m]) for m in self.metrics]

    def oriented(self, values: Sequence[float]) -> list[float]:
        """Values with higher = better (lower-is-better metrics negated)."""
        return [v if METRICS[m].higher_is_better else -v for m, v in zip(self.metrics, values, strict=True)]

    def constraint(self, metrics: dict[str, float]) -> list[float] | None:
        """The constraint values (feasible when <= 0; Optuna's `Trial.set_constraint`), or None
        without `--max-ms`."""
        if self.max_ms is None:
            return None
        return [float(metrics[MS_METRIC]) - self.max_ms]

    def describe(self) -> str:
        text = ", ".join(f"{m} ({'higher' if METRICS[m].higher_is_better else 'lower'} is better)"
                         for m in self.metrics)
        return text + (f", at most {self.max_ms:g} ms per scan" if self.max_ms is not None else "")


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


def gives(s: Scenario, metric: str) -> bool:
    """Whether scenario `s` can report `metric`, by the runner's methods: a behaviour that is
    judged by its outcome (`DEFAULT_SECONDS` of the registry: escape-room, room-finder,
    hospital) gives behaviour figures, not the perceptor's scores; those need the simulator's
    truth (poses or a plain scored run); localisation errors need a localised run."""
    judged = s.behaviour is not None and behaviour_name(s.behaviour) in DEFAULT_SECONDS
    if metric.startswith("localisation."):
        return s.localise
    if metric.startswith("behaviour."):
        return judged
    if not METRICS[metric].needs_truth:
        return True
    return s.recording is None and not judged


def recording_has_truth(s: Scenario) -> bool:
    from pico_studio.config import Config
    from pico_studio.sources import open_source

    assert s.recording is not None
    source = open_source(s.recording, Config().sources)
    try:
        return bool(getattr(source, "has_truth", False))
    finally:
        getattr(source, "close", lambda: None)()


def check_truth(objective: Objective, *sets: ScenarioSet | None) -> None:
    """Refuse a truth metric on a scenario without ground truth (a recording without it), and
    a metric that no scenario of the set reports."""
    for ss in (s for s in sets if s is not None):
        for m in objective.metrics:
            for s in ss.scenarios:
                no_truth = METRICS[m].needs_truth and s.recording is not None and (
                    not gives(s, m) or not recording_has_truth(s))
                if no_truth:
                    raise ConfigError(f"scenario '{s.name}' ({s.recording}) has no ground truth for {m}",
                                      file=ss.path, field="--objective")
            if not any(gives(s, m) for s in ss.scenarios):
                raise ConfigError(f"no scenario of '{ss.name}' reports {m}", file=ss.path, field="--objective")


def relevant(ss: ScenarioSet, objective: Objective) -> tuple[ScenarioSet, list[str]]:
    """The set without the scenarios that report none of the objective's metrics (a judged
    behaviour run costs minutes and adds nothing to a perception score), and their names."""
    keep = [s for s in ss.scenarios if any(gives(s, m) for m in objective.metrics)]
    dropped = [s.name for s in ss.scenarios if s not in keep]
    return ScenarioSet(ss.name, ss.path, keep), dropped
