"""Two configs judged on the same sensor data: their whole-run figures side by side, what B's
world model adds and loses against A's, and which figures B makes worse.

    runs = [record_sim(sim, cfg_a, Wander(cfg_a.ui.wander), seconds=60)]   # the drive, once
    c = compare_runs(runs, cfg_a, cfg_b, workers=2)
    c.as_dict(fail_on=["doors.f1"], tolerance=0.01)
    # {"frames": N, "metrics": {name: {"a", "b", "delta"}}, "diff": {"walls_added", ...},
    #  "regressed": [names], ...}

The sensor data of each run is recorded once (`rejudge.KeptRun`), so the comparison is about
what perception and localisation make of it, not about a different drive. Metrics are the
whole-run totals of `rejudge` (`metrics.METRICS` names, plus `local_map.agreement` and the
mean counts), averaged over the runs that report each (as `eval --scenarios` does); timings
are reported beside them (`ms_per_scan`), never compared, so A vs A has every delta 0.

**diff**: per frame, B's world model against A's (`diff.diff_world_models`), at the end of
each run (the local map built over the whole drive), summed over the runs;
`frames_differing` counts the frames where any feature was added or lost.
"""

from __future__ import annotations

import difflib
import math
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from typing import Any

from pico_studio.config import Config
from pico_studio.errors import UserError
from pico_studio.evaluation.diff import KINDS, SAME, DiffTolerances, diff_arrays
from pico_studio.evaluation.metrics import METRICS
from pico_studio.evaluation.rejudge import (
    Judged,
    KeptRun,
    higher_is_better,
    record_replay,
    record_sim,
    rejudge,
)
from pico_studio.evaluation.runner import mean_metrics
from pico_studio.evaluation.scenarios import Scenario, ScenarioSet

DIFF_KEYS = tuple(f"{k}_{w}" for k in KINDS for w in ("added", "lost"))
TIMINGS = ("perceptor.ms_per_scan",)  # reported, never compared: they differ run to run


@dataclass
class Comparison:
    frames: int
    a: dict[str, float]  # whole-run metrics of A (mean over the runs having each)
    b: dict[str, float]
    diff: dict[str, int]  # DIFF_KEYS -> count at the end of the runs, summed over the runs
    frames_differing: int = 0
    ms_per_scan: dict[str, float | None] = field(default_factory=dict)  # {"a", "b"}, None: not timed
    notes: list[str] = field(default_factory=list)

    def metrics(self) -> dict[str, dict[str, float]]:
        """{name: {"a": x, "b": y, "delta": y - x}} for the metrics both configs report."""
        names = [n for n in self.a if n in self.b]
        return {n: {"a": self.a[n], "b": self.b[n], "delta": self.b[n] - self.a[n]} for n in names}

    def regressed(self, names: list[str], tolerance: float = 0.0) -> list[str]:
        """The metrics of `names` on which B is worse than A by more than `tolerance`
        (lower where higher is better, higher where lower is better). An unknown name, or
        one this comparison did not measure, is a `UserError` on `--fail-on`."""
        both = self.metrics()
        out = []
        for name in names:
            if name not in both:
                known = sorted(set(METRICS) | set(both))
                if name in known:
                    why = "not measured on these runs" + ("" if METRICS.get(name) is None or not METRICS[name].needs_truth
                                                          else " (it needs the simulator's truth)")
                    raise UserError(f"{name}: {why}; measured: {', '.join(sorted(both))}", field="--fail-on")
                close = difflib.get_close_matches(name, known, n=1, cutoff=0.5)
                hint = f"; did you mean '{close[0]}'?" if close else f"; known: {', '.join(sorted(both))}"
                raise UserError(f"unknown metric {name!r}{hint}", field="--fail-on")
            d = both[name]["delta"]
            worse = -d if higher_is_better(name) else d
            if worse > tolerance:
                out.append(name)
        return out

    def as_dict(self, fail_on: list[str] | None = None, tolerance: float = 0.0) -> dict[str, Any]:
        """The `compare --json` object."""
        return {
            "frames": self.frames,
            "metrics": self.metrics(),
            "diff": dict(self.diff),
            "regressed": self.regressed(fail_on or [], tolerance),
            "frames_differing": self.frames_differing,
            "ms_per_scan": dict(self.ms_per_scan),
            "notes": list(self.notes),
        }


def run_diff(a: Judged, b: Judged, tol: DiffTolerances = SAME) -> tuple[dict[str, int], int]:
    """(B vs A at the run's last frame, the number of frames where B differs from A)."""
    last = {k: 0 for k in DIFF_KEYS}
    differing = 0
    n = min(len(a.features), len(b.features))
    for i in range(n):
        d = diff_arrays(a.features[i], b.features[i], tol)
        if not d.empty:
            differing += 1
        if i == n - 1:
            last = d.counts()
    return last, differing


def _judge_pair(run: KeptRun, cfg_a: Config, cfg_b: Config, pool: ProcessPoolExecutor | None,
                pipelines: tuple[Any, Any] | None = None) -> tuple[Judged, Judged]:
    if pipelines is not None:  # A and B each perceived in one process and scored in another
        wa, wb = pipelines
        wa.set_run(run)
        wb.set_run(run)
        ga, gb = wa.submit(cfg_a), wb.submit(cfg_b)
        return wa.result(ga), wb.result(gb)
    if pool is None:
        return rejudge(run, cfg_a), rejudge(run, cfg_b)
    fa = pool.submit(rejudge, run, cfg_a)
    jb = rejudge(run, cfg_b)  # the other core meanwhile
    return fa.result(), jb


def compare_runs(runs: list[KeptRun], cfg_a: Config, cfg_b: Config, *, workers: int = 1,
                 extra: list[tuple[dict[str, float], dict[str, float], int]] | None = None) -> Comparison:
    """A and B re-judged on every kept run: one after the other here (`workers` 1), A in a
    second process meanwhile (2, 3), or each in a pair of worker processes, perceiving in one
    and localising + scoring in the other (4 or more: `rejudge_worker.ProcessRejudger`). The
    same figures whichever.

    `extra`: (metrics of A, metrics of B, frames) of runs judged elsewhere (a scenario set's
    eval-method scenarios, `runner.evaluate_scenario`), averaged in with the rest."""
    rows_a: list[dict[str, float]] = []
    rows_b: list[dict[str, float]] = []
    diff = {k: 0 for k in DIFF_KEYS}
    frames = differing = 0
    notes: list[str] = []
    ms_a: list[float] = []
    ms_b: list[float] = []
    pool = None
    pipelines = None
    if workers >= 4:
        from pico_studio.evaluation.rejudge_worker import ProcessRejudger

        pipelines = (ProcessRejudger(KeptRun([])), ProcessRejudger(KeptRun([])))
    elif workers > 1:
        import multiprocessing

        from pico_studio import plugins

        # the worker loads the plugins this process has (a config may select their stages)
        pool = ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("spawn"),
                                   initializer=plugins.load_plugins, initargs=(plugins.specs(),))
    try:
        for run in runs:
            ja, jb = _judge_pair(run, cfg_a, cfg_b, pool, pipelines)
            last, n_diff = run_diff(ja, jb)
            for k in DIFF_KEYS:
                diff[k] += last[k]
            differing += n_diff
            frames += len(ja.times)
            rows_a.append(_compared(ja.totals))
            rows_b.append(_compared(jb.totals))
            ms_a.append(ja.totals.get("perceptor.ms_per_scan", math.nan))
            ms_b.append(jb.totals.get("perceptor.ms_per_scan", math.nan))
            prefix = f"{run.name}: " if run.name and len(runs) > 1 else ""
            notes += [prefix + n for n in ja.notes if prefix + n not in notes]
    finally:
        if pool is not None:
            pool.shutdown(cancel_futures=True)
        for w in pipelines or ():
            w.close()
    for a, b, n in extra or []:
        rows_a.append(_compared(a))
        rows_b.append(_compared(b))
        frames += n
    return Comparison(frames, mean_metrics(rows_a), mean_metrics(rows_b), diff, differing,
                      {"a": _nanmean(ms_a), "b": _nanmean(ms_b)}, notes)


def _compared(totals: dict[str, float]) -> dict[str, float]:
    return {k: v for k, v in totals.items() if k not in TIMINGS and math.isfinite(v)}


def _nanmean(values: list[float]) -> float | None:
    ok = [v for v in values if math.isfinite(v)]
    return float(sum(ok) / len(ok)) if ok else None


# ----- the runs to compare on ---------------------------------------------------------------------


def sim_run(map_path: str, cfg: Config, *, sim_config: str | None = None, seed: int | None = None,
            seconds: float = 30.0, dt: float = 0.05, behaviour: str = "wander", localise: bool = False,
            name: str = "") -> KeptRun:
    """The simulator on `map_path` driven by `behaviour` (built from `cfg`: A's) for `seconds`,
    every frame and its truth kept. A behaviour that reads the world model drives on A's."""
    from pico_studio.core.behaviours.registry import make_behaviour
    from pico_studio.json_map import load_map
    from pico_studio.sim import Simulator
    from pico_studio.sim.sim_config import load_sim_config

    gmap = load_map(map_path, cfg.map)
    sc = load_sim_config(sim_config) if sim_config is not None else None
    sim = Simulator(gmap, cfg.sim, sc, seed=seed)
    start = tuple(float(v) for v in sim.truth.pose)
    b = make_behaviour(behaviour, cfg, gmap, start)  # type: ignore[arg-type]
    return record_sim(sim, cfg, b, seconds=seconds, dt=dt, localise=localise, initial_pose=start,  # type: ignore[arg-type]
                      perceptor=_drive_perceptor(behaviour, cfg, gmap, start), name=name or map_path)


def _drive_perceptor(behaviour: str, cfg: Config, gmap: Any, start: Any) -> Any:
    """A's perceptor for a reference behaviour that steers by the world model (the hospital,
    the escape room, the room finder); None for one that drives on the raw laser."""
    from pico_studio.core.behaviours.registry import DEFAULT_SECONDS, behaviour_name
    from pico_studio.evaluation.runner import make_perceptor

    name = behaviour_name(behaviour)
    if name not in DEFAULT_SECONDS:
        return None
    return make_perceptor(cfg, gmap, start, localise=name == "hospital")


def recording_run(source: str, cfg: Config, *, seconds: float | None = None, map_path: str | None = None,
                  name: str = "") -> KeptRun:
    """Every frame of a recording (`bag:FILE` | `carmen:FILE`), localised on `map_path` when
    given and the recording knows its true pose."""
    from pico_studio.json_map import load_map
    from pico_studio.sources import open_source

    replay = open_source(source, cfg.sources)
    if not hasattr(replay, "frame_count"):
        raise UserError("compare needs a recording (bag:FILE or carmen:FILE) or the simulator", field="--source")
    gmap = load_map(map_path, cfg.map) if map_path is not None else None
    return record_replay(replay, seconds=seconds, global_map=gmap, name=name or source)


def scenario_runs(ss: ScenarioSet, cfg_a: Config, cfg_b: Config, *, seconds: float | None = None,
                  seed: int | None = None) -> tuple[list[KeptRun], list[tuple[dict[str, float], dict[str, float], int]]]:
    """The kept runs of a scenario set (recordings and driven runs), and the eval-method
    scenarios (`poses`: a fresh perceptor at each random pose, the robot turning on the spot,
    so the sensor data is the same for both) judged with A and with B directly."""
    from pico_studio.evaluation.runner import evaluate_scenario

    runs: list[KeptRun] = []
    extra: list[tuple[dict[str, float], dict[str, float], int]] = []
    for s in ss:
        s = _override(s, seconds, seed)
        if s.method == "poses":
            ra, rb = evaluate_scenario(s, cfg_a), evaluate_scenario(s, cfg_b)
            extra.append((ra.metrics, rb.metrics, ra.frames))
        elif s.recording is not None:
            runs.append(recording_run(s.recording, cfg_a, seconds=s.seconds, map_path=s.map if s.localise else None,
                                      name=s.name))
        else:
            runs.append(_scenario_sim_run(s, cfg_a))
    return runs, extra


def _override(s: Scenario, seconds: float | None, seed: int | None) -> Scenario:
    from dataclasses import replace

    if seconds is not None:
        s = replace(s, seconds=seconds)
    return s if seed is None else replace(s, seed=seed)


def _scenario_sim_run(s: Scenario, cfg: Config) -> KeptRun:
    from pico_studio.core.behaviours.registry import DEFAULT_SECONDS, behaviour_name, make_behaviour
    from pico_studio.evaluation.runner import _world
    from pico_studio.sim import Simulator

    gmap, start, _, sc = _world(s, cfg)
    sim = Simulator(gmap, cfg.sim, sc, seed=s.seed, initial_pose=start)
    pose = tuple(float(v) for v in sim.truth.pose)
    spec = s.behaviour or "wander"
    seconds = s.seconds if s.seconds is not None else DEFAULT_SECONDS.get(behaviour_name(spec), 10.0)
    b = make_behaviour(spec, cfg, gmap, pose)  # type: ignore[arg-type]
    return record_sim(sim, cfg, b, seconds=seconds, dt=s.dt, localise=s.localise, initial_pose=pose,  # type: ignore[arg-type]
                      perceptor=_drive_perceptor(spec, cfg, gmap, pose), name=s.name)
