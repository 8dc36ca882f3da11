"""The search space of a study, derived from the config declaration (nothing declared twice).

Every parameter matched by `--params GLOB[,GLOB…]` becomes one dimension with the range, step
and choices its `param(...)` declaration gives:

- a float: uniform on lo..hi in steps of `step`; on a log scale (no step) when lo > 0 and the
  range spans two decades or more (hi / lo >= 100), so small values get as many trials as big;
- an int: lo..hi in steps of `step` (1 when undeclared); log scale by the same rule (step 1);
- a bool: true or false; a choice: one of its `choices`. Strings (paths, topics) are skipped.

Only the core's areas can be tuned (`TUNABLE_ROOTS`): changing the simulator, the sources or
the page would change the question, not the answer.
"""

from __future__ import annotations

import fnmatch
import hashlib
import json
from dataclasses import asdict, dataclass
from typing import Any

from pico_studio.config import Config, ParamInfo, from_dict, get_value, params, to_dict
from pico_studio.errors import ConfigError

TUNABLE_ROOTS = ("perception", "localisation", "behaviour")
DEFAULT_PARAMS = "perception.*"
LOG_SPAN = 100.0  # hi / lo at or beyond which a positive range is searched on a log scale


@dataclass(frozen=True)
class Dimension:
    """One searched parameter: its dotted path and the Optuna distribution it maps to."""

    path: str
    kind: str  # "float" | "int" | "bool" | "choice"
    lo: float | None = None
    hi: float | None = None
    step: float | None = None
    log: bool = False
    choices: tuple[Any, ...] | None = None

    @classmethod
    def from_param(cls, p: ParamInfo) -> Dimension:
        s = p.spec
        if s.kind == "bool":
            return cls(p.path, "bool", choices=(False, True))
        if s.kind == "choice":
            return cls(p.path, "choice", choices=tuple(s.choices or ()))
        assert s.lo is not None and s.hi is not None
        log = s.lo > 0 and s.hi / s.lo >= LOG_SPAN
        if s.kind == "int":
            step = 1 if log else max(1, int(s.step or 1))
            return cls(p.path, "int", float(s.lo), float(s.hi), float(step), log)
        # Optuna cannot step a log scale; a declared step is a slider's resolution, not a rule
        return cls(p.path, "float", float(s.lo), float(s.hi), None if log else s.step, log)

    def suggest(self, trial: Any) -> Any:
        """Ask an Optuna trial for this dimension's value."""
        if self.kind in ("bool", "choice"):
            return trial.suggest_categorical(self.path, list(self.choices or ()))
        assert self.lo is not None and self.hi is not None
        if self.kind == "int":
            return trial.suggest_int(self.path, int(self.lo), int(self.hi),
                                     step=int(self.step or 1), log=self.log)
        hi = self.hi
        if self.step:  # Optuna wants hi on the grid from lo
            hi = self.lo + self.step * int((self.hi - self.lo) / self.step + 1e-9)
        return trial.suggest_float(self.path, self.lo, hi, step=self.step, log=self.log)

    def describe(self) -> str:
        if self.kind in ("bool", "choice"):
            return f"{self.path}: one of {', '.join(map(str, self.choices or ()))}"
        scale = ", log scale" if self.log else (f", step {self.step:g}" if self.step else "")
        return f"{self.path}: {self.lo:g} .. {self.hi:g}{scale}"


@dataclass(frozen=True)
class SearchSpace:
    globs: tuple[str, ...]
    dimensions: tuple[Dimension, ...]

    @property
    def paths(self) -> list[str]:
        return [d.path for d in self.dimensions]

    def fingerprint(self) -> str:
        """A short hash of the dimensions: a study remembers it and refuses another space."""
        text = json.dumps([asdict(d) for d in self.dimensions], sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    def suggest(self, trial: Any) -> dict[str, Any]:
        return {d.path: d.suggest(trial) for d in self.dimensions}

    def start_params(self, cfg: Config) -> dict[str, Any]:
        """The values of `cfg` in this space: the study's first trial (the start config)."""
        return {d.path: get_value(cfg, d.path) for d in self.dimensions}

    def apply(self, cfg: Config, values: dict[str, Any]) -> Config:
        """`cfg` with the trial's values, validated together (cross-field rules such as
        door_min_width < door_max_width see the whole trial); a ConfigError fails the trial."""
        tree = to_dict(cfg)
        for path, value in values.items():
            *sections, name = path.split(".")
            node = tree
            for part in sections:
                node = node[part]
            if name not in node:
                raise ConfigError("unknown parameter", field=path)
            node[name] = value
        return from_dict(Config, tree)


def parse_globs(text: str | None) -> tuple[str, ...]:
    globs = tuple(g.strip() for g in (text or DEFAULT_PARAMS).split(",") if g.strip())
    if not globs:
        raise ConfigError("needs at least one parameter glob, e.g. perception.merge.*", field="--params")
    return globs


def search_space(cfg: Config, globs: str | tuple[str, ...] | None = None) -> SearchSpace:
    """The dimensions of every tunable parameter of `cfg` matched by one of `globs`."""
    globs = parse_globs(globs) if not isinstance(globs, tuple) else globs
    tunable = [p for p in params(cfg)
               if p.path.split(".", 1)[0] in TUNABLE_ROOTS and p.spec.kind != "str"]
    dims: list[Dimension] = []
    for g in globs:
        hits = [p for p in tunable if fnmatch.fnmatchcase(p.path, g)]
        if not hits:
            roots = ", ".join(r + ".*" for r in TUNABLE_ROOTS)
            raise ConfigError(f"'{g}' matches no tunable parameter (those under {roots}; "
                              "see `pico-studio config defaults`)", field="--params")
        dims.extend(Dimension.from_param(p) for p in hits if p.path not in {d.path for d in dims})
    return SearchSpace(globs, tuple(dims))
