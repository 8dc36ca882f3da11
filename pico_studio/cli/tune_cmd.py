"""`pico-studio tune`: search perception parameters that score best against the truth.

    pico-studio tune --scenarios pico_studio/data/scenarios/smoke.yaml --trials 40 \\
        --params 'perception.merge.*,perception.identify.*' --out tune-hospital
    pico-studio tune --map examples/maps/hospital_2019.json --storage postgresql://u@db/optuna \\
        --study hospital --trials 400     # the same line on every machine: one study

See `pico_studio.tuning` for the search space, storage, workers and report.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from pico_studio.cli import limits
from pico_studio.cli.plugin_args import add_plugin_argument
from pico_studio.config import load_config
from pico_studio.errors import ConfigError
from pico_studio.progress import Progress
from pico_studio.tuning.space import DEFAULT_PARAMS, search_space

if TYPE_CHECKING:
    from pico_studio.tuning.backend import ScenarioSet

# Optuna and the evaluation are imported when `tune` runs, not for every other command.


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("tune", help="search parameters that score best against the truth (Optuna)")
    src = p.add_argument_group("what to tune on (a scenario set, or one map / recording)")
    src.add_argument("--scenarios", help="a scenario set YAML (e.g. pico_studio/data/scenarios/builtin.yaml)")
    src.add_argument("--map", help="one map instead of a scenario set")
    src.add_argument("--sim-config", help="the official simulator's config JSON for --map")
    src.add_argument("--source", help="one recording (bag:FILE | carmen:FILE) with its truth, "
                                      "localised on --map")
    src.add_argument("--poses", type=limits.COUNT, default=10, help="random free poses on --map (default 10)")
    p.add_argument("--config", help="the start config YAML (default: the defaults)")
    p.add_argument("--params", default=DEFAULT_PARAMS,
                   help=f"parameter globs to search, comma separated (default {DEFAULT_PARAMS})")
    p.add_argument("--objective", default=None,
                   help="metric(s) to optimise, comma separated; several give a Pareto front "
                        "(default perception_score: mean of wall, corner, door F1 and convexity)")
    p.add_argument("--max-ms", type=limits.MILLISECONDS, default=None, help="at most this perceptor CPU per scan (ms)")
    p.add_argument("--holdout", help="a scenario set YAML, or a fraction of --scenarios, kept out of the search")
    p.add_argument("--trials", type=limits.COUNT, default=50, help="trials in the study, all workers together (default 50)")
    p.add_argument("--workers", type=limits.WORKERS, default=1, help="local processes on the study (default 1)")
    p.add_argument("--storage", help="a database URL (postgresql://…) shared by several machines "
                                     "(default: a journal file in --out)")
    p.add_argument("--study", help="the study's name (default: the scenario set's)")
    p.add_argument("--seed", type=limits.SEED, default=0, help="seed of the sampler and of a fractional hold-out")
    p.add_argument("--out", default="tune-out", help="folder for best.yaml, report.html, the journal")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    add_plugin_argument(p)
    p.set_defaults(func=_tune)


def _scenarios(args: argparse.Namespace) -> ScenarioSet:
    """The scenario set to search on: --scenarios, or one built from --map / --source."""
    from pico_studio.tuning.backend import Scenario, ScenarioSet, load_scenarios

    if args.scenarios and (args.map or args.source):
        raise ConfigError("give either --scenarios or --map/--source, not both", field="--scenarios")
    if args.scenarios:
        return load_scenarios(args.scenarios)
    if args.source:  # a recording, localised on --map when one is given (its truth scores it)
        kind, _, file = args.source.partition(":")
        if kind not in ("bag", "carmen") or not file:
            raise ConfigError(f"must be bag:FILE or carmen:FILE, got {args.source!r}", field="--source")
        name = Path(file).stem
        one = Scenario(name, map=_existing(args.map, "--map"), recording=f"{kind}:{_existing(file, '--source')}",
                       localise=args.map is not None)
        return ScenarioSet(name, None, [one])
    if args.map:
        name = Path(args.map).stem
        one = Scenario(name, map=_existing(args.map, "--map"), sim_config=_existing(args.sim_config, "--sim-config"),
                       seed=args.seed, poses=args.poses)
        return ScenarioSet(name, None, [one])
    raise ConfigError("needs --scenarios FILE, --map MAP or --source bag:FILE", field="--scenarios")


def _existing(path: str | None, field: str) -> str | None:
    if path is None:
        return None
    if not Path(path).is_file():
        raise ConfigError(f"no such file: {path}", field=field)
    return str(Path(path).resolve())


def split_holdout(ss: ScenarioSet, holdout: str | None, seed: int) -> tuple[ScenarioSet, ScenarioSet | None]:
    """(search set, hold-out set) from `--holdout FILE|FRACTION`."""
    from pico_studio.tuning.backend import ScenarioSet, load_scenarios

    if holdout is None:
        return ss, None
    try:
        frac = float(holdout)
    except ValueError:
        return ss, load_scenarios(holdout)
    n = len(ss.scenarios)
    if not (0 < frac < 1) or not math.isfinite(frac):
        raise ConfigError(f"a fraction must lie between 0 and 1, got {holdout}", field="--holdout")
    k = min(n - 1, max(1, round(frac * n)))
    if n < 2:
        raise ConfigError(f"scenario set '{ss.name}' has {n} scenario: nothing to hold out", field="--holdout")
    order = np.random.default_rng(seed).permutation(n)
    kept = {int(i) for i in order[:k]}
    pick = lambda held: tuple(s for i, s in enumerate(ss.scenarios) if (i in kept) == held)  # noqa: E731
    return (ScenarioSet(ss.name, ss.path, list(pick(False))),
            ScenarioSet(f"{ss.name} (held out)", ss.path, list(pick(True))))


def _tune(args: argparse.Namespace) -> int:
    from pico_studio.tuning.objective import check_truth, parse_objective, relevant
    from pico_studio.tuning.report import summarise
    from pico_studio.tuning.study import StudySpec, prepare, shown_url, storage_url
    from pico_studio.tuning.workers import run_workers

    if args.trials < 1:
        raise ConfigError(f"must be at least 1, got {args.trials}", field="--trials")
    cfg = load_config(args.config)
    space = search_space(cfg, args.params)
    objective = parse_objective(args.objective, args.max_ms)
    search, holdout = split_holdout(_scenarios(args), args.holdout, args.seed)
    check_truth(objective, search, holdout)
    for label, ss in (("search", search), ("hold-out", holdout)):
        if ss is None:
            continue
        kept, dropped = relevant(ss, objective)
        if dropped:
            print(f"pico-studio tune: {label} set: leaving out {', '.join(dropped)} "
                  f"(they report no {', '.join(objective.metrics)})", file=sys.stderr)
        search, holdout = (kept, holdout) if label == "search" else (search, kept)
    out = Path(args.out)
    spec = StudySpec(storage_url(args.storage, out), args.study or search.name, space, objective,
                     search, cfg, args.trials, args.seed)
    t0 = time.perf_counter()
    study = prepare(spec)
    with Progress(args.trials, "tune", "trials") as progress:
        run_workers(spec, args.workers, on_progress=progress.set)
    report = summarise(study, spec, out, holdout=holdout, seconds_wall=time.perf_counter() - t0)
    if args.json:
        print(json.dumps(report.to_json()))
        return 0
    j = report.to_json()
    print(f"study '{spec.study_name}' in {shown_url(spec.storage)}: {report.trials} trials, "
          f"{report.complete} complete, {report.failed} failed ({report.seconds_wall:.0f} s)")
    print(f"  objective  {objective.describe()}; {len(space.dimensions)} parameters")
    print(f"  search     start {_fmt(j['default']['value'])} -> best {_fmt(j['best']['value'])} "
          f"(trial {report.best_number})")
    if holdout is not None:
        print(f"  hold-out   start {_fmt(j['holdout']['default'])} -> best {_fmt(j['holdout']['best'])}")
    if report.config_path:
        print(f"  config     {report.config_path}; report {out / 'report.html'}")
    for e in report.errors[:3]:
        print(f"  failed     {e}")
    return 0


def _fmt(v: object) -> str:
    if v is None:
        return "-"
    if isinstance(v, list):
        return "[" + ", ".join(f"{x:.4f}" for x in v) + "]"
    return f"{v:.4f}"
