"""One Optuna study on disk or in a database: open it, refuse another search space, run trials.

Storage: by default an embedded journal file (`journal.log` in `--out`; no server, resumable,
shared by `--workers` local processes through its file lock); `--storage postgresql://…` (or
any SQLAlchemy URL) for a database that several machines share (`--study NAME`).

A study remembers what it searches (user attributes `space`, `params`, `objective`, `max_ms`,
`scenarios`); opening it with anything else is refused before a single write. `--trials N` is
the study's size: every worker (local or on another machine) stops when the study holds N
trials, so a resumed or shared study adds up instead of starting over. Local workers hold N
exactly (each checks the count and makes its next trial under one file lock); machines sharing
a database may each start one more when they check at the same moment. The first trial of a
new study is the start config (`--config`, else the defaults): the "default" of the report.

A trial whose config fails validation or whose run raises is recorded as failed (its error in
the user attribute `error`) and the study goes on.
"""

from __future__ import annotations

import fcntl
import hashlib
import logging
import os
import re
import socket
import time
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import optuna
from optuna.trial import FrozenTrial, TrialState

from pico_studio.config import Config
from pico_studio.errors import ConfigError
from pico_studio.tuning.backend import ScenarioSet, evaluate_scenarios
from pico_studio.tuning.objective import CONSTRAINT_ATTR, Objective
from pico_studio.tuning.space import SearchSpace

JOURNAL = "journal.log"
START_ATTR = "start"
COUNTED = (TrialState.COMPLETE, TrialState.FAIL, TrialState.PRUNED, TrialState.RUNNING)


@dataclass(frozen=True)
class StudySpec:
    """Everything a worker process needs to join the study (plain, picklable data)."""

    storage: str  # a database URL, or the path of a journal file
    study_name: str
    space: SearchSpace
    objective: Objective
    scenarios: ScenarioSet
    base: Config
    trials: int
    seed: int = 0

    @property
    def is_journal(self) -> bool:
        return "://" not in self.storage

    def attrs(self) -> dict[str, Any]:
        """What the study remembers about itself, to refuse a study of another question."""
        return {"space": self.space.fingerprint(), "params": self.space.paths,
                "objective": list(self.objective.metrics), "max_ms": self.objective.max_ms,
                "scenarios": [s.name for s in self.scenarios.scenarios]}


def storage_url(storage: str | None, out: Path) -> str:
    """The `--storage` URL as given (psycopg 3 named for postgresql://), else the journal."""
    if storage is None:
        return str(out / JOURNAL)
    if storage.startswith("postgresql://") or storage.startswith("postgres://"):
        return "postgresql+psycopg://" + storage.split("://", 1)[1]
    if "://" not in storage:
        raise ConfigError("must be a database URL such as postgresql://user@host/db "
                          "(leave it out for a journal file in --out)", field="--storage")
    return storage


def shown_url(url: str) -> str:
    """A storage URL with any password hidden, for messages."""
    return re.sub(r"(://[^:/@]+):[^@]*@", r"\1:***@", url).replace("postgresql+psycopg://", "postgresql://")


def open_storage(url: str) -> optuna.storages.BaseStorage:
    """The storage behind `url`, or a ConfigError naming it when it cannot be reached."""
    _quiet()
    if "://" not in url:
        from optuna.storages.journal import JournalFileBackend, JournalStorage

        Path(url).parent.mkdir(parents=True, exist_ok=True)
        return JournalStorage(JournalFileBackend(url))
    attempts = 4
    for attempt in range(attempts):
        try:
            # a heartbeat lets a study on several machines fail the trials of a worker that died
            return optuna.storages.RDBStorage(url, heartbeat_interval=30, grace_period=120,
                                              engine_kwargs={"pool_pre_ping": True})
        except Exception as e:  # sqlalchemy's errors name the driver, the host and the reason
            # machines starting together on an empty database race to create its tables: the
            # loser sees a unique violation (IntegrityError) or a table made meanwhile
            # (PostgreSQL's DuplicateTable, as a ProgrammingError); the tables are there now
            if _created_meanwhile(e) and attempt < attempts - 1:
                time.sleep(0.5 + attempt)
                continue
            reason = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
            raise ConfigError(f"cannot open storage {shown_url(url)}: {reason}", field="--storage") from None
    raise AssertionError("unreachable")


def _created_meanwhile(e: Exception) -> bool:
    """Did opening the storage fail because another process created its tables at the same time?"""
    text = str(e)
    return "IntegrityError" in type(e).__name__ or "DuplicateTable" in text or "already exists" in text


def _quiet() -> None:
    """Optuna's per-trial log lines and experimental-feature notes would bury the progress."""
    optuna.logging.set_verbosity(optuna.logging.ERROR)
    warnings.filterwarnings("ignore", category=optuna.exceptions.ExperimentalWarning)
    logging.getLogger("sqlalchemy").setLevel(logging.ERROR)


def open_study(spec: StudySpec, *, create: bool = True, sampler: Any = None) -> tuple[optuna.Study, bool]:
    """(the study, whether this call made it); refused if it searches another space."""
    _quiet()
    storage = open_storage(spec.storage)
    names = {s.study_name for s in optuna.get_all_study_summaries(storage, include_best_trial=False)}
    where = shown_url(spec.storage)
    if spec.study_name not in names:
        if not create:
            raise ConfigError(f"no study '{spec.study_name}' in {where}", field="--study")
        try:
            study = optuna.create_study(storage=storage, study_name=spec.study_name, sampler=sampler,
                                        directions=spec.objective.directions)
            _refuse_other(study, spec, where, fresh=True)
            return study, True
        except optuna.exceptions.DuplicatedStudyError:
            pass  # another machine made it a moment ago: join it
    study = optuna.load_study(study_name=spec.study_name, storage=storage, sampler=sampler)
    _refuse_other(study, spec, where)
    return study, False


def _refuse_other(study: optuna.Study, spec: StudySpec, where: str, *, fresh: bool = False) -> None:
    have = study.user_attrs
    want = spec.attrs()
    if not have and (fresh or not study.trials):  # a new study (or one being made by a peer)
        for k, v in want.items():
            study.set_user_attr(k, v)
        return
    # a peer that has just made the study writes its attributes one at a time: a machine that
    # joins in between sees some of them; wait (bounded) for the rest before comparing
    deadline = time.monotonic() + 30.0
    while set(want) - set(have) and time.monotonic() < deadline:
        time.sleep(0.2)
        have = study.user_attrs
    for key, what in (("space", "search space (--params)"), ("objective", "objective"),
                      ("max_ms", "--max-ms"), ("scenarios", "scenario set")):
        if have.get(key) != want[key]:
            extra = ""
            if key == "space":
                old, new = set(have.get("params", [])), set(want["params"])
                diff = sorted(old ^ new)
                extra = f" ({len(old)} vs {len(new)} parameters{', e.g. ' + diff[0] if diff else ''})"
            raise ConfigError(f"study '{spec.study_name}' in {where} has another {what}{extra}; "
                              "use another --study or --out", field="--study")


def prepare(spec: StudySpec) -> optuna.Study:
    """Open the study for a run: the start config queued when new; on a journal, trials left
    running by an interrupted run are marked failed (a journal has one run at a time)."""
    study, made = open_study(spec)
    trials = study.get_trials(deepcopy=False)
    if spec.is_journal:
        for t in trials:
            if t.state == TrialState.RUNNING:
                study.tell(t.number, state=TrialState.FAIL)
    if made:  # only the maker queues it, so machines starting together run it once
        study.enqueue_trial(spec.space.start_params(spec.base), user_attrs={START_ATTR: True})
    return study


def counted(study: optuna.Study) -> int:
    return len(study.get_trials(deepcopy=False, states=COUNTED))


def make_objective(spec: StudySpec, worker: int) -> Callable[[optuna.Trial], list[float]]:
    def objective(trial: optuna.Trial) -> list[float]:
        trial.set_user_attr("worker", f"{socket.gethostname()}:{os.getpid()}/{worker}")
        try:
            values = spec.space.suggest(trial)
            cfg = spec.space.apply(spec.base, values)
            t0 = time.perf_counter()
            result = evaluate_scenarios(spec.scenarios, cfg)
            trial.set_user_attr("seconds_wall", time.perf_counter() - t0)
            trial.set_user_attr("metrics", {k: float(v) for k, v in result.metrics.items()})
            con = spec.objective.constraint(result.metrics)
            if con is not None:  # the samplers and best_trial read it; the page reads the attribute
                trial.set_constraint("max_ms", con[0])
                trial.set_user_attr(CONSTRAINT_ATTR, con)
            return spec.objective.values(result.metrics)
        except Exception as e:
            trial.set_user_attr("error", f"{type(e).__name__}: {e}".splitlines()[0])
            raise

    return objective


def run_worker(spec: StudySpec, worker: int = 0, *, on_trial: Callable[[int], None] | None = None) -> list[int]:
    """Run trials until the study holds `spec.trials`; the numbers of the trials this ran."""
    _quiet()
    study, _ = open_study(spec, create=False)
    # a seed per worker and per start, so workers and resumed runs do not repeat each other
    seed = int(hashlib.sha256(f"{spec.seed}/{worker}/{len(study.trials)}".encode()).hexdigest()[:8], 16)
    startup = max(3, min(10, spec.trials // 4))
    study.sampler = optuna.samplers.TPESampler(seed=seed, n_startup_trials=startup, multivariate=True)
    objective = make_objective(spec, worker)
    mine: list[int] = []

    def record(study: optuna.Study, trial: FrozenTrial) -> None:
        mine.append(trial.number)
        if on_trial is not None:
            on_trial(counted(study))

    if spec.is_journal:
        # local workers: the count is checked and the next trial made under one file lock, so
        # two workers seeing N - 1 trials at once cannot both start the N-th
        while True:
            with _exclusive(Path(spec.storage + ".count.lock")):
                if counted(study) >= spec.trials:
                    break
                trial = study.ask()
            try:
                values = objective(trial)
            except Exception:
                done = study.tell(trial, state=TrialState.FAIL)
            else:
                done = study.tell(trial, values)
            record(study, done)
        return mine
    # a database several machines share: one trial per optimize() so the count is checked before
    # each (other workers add too; two machines checking at once may each start one more);
    # optimize() also runs the database heartbeat and records a raising trial as failed
    while counted(study) < spec.trials:
        study.optimize(objective, n_trials=1, catch=(Exception,), callbacks=[record])
    return mine


@contextmanager
def _exclusive(path: Path) -> Iterator[None]:
    """Hold an exclusive lock on `path` (made if missing) for the block: processes on one machine."""
    with open(path, "a") as f:
        fcntl.flock(f.fileno(), fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(f.fileno(), fcntl.LOCK_UN)


def finished(study: optuna.Study) -> list[FrozenTrial]:
    return [t for t in study.get_trials(deepcopy=False) if t.state.is_finished()]


def start_trial(study: optuna.Study) -> FrozenTrial | None:
    for t in study.get_trials(deepcopy=False):
        if t.user_attrs.get(START_ATTR) and t.state == TrialState.COMPLETE:
            return t
    return None


def best_trials(study: optuna.Study) -> list[FrozenTrial]:
    """The best feasible trial (one objective) or the feasible Pareto front (several)."""
    try:
        if len(study.directions) == 1:
            return [study.best_trial]
        return sorted(study.best_trials, key=lambda t: t.number)
    except ValueError:  # no complete (feasible) trial yet
        return []
