"""What a study found: the best config as a partial YAML, the summary (`--json`), an HTML
report with Optuna's plotly figures (history, parameter importances, parallel coordinates)
and the best trial against the start config per metric, on the search and hold-out sets.

The `--json` shape (values oriented: higher is better; a list of values with several
objectives):

    {"study": NAME, "trials": N, "complete": N,
     "default": {"value": V}, "best": {"value": V, "params": {...}, "config": PATH},
     "holdout": {"default": V, "best": V}}
"""

from __future__ import annotations

import html
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import optuna
from optuna.trial import FrozenTrial, TrialState

from pico_studio.config import Config, changed_params, dump_yaml, walk
from pico_studio.config.spec import SectionInfo
from pico_studio.tuning.backend import METRICS, ScenarioSet, evaluate_scenarios
from pico_studio.tuning.objective import Objective
from pico_studio.tuning.study import StudySpec, best_trials, start_trial

BEST_YAML = "best.yaml"
REPORT_HTML = "report.html"


def partial_yaml(cfg: Config, header: str = "") -> str:
    """`dump_yaml(cfg)` cut down to the values that differ from the declared defaults (and
    the sections holding them), comments kept: a partial file that loads back as `cfg`."""
    changed = {p.path for p in changed_params(cfg)}
    keep: list[str] = [f"# {line}".rstrip() for line in header.splitlines()]
    lines = iter(dump_yaml(cfg, comments=True).splitlines())
    for item in walk(cfg):  # dump_yaml writes two lines per section (meaning, name), one per value
        own = [next(lines), next(lines)] if isinstance(item, SectionInfo) else [next(lines)]
        wanted = (any(c.startswith(item.path + ".") for c in changed) if isinstance(item, SectionInfo)
                  else item.path in changed)
        if wanted:
            keep.extend(own)
    return "\n".join(keep) + "\n"


@dataclass
class Side:
    """The start config or the best trial: its values and metrics on the search and hold-out sets."""

    values: list[float] | None
    metrics: dict[str, float]
    holdout_values: list[float] | None = None
    holdout_metrics: dict[str, float] = field(default_factory=dict)


def _one(values: list[float] | None) -> Any:
    if values is None:
        return None
    return values[0] if len(values) == 1 else values


def evaluate_holdout(objective: Objective, holdout: ScenarioSet | None, cfg: Config) -> tuple[list[float] | None, dict[str, float]]:
    if holdout is None:
        return None, {}
    m = {k: float(v) for k, v in evaluate_scenarios(holdout, cfg).metrics.items()}
    try:
        return objective.oriented(objective.values(m)), m
    except ValueError:  # the hold-out reports only other metrics (e.g. behaviour outcomes)
        return None, m


@dataclass
class TuneReport:
    study: str
    trials: int
    complete: int
    failed: int
    default: Side
    best: Side | None
    best_number: int | None
    best_params: dict[str, Any]
    config_path: str | None
    pareto: list[int]
    seconds_wall: float = 0.0
    errors: list[str] = field(default_factory=list)

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "study": self.study, "trials": self.trials, "complete": self.complete,
            "default": {"value": _one(self.default.values)},
            "best": {"value": _one(self.best.values) if self.best else None,
                     "params": self.best_params, "config": self.config_path},
            "holdout": {"default": _one(self.default.holdout_values),
                        "best": _one(self.best.holdout_values) if self.best else None},
        }
        if len(self.pareto) > 1:
            out["best"]["pareto"] = self.pareto
        return out


def summarise(study: optuna.Study, spec: StudySpec, out: Path, *, holdout: ScenarioSet | None = None,
              seconds_wall: float = 0.0) -> TuneReport:
    """Score default and best on the hold-out set, write best.yaml and report.html into `out`."""
    obj = spec.objective
    trials = study.get_trials(deepcopy=False)
    start = start_trial(study)
    start_cfg = spec.base
    default = Side(obj.oriented(start.values) if start else None,
                   dict(start.user_attrs.get("metrics", {})) if start else {})
    default.holdout_values, default.holdout_metrics = evaluate_holdout(obj, holdout, start_cfg)
    front = best_trials(study)
    best_t: FrozenTrial | None = None
    if front:  # several objectives: the front's best on the first metric stands for it
        best_t = max(front, key=lambda t: obj.oriented(t.values)[0])
    best, config_path, params = None, None, {}
    if best_t is not None:
        params = dict(best_t.params)
        cfg = spec.space.apply(spec.base, params)
        best = Side(obj.oriented(best_t.values), dict(best_t.user_attrs.get("metrics", {})))
        best.holdout_values, best.holdout_metrics = evaluate_holdout(obj, holdout, cfg)
        out.mkdir(parents=True, exist_ok=True)
        p = out / BEST_YAML
        p.write_text(partial_yaml(cfg, header=(
            f"pico-studio tune: study '{spec.study_name}', trial {best_t.number} of {len(trials)}\n"
            f"objective: {obj.describe()}\n"
            f"scenarios: {spec.scenarios.name} ({len(spec.scenarios.scenarios)})\n"
            f"load it with --config {p.name}")), encoding="utf-8")
        config_path = str(p)
    errors = _grouped([str(t.user_attrs["error"]) for t in trials if "error" in t.user_attrs])
    report = TuneReport(
        study=spec.study_name, trials=len(trials),
        complete=sum(t.state == TrialState.COMPLETE for t in trials),
        failed=sum(t.state == TrialState.FAIL for t in trials),
        default=default, best=best, best_number=best_t.number if best_t else None,
        best_params=params, config_path=config_path,
        pareto=[t.number for t in front] if len(study.directions) > 1 else [],
        seconds_wall=seconds_wall, errors=errors)
    write_html(study, spec, report, out / REPORT_HTML)
    return report


def _grouped(errors: list[str]) -> list[str]:
    """Failed trials' errors, the same error once with its count (values in brackets and
    numbers do not make an error another)."""
    counts: dict[str, int] = {}
    for e in errors:
        key = re.sub(r"\([^)]*\)", "(…)", e)
        counts[key] = counts.get(key, 0) + 1
    return [f"{k} ({n} trials)" if n > 1 else k for k, n in sorted(counts.items(), key=lambda kv: -kv[1])]


def _metric_rows(r: TuneReport) -> str:
    def cell(d: dict[str, float], k: str) -> str:
        return f"{d[k]:.4g}" if k in d else "–"

    b = r.best or Side(None, {})
    rows = []
    for k in sorted(set(r.default.metrics) | set(b.metrics)):
        arrow = "↑" if k in METRICS and METRICS[k].higher_is_better else "↓"
        rows.append(f"<tr><td>{html.escape(k)} {arrow}</td><td>{cell(r.default.metrics, k)}</td>"
                    f"<td>{cell(b.metrics, k)}</td><td>{cell(r.default.holdout_metrics, k)}</td>"
                    f"<td>{cell(b.holdout_metrics, k)}</td></tr>")
    return "\n".join(rows)


def _figures(study: optuna.Study, spec: StudySpec) -> list[tuple[str, str]]:
    """(title, html) of each figure Optuna can draw from this study (a note when it cannot)."""
    from optuna import visualization as vis

    obj = spec.objective
    name = obj.metrics[0]
    several = len(study.directions) > 1
    # several objectives: the figures follow the first; PED-ANOVA wants "low is good" then
    target = (lambda t: t.values[0]) if several else None
    low_good = (lambda t: -obj.oriented(t.values)[0]) if several else None
    kw: dict[str, Any] = {"target": target, "target_name": name} if several else {"target_name": name}
    out: list[tuple[str, str]] = []
    importances: dict[str, float] = {}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            importances = optuna.importance.get_param_importances(
                study, evaluator=optuna.importance.PedAnovaImportanceEvaluator(), target=low_good)
    except Exception as e:  # too few complete trials, or no variation
        out.append(("Parameter importances", f"<p>not available: {html.escape(str(e))}</p>"))
    makers = [("Optimisation history", lambda: vis.plot_optimization_history(study, **kw))]
    if importances:
        makers.append(("Parameter importances", lambda: vis.plot_param_importances(
            study, evaluator=optuna.importance.PedAnovaImportanceEvaluator(), target=low_good,
            target_name=name)))
        top = list(importances)[:8]
        makers.append(("Parallel coordinates (the 8 most important parameters)",
                       lambda: vis.plot_parallel_coordinate(study, params=top, **kw)))
    if len(study.directions) > 1:
        makers.append(("Pareto front", lambda: vis.plot_pareto_front(
            study, target_names=list(spec.objective.metrics))))
    first = True
    for title, make in makers:
        try:
            with warnings.catch_warnings():  # PED-ANOVA notes a target is "low is good": it is
                warnings.simplefilter("ignore", UserWarning)
                fig = make()
            out.append((title, fig.to_html(full_html=False, include_plotlyjs=first)))
            first = False
        except Exception as e:
            out.append((title, f"<p>not available: {html.escape(str(e))}</p>"))
    return out


def write_html(study: optuna.Study, spec: StudySpec, r: TuneReport, path: Path) -> Path:
    """A self-contained page (plotly.js inlined: it opens without a network)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    parts = [
        f"<h1>pico-studio tune: {html.escape(r.study)}</h1>",
        f"<p>{r.trials} trials, {r.complete} complete, {r.failed} failed; "
        f"{r.seconds_wall:.0f} s wall. Objective: {html.escape(spec.objective.describe())}. "
        f"Scenarios: {html.escape(spec.scenarios.name)} ({len(spec.scenarios.scenarios)}). "
        f"{len(spec.space.dimensions)} parameters ({html.escape(', '.join(spec.space.globs))}).</p>",
        "<h2>Best trial against the start config</h2>",
        f"<p>Best: trial {r.best_number}; config {html.escape(str(r.config_path))}</p>",
        "<table border=1 cellpadding=4><tr><th>metric</th><th>start (search)</th><th>best (search)</th>"
        "<th>start (hold-out)</th><th>best (hold-out)</th></tr>", _metric_rows(r), "</table>",
        "<h2>Best parameters</h2><pre>" + html.escape(
            "\n".join(f"{k}: {v}" for k, v in r.best_params.items())) + "</pre>",
    ]
    if r.errors:
        parts.append("<h2>Failed trials</h2><ul>" + "".join(
            f"<li>{html.escape(e)}</li>" for e in r.errors[:20]) + "</ul>")
    for title, fig in _figures(study, spec):
        parts.append(f"<h2>{html.escape(title)}</h2>{fig}")
    path.write_text("<!doctype html><meta charset=utf-8><title>pico-studio tune</title>\n"
                    + "\n".join(parts), encoding="utf-8")
    return path
