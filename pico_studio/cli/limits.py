"""Ranges for every number given on the command line, as argparse `type=` validators (and
one `action=` for a cap on a product), so a bad value is refused by argparse itself:
`pico-studio run: error: argument --dt: must be ... got 1e-09`, exit 2, before any work.

    p.add_argument("--dt", type=limits.DT, action=limits.StepCap, ...)
    p.add_argument("--seed", type=limits.SEED, ...)

Why these ranges:
* `--dt` 1e-4 .. 10 s: the simulator's physics and the perceptor expect a control period
  around 0.05 s; below 0.1 ms a run is only steps (`--dt 1e-9 --seconds 1` = 10^9 steps).
* `--seconds` 0 .. 10^6 s (11 days), and `seconds / dt` at most `MAX_STEPS` (10^7 steps,
  about 6 days at 20 Hz, hours of CPU): a run that cannot end in reasonable time is refused.
* `--resolution` 1e-4 .. 100 m/px (the raster's pixel cap bounds the image itself).
* `--seed` 0 .. 2^32 - 1: what numpy's seeding and the bag's record of it accept.
* counts (`--poses`, `--frames`) 1 .. 10^4 each.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable, Sequence
from typing import Any

MAX_STEPS = 10_000_000
DEFAULT_DT = 0.05  # what `run` uses without --dt
DEFAULT_SECONDS = 10.0  # what `run` uses without --seconds


def number(lo: float, hi: float, *, lo_open: bool = False, unit: str = "") -> Callable[[str], float]:
    """A `type=` for a finite float in [lo, hi] (or (lo, hi] with `lo_open`)."""
    bracket = "(" if lo_open else "["
    unit_text = f" {unit}" if unit else ""

    def parse(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
        if not math.isfinite(v) or v < lo or v > hi or (lo_open and v == lo):
            raise argparse.ArgumentTypeError(
                f"must be a finite number in {bracket}{lo:g}, {hi:g}]{unit_text}, got {text}"
            )
        return v

    parse.__name__ = "number"
    return parse


def whole(lo: int, hi: int, what: str = "a whole number") -> Callable[[str], int]:
    """A `type=` for an integer in [lo, hi] (decimal digits only: no 1e3, no 5000 digits)."""

    def parse(text: str) -> int:
        t = text.strip()
        digits = t.lstrip("+-")
        if not digits.isdigit() or not digits.isascii() or len(digits) > 30:
            raise argparse.ArgumentTypeError(f"must be {what}, got {text[:40]!r}")
        v = int(t)
        if not lo <= v <= hi:
            raise argparse.ArgumentTypeError(f"must be {what} in [{lo}, {hi}], got {v}")
        return v

    parse.__name__ = "whole"
    return parse


DT = number(1e-4, 10.0, unit="s")
SECONDS = number(0.0, 1e6, unit="s")
RESOLUTION = number(1e-4, 100.0, unit="m/px")
SEED = whole(0, 2**32 - 1, "a seed")
COUNT = whole(1, 10_000, "a count")
TURN = number(-10.0, 10.0, unit="rad/s")
CLEARANCE = number(0.0, 10.0, unit="m")
WORKERS = whole(1, 64, "a number of processes")
PORT = whole(0, 65535, "a port")
PIXELS = whole(16, 8192, "a size in pixels")
FPS = number(0.0, 240.0, lo_open=True, unit="frames/s")
TOLERANCE = number(0.0, 1e6)
MILLISECONDS = number(0.0, 1e6, lo_open=True, unit="ms")


class StepCap(argparse.Action):
    """Stores --seconds or --dt and refuses the pair when seconds / dt > MAX_STEPS (with
    the default of the one not given): whichever of the two comes second sees the first."""

    def __call__(
        self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
        values: str | Sequence[Any] | None, option_string: str | None = None,
    ) -> None:
        setattr(namespace, self.dest, values)
        seconds = getattr(namespace, "seconds", None)
        dt = getattr(namespace, "dt", None)
        s = DEFAULT_SECONDS if seconds is None else float(seconds)
        d = DEFAULT_DT if dt is None else float(dt)
        if d > 0 and s / d > MAX_STEPS:
            raise argparse.ArgumentError(
                self,
                f"--seconds {s:g} at --dt {d:g} is {s / d:.3g} steps, over the {MAX_STEPS:.0e} "
                "step limit: a larger --dt or fewer --seconds",
            )
