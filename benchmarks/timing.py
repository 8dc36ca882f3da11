"""Shared by the benchmarks: CPU-time medians, the compiled-vs-Python peer, the machine's load.

Figures are process CPU time (`time.process_time`), so another job on the machine slows the
wall clock but not the figure (much: caches and memory bandwidth are shared). The peer of a
compiled loop is the same code uncompiled (`pico_studio.jit.uncompiled()`: every kernel's
`.py_func`), timed in the same process; the ratio is the figure that travels between machines.
"""

from __future__ import annotations

import os
import statistics
import time
from collections.abc import Callable, Sequence
from typing import Any

from pico_studio.jit import uncompiled, warm_up


def load() -> str:
    """The machine's load averages and cores, for the report."""
    one, five, fifteen = os.getloadavg()
    return f"load {one:.2f} / {five:.2f} / {fifteen:.2f} (1 / 5 / 15 min), {os.cpu_count()} cores"


def cpu_ms(fn: Callable[..., Any], *args: Any) -> float:
    t0 = time.process_time()
    fn(*args)
    return (time.process_time() - t0) * 1000


def median_ms(fn: Callable[[Any], Any], items: Sequence[Any], repeats: int) -> float:
    """Median CPU ms of fn(item) over every item, `repeats` times."""
    return statistics.median(cpu_ms(fn, x) for _ in range(repeats) for x in items)


def compiled_vs_python(fn: Callable[[Any], Any], items: Sequence[Any], repeats: int,
                       python_items: int | None = None) -> tuple[float, float]:
    """(compiled, uncompiled) median CPU ms of fn(item); the uncompiled run (slow) on the
    first `python_items` items once, the compiled one on the same items `repeats` times."""
    warm_up()
    sub = items[:python_items] if python_items else items
    fast = median_ms(fn, sub, repeats)
    with uncompiled():
        slow = median_ms(fn, sub, 1)
    return fast, slow


def ratio_line(label: str, fast: float, slow: float, unit: str = "ms") -> str:
    return f"  {label:34s} {fast:9.4f} {unit} compiled  {slow:9.3f} {unit} .py_func  ({slow / fast:5.0f}x)"
