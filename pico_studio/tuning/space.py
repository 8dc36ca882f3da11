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
import math
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

    def suggest(self, trial: Any, lo: float | None = None, hi: float | None = None) -> Any:
        """Ask an Optuna trial for this dimension's value, on lo..hi when an ordering with a
        sibling narrows the declared range (an empty narrowing keeps the declared one: the
        trial then fails validation, as it would have)."""
        if self.kind in ("bool", "choice"):
            return trial.suggest_categorical(self.path, list(self.choices or ()))
        assert self.lo is not None and self.hi is not None
        lo = self.lo if lo is None else max(self.lo, lo)
        hi = self.hi if hi is None else min(self.hi, hi)
        if lo > hi:
            lo, hi = self.lo, self.hi
        if self.kind == "int":
            step = int(self.step or 1)
            return trial.suggest_int(self.path, math.ceil(lo), math.floor(hi), step=step, log=self.log)
        if self.step:  # on the declared grid from self.lo (Optuna wants hi on the grid from lo)
            lo = round(self.lo + self.step * math.ceil((lo - self.lo) / self.step - 1e-9), 12)
            hi = round(lo + self.step * int((hi - lo) / self.step + 1e-9), 12)
        return trial.suggest_float(self.path, lo, hi, step=self.step, log=self.log)

    def describe(self) -> str:
        if self.kind in ("bool", "choice"):
            return f"{self.path}: one of {', '.join(map(str, self.choices or ()))}"
        scale = ", log scale" if self.log else (f", step {self.step:g}" if self.step else "")
        return f"{self.path}: {self.lo:g} .. {self.hi:g}{scale}"


@dataclass(frozen=True)
class Order:
    """A declared ordering between two parameters (`below=` / `at_most=`): `lower` stays
    below (strict) or at most `upper`. A side outside the space is fixed at its base value."""

    lower: str
    upper: str
    strict: bool
    fixed_lower: float | None = None  # the base value when `lower` is not searched
    fixed_upper: float | None = None

    def gap(self, dim: Dimension) -> float:
        """The least difference a strict order needs on `dim`'s grid."""
        if not self.strict:
            return 0.0
        return dim.step or (1.0 if dim.kind == "int" else 1e-9 * max(1.0, abs(dim.hi or 1.0)))


@dataclass(frozen=True)
class SearchSpace:
    globs: tuple[str, ...]
    dimensions: tuple[Dimension, ...]
    # the declared orderings touching a searched parameter: sampled in order, so no trial is
    # spent on a config validation refuses (door_min_width >= door_max_width was ~30%)
    orders: tuple[Order, ...] = ()

    @property
    def paths(self) -> list[str]:
        return [d.path for d in self.dimensions]

    def fingerprint(self) -> str:
        """A short hash of the dimensions: a study remembers it and refuses another space."""
        text = json.dumps([asdict(d) for d in self.dimensions], sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    def suggest(self, trial: Any) -> dict[str, Any]:
        """One value per dimension; a parameter bounded from below by an ordered sibling is
        asked after it, on the range that keeps the order."""
        dims = {d.path: d for d in self.dimensions}
        values: dict[str, Any] = {}
        for d in self._ordered():
            lo = hi = None
            for o in self.orders:
                if o.upper == d.path:  # bounded below by the lower one's value
                    below = values.get(o.lower, o.fixed_lower)
                    if below is not None:
                        lo = max(lo if lo is not None else -math.inf, below + o.gap(d))
                if o.lower == d.path:  # bounded above by the upper one's largest value
                    up = self._top(o.upper, dims) if o.upper in dims else o.fixed_upper
                    if up is not None:
                        hi = min(hi if hi is not None else math.inf, up - o.gap(d))
            values[d.path] = d.suggest(trial, lo, hi)
        return {d.path: values[d.path] for d in self.dimensions}

    def _top(self, path: str, dims: dict[str, Dimension], depth: int = 0) -> float | None:
        """The largest value a searched parameter can take: its declared top, lowered by the
        orderings bounding it from above (a chain: door_min_width < door_max_width <=
        wide_door_max_width, the last fixed or searched)."""
        top = dims[path].hi
        if depth > len(self.orders):  # a cycle cannot be declared consistently
            return top
        for o in self.orders:
            if o.lower != path:
                continue
            up = self._top(o.upper, dims, depth + 1) if o.upper in dims else o.fixed_upper
            if up is not None:
                bound = up - o.gap(dims[path])
                top = bound if top is None else min(top, bound)
        return top

    def _ordered(self) -> list[Dimension]:
        """The dimensions, each after every searched one that bounds it from below."""
        done: list[Dimension] = []
        pending = list(self.dimensions)
        while pending:
            for d in pending:
                if all(o.lower in {e.path for e in done} or o.lower not in self.paths
                       for o in self.orders if o.upper == d.path):
                    done.append(d)
                    pending.remove(d)
                    break
            else:  # a cycle cannot be declared consistently; ask the rest as they come
                done.extend(pending)
                break
        return done

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
    return SearchSpace(globs, tuple(dims), _orders(cfg, {d.path for d in dims}))


def _orders(cfg: Config, searched: set[str]) -> tuple[Order, ...]:
    """The declared orderings with at least one side searched."""
    out = []
    for p in params(cfg):
        if p.spec.upper is None:
            continue
        other, strict = p.spec.upper
        upper = p.path.rsplit(".", 1)[0] + "." + other
        if p.path not in searched and upper not in searched:
            continue
        out.append(Order(p.path, upper, strict,
                         None if p.path in searched else float(p.value),
                         None if upper in searched else float(get_value(cfg, upper))))
    return tuple(out)
