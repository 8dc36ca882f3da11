"""The evaluation a trial runs, in one place: scenario sets, metrics and the runner.

INTERIM until the evaluation spine lands on main (then this re-exports
`pico_studio.evaluation.{scenarios,runner,metrics}`): a scenario set is a YAML list of
`{name, map, sim_config, seed, poses}` scored by `pico-studio eval`'s own `evaluate`.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pico_studio.config import Config, dump_yaml
from pico_studio.errors import ConfigError
from pico_studio.user_files import parse_yaml, read_text


@dataclass(frozen=True)
class Metric:
    name: str
    help: str
    higher_is_better: bool
    needs_truth: bool = True


METRICS: dict[str, Metric] = {m.name: m for m in [
    Metric("walls.f1", "wall F1", True),
    Metric("corners.f1", "corner F1", True),
    Metric("doors.f1", "door F1", True),
    Metric("corners.convexity", "convex/concave accuracy", True),
    Metric("endpoint_error_m", "wall end-point error", False),
    Metric("perceptor.ms_per_scan", "perceptor CPU per scan", False, needs_truth=False),
    Metric("perception_score", "mean of wall, corner, door F1 and convexity", True),
]}


@dataclass(frozen=True)
class Scenario:
    name: str
    map: str | None = None
    world: str | None = None
    sim_config: str | None = None
    seed: int = 0
    behaviour: str | None = None
    poses: int | None = None
    recording: str | None = None
    localise: bool = False
    frames: int = 20


@dataclass(frozen=True)
class ScenarioSet:
    name: str
    path: Path | None
    scenarios: list[Scenario] = field(default_factory=list)


@dataclass
class ScenarioResult:
    name: str
    summary: dict[str, Any]
    metrics: dict[str, float]
    frames: int = 0
    seconds_wall: float = 0.0


@dataclass
class SetResult:
    per_scenario: dict[str, ScenarioResult]
    metrics: dict[str, float]
    frames: int = 0


def load_scenarios(path: str | Path) -> ScenarioSet:
    p = Path(path)
    data = parse_yaml(read_text(p, ConfigError, "a scenario set"), ConfigError, p)
    items = data.get("scenarios") if isinstance(data, dict) else None
    if not isinstance(items, list) or not items:
        raise ConfigError("needs a non-empty list of scenarios", file=p, field="scenarios")
    out = []
    for i, it in enumerate(items):
        if not isinstance(it, dict) or "map" not in it:
            raise ConfigError("needs a map", file=p, field=f"scenarios[{i}].map")
        out.append(Scenario(name=str(it.get("name", f"s{i}")), map=str(p.parent / it["map"]),
                            seed=int(it.get("seed", 0)), poses=int(it.get("poses", 3)),
                            frames=int(it.get("frames", 20))))
    return ScenarioSet(str(data.get("name", p.stem)), p, out)


def _f1(p: float, r: float) -> float:
    return 0.0 if p + r <= 0 else 2 * p * r / (p + r)


def evaluate_scenario(s: Scenario, cfg: Config, *, progress: Any = None) -> ScenarioResult:
    # interim only: `pico-studio eval` in a child process (the runner of the spine replaces it;
    # a child, because tuning sits below the CLI and must not import it)
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        f.write(dump_yaml(cfg, comments=False))
    assert s.map is not None and s.poses is not None
    cmd = [sys.executable, "-m", "pico_studio", "eval", "--map", s.map, "--config", f.name, "--seed", str(s.seed),
           "--poses", str(s.poses), "--frames", str(s.frames), "--json"]
    if s.sim_config:
        cmd += ["--sim-config", s.sim_config]
    try:
        done = subprocess.run(cmd, capture_output=True, text=True, check=False)
    finally:
        Path(f.name).unlink()
    if done.returncode != 0:
        raise RuntimeError(done.stderr.strip().splitlines()[-1] if done.stderr.strip() else "eval failed")
    r = json.loads(done.stdout)
    m = {"walls.f1": _f1(r["wall_precision"], r["wall_recall"]),
         "corners.f1": _f1(r["corner_precision"], r["corner_recall"]),
         "doors.f1": _f1(r["door_precision"], r["door_recall"]),
         "corners.convexity": r["convexity_accuracy"],
         "endpoint_error_m": r["endpoint_error_m"], "perceptor.ms_per_scan": r["ms_per_scan"]}
    m["perception_score"] = (m["walls.f1"] + m["corners.f1"] + m["doors.f1"] + m["corners.convexity"]) / 4
    return ScenarioResult(s.name, r, m, r["frames"])


def evaluate_scenarios(ss: ScenarioSet, cfg: Config, *, workers: int = 1, progress: Any = None) -> SetResult:
    res = [evaluate_scenario(s, cfg) for s in ss.scenarios]
    keys = res[0].metrics.keys()
    return SetResult({r.name: r for r in res}, {k: sum(r.metrics[k] for r in res) / len(res) for k in keys},
                     sum(r.frames for r in res))

