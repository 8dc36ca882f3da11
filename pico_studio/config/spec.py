"""How a parameter is declared: `param(...)` and `section(...)` on frozen dataclasses.

Each parameter is declared once, next to its siblings in a section dataclass, with its
default, range, step, unit and a one-line meaning. Sliders, the YAML export and validation
are all derived from that declaration by `walk()`; nothing else lists the parameters.

    @dataclass(frozen=True)
    class ProximityParams:
        radius: float = param(0.35, lo=0.1, hi=2.0, step=0.01, unit="m",
                              help="Radius of the close-proximity bubble around the robot")
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any

from pico_studio.config.plugin_params import LiveChoices

_SPEC = "pico_studio.param"
_SECTION = "pico_studio.section"


@dataclass(frozen=True)
class ParamSpec:
    """Everything known about one parameter except its current value."""

    default: Any
    help: str
    unit: str = ""
    lo: float | None = None
    hi: float | None = None
    step: float | None = None
    # a tuple, or a `LiveChoices` that plugins add names to (read it when needed, never copy)
    choices: Sequence[str] | None = None
    # the sibling parameter (same section) this one must stay below (`below`, strictly) or
    # not exceed (`at_most`): validation and the tuner's search space both read it
    below: str | None = None
    at_most: str | None = None

    @property
    def upper(self) -> tuple[str, bool] | None:
        """(sibling, strict) this value is bounded by, or None."""
        if self.below is not None:
            return self.below, True
        if self.at_most is not None:
            return self.at_most, False
        return None

    @property
    def kind(self) -> str:
        """One of "bool", "int", "float", "choice", "str"."""
        if self.choices is not None:
            return "choice"
        if isinstance(self.default, bool):
            return "bool"
        if isinstance(self.default, int):
            return "int"
        if isinstance(self.default, float):
            return "float"
        return "str"

    def describe(self) -> str:
        """The meaning with unit and range, as a slider hint or a YAML comment."""
        parts = [self.help]
        if self.unit:
            parts.append(f"[{self.unit}]")
        if self.choices is not None:
            parts.append("one of: " + ", ".join(self.choices))
        elif self.lo is not None or self.hi is not None:
            parts.append(f"range {_fmt(self.lo)} .. {_fmt(self.hi)}")
        if self.upper is not None:
            parts.append(("below " if self.upper[1] else "at most ") + self.upper[0])
        return " ".join(parts)


def _fmt(v: float | None) -> str:
    return "-" if v is None else f"{v:g}"


def param(
    default: Any,
    *,
    help: str,
    unit: str = "",
    lo: float | None = None,
    hi: float | None = None,
    step: float | None = None,
    choices: Sequence[str] | None = None,
    below: str | None = None,
    at_most: str | None = None,
) -> Any:
    """Declare a parameter field of a section dataclass."""
    spec = ParamSpec(
        default=default,
        help=help,
        unit=unit,
        lo=lo,
        hi=hi,
        step=step,
        choices=choices if isinstance(choices, LiveChoices) or choices is None else tuple(choices),
        below=below,
        at_most=at_most,
    )
    if below is not None and at_most is not None:
        raise TypeError(f"parameter {help!r} takes one of below= and at_most=, not both")
    if spec.kind in ("int", "float"):
        if spec.lo is None or spec.hi is None:
            raise TypeError(f"numeric parameter {help!r} needs lo and hi")
        if not spec.lo <= default <= spec.hi:
            raise TypeError(f"default {default} of {help!r} is outside {spec.lo}..{spec.hi}")
    if spec.choices is not None and default not in spec.choices:
        raise TypeError(f"default {default!r} of {help!r} is not one of {spec.choices}")
    return dataclasses.field(default=default, metadata={_SPEC: spec})


def section(cls: type, help: str) -> Any:
    """Declare a nested section (another frozen dataclass of params/sections)."""
    return dataclasses.field(default_factory=cls, metadata={_SECTION: help})


@dataclass(frozen=True)
class ParamInfo:
    """One parameter found by `walk`: its dotted path, its declaration and current value."""

    path: str
    spec: ParamSpec
    value: Any

    @property
    def name(self) -> str:
        return self.path.rsplit(".", 1)[-1]

    @property
    def group(self) -> str:
        return self.path.rsplit(".", 1)[0] if "." in self.path else ""


@dataclass(frozen=True)
class SectionInfo:
    path: str
    help: str


def walk(obj: Any, prefix: str = "") -> Iterator[ParamInfo | SectionInfo]:
    """Every section and parameter of a config object, depth first, in declaration order."""
    for f in dataclasses.fields(obj):
        path = f"{prefix}{f.name}"
        value = getattr(obj, f.name)
        if _SECTION in f.metadata:
            yield SectionInfo(path, f.metadata[_SECTION])
            yield from walk(value, path + ".")
        elif _SPEC in f.metadata:
            yield ParamInfo(path, f.metadata[_SPEC], value)


def params(obj: Any) -> list[ParamInfo]:
    return [p for p in walk(obj) if isinstance(p, ParamInfo)]


def coerce(spec: ParamSpec, value: Any) -> Any:
    """The value as the parameter's type, or ValueError saying what is wrong with it."""
    kind = spec.kind
    if kind == "bool":
        if isinstance(value, bool):
            return value
        raise ValueError(f"must be true or false, got {value!r}")
    if kind == "choice":
        if isinstance(value, str) and value in (spec.choices or ()):
            return value
        raise ValueError(f"must be one of {', '.join(spec.choices or ())}, got {value!r}")
    if kind == "str":
        if isinstance(value, str):
            return value
        raise ValueError(f"must be a string, got {value!r}")
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"must be a number, got {value!r}")
    if not math.isfinite(value):
        raise ValueError(f"must be a finite number, got {value!r}")
    if kind == "int":
        if float(value) != int(value):
            raise ValueError(f"must be a whole number, got {value!r}")
        value = int(value)
    else:
        value = float(value)
    assert spec.lo is not None and spec.hi is not None
    if not spec.lo <= value <= spec.hi:
        unit = f" {spec.unit}" if spec.unit else ""
        raise ValueError(
            f"{value:g} is out of range; allowed {spec.lo:g} .. {spec.hi:g}{unit}"
        )
    return value
