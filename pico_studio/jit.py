"""Compiled loops: the one place that imports numba and says how it is used.

Every hot loop of the core (segmenters, refit, corners, the localisation matcher, the
planner, truth scoring, the simulator's raycast) is a plain Python function decorated with
`kernel(example)`: numba compiles it on first call (`nopython`, `cache=True`, no fast-math,
so it gives the same floats as the Python it was written as; numpy's error model, so a
division by zero gives inf or NaN as numpy's float64 does instead of raising), and the
uncompiled function
stays reachable as `f.py_func` — the reference the tests and benchmarks compare against.

The cache. numba reads `NUMBA_CACHE_DIR` once, when it is imported, so this module settles
the folder *before* importing numba. numba checks a cached function against its own source
file only: a kernel that calls a helper from another module (door_kernels.jamb_doors calls
identify_kernels.backed) keeps the helper's old code when only the helper's file changed — a
`git pull` could leave a checkout silently computing with yesterday's rule (numba/numba#1833).
So every folder below ends in the `source_digest()` of every kernel module and this file:
changed code is a new folder, compiled afresh.

1. `NUMBA_CACHE_DIR` already set: used as is (the user knows best);
2. `PICO_STUDIO_CACHE` set: `$PICO_STUDIO_CACHE/numba/<digest>`;
3. the package folder writable (a checkout, a user install): `<package>/__pycache__/numba/<digest>`,
   the other digests' folders there removed once a day old;
4. else (a read-only checkout, a system install): `$XDG_CACHE_HOME/pico_studio/numba/<digest>`
   (`~/.cache/...`), or a per-user folder in the temp directory when that is not writable.

`warm_up()` compiles (or loads from the cache) every kernel on tiny inputs of the types the
real calls use: `./dev setup` runs it once, the tests once per session (tests/conftest.py),
`pico-studio serve` in a background thread so the page is up at once.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib
import os
import shutil
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, TypeVar, cast

PACKAGE_DIR = Path(__file__).resolve().parent

# modules holding kernels, imported by warm_up (tests/test_jit.py checks the list is whole)
KERNEL_MODULES = (
    "pico_studio.sim.raycast",  # first: a simulator's first scan needs it (serve starts sooner)
    "pico_studio.core.geometry",
    "pico_studio.core.perception.scan_kernels",
    "pico_studio.core.perception.segment_refit",
    "pico_studio.core.perception.segment_split_merge",
    "pico_studio.core.perception.segment_angle",
    "pico_studio.core.perception.segment_ransac",
    "pico_studio.core.perception.corners",
    "pico_studio.core.perception.identify_kernels",
    "pico_studio.core.perception.map_proven_kernels",
    "pico_studio.core.perception.face_kernels",
    "pico_studio.core.perception.door_kernels",
    "pico_studio.core.perception.door_memory_kernels",
    "pico_studio.core.perception.line_jambs",
    "pico_studio.core.perception.junction_kernels",
    "pico_studio.core.perception.merge_kernels",
    "pico_studio.core.perception.objects",
    "pico_studio.core.perception.entrance",
    "pico_studio.core.perception.rooms",
    "pico_studio.core.perception.laser_motion",
    "pico_studio.core.perception.scan_match_kernels",
    "pico_studio.core.localisation.match_kernels",
    "pico_studio.core.localisation.combined_kernels",
    "pico_studio.core.behaviours.planner",
    "pico_studio.core.behaviours.wander",
    "pico_studio.sim.truth_kernels",
    "pico_studio.sim.base_kernels",
    "pico_studio.evaluation.score_kernels",
)


def _writable(folder: Path) -> bool:
    """Can files be created in `folder` (made if missing)? Tried, as numba itself does."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder):
            pass
        return True
    except OSError:
        return False


def source_digest(files: list[Path]) -> str:
    """12 hex digits of the SHA-256 of `files`' names and bytes (a missing file counts as empty)."""
    h = hashlib.sha256()
    for f in files:
        h.update(f.name.encode() + b"\0")
        with contextlib.suppress(OSError):
            h.update(f.read_bytes())
        h.update(b"\0")
    return h.hexdigest()[:12]


def kernel_sources(package_dir: Path = PACKAGE_DIR) -> list[Path]:
    """This file and every module of `KERNEL_MODULES`, as files of `package_dir`."""
    return [package_dir / "jit.py"] + [package_dir.joinpath(*name.split(".")[1:]).with_suffix(".py")
                                       for name in KERNEL_MODULES]


def _prune(folder: Path, keep: str, age: float = 86400.0) -> None:
    """Remove `folder`'s other digests' caches untouched for `age` seconds (best effort: another
    process of another version may be using a younger one)."""
    now = time.time()
    with contextlib.suppress(OSError):
        for old in folder.iterdir():
            if old.name != keep and old.is_dir() and now - old.stat().st_mtime > age:
                shutil.rmtree(old, ignore_errors=True)


def choose_cache_dir(env: dict[str, str] | os._Environ[str], package_dir: Path = PACKAGE_DIR) -> str | None:
    """The folder for NUMBA_CACHE_DIR by the rules above; None: nowhere to write (numba compiles
    in memory)."""
    if env.get("NUMBA_CACHE_DIR"):
        return env["NUMBA_CACHE_DIR"]
    digest = source_digest(kernel_sources(package_dir))
    if env.get("PICO_STUDIO_CACHE"):
        return str(Path(env["PICO_STUDIO_CACHE"]) / "numba" / digest)
    if _writable(package_dir / "__pycache__"):
        _prune(package_dir / "__pycache__" / "numba", digest)
        return str(package_dir / "__pycache__" / "numba" / digest)
    xdg = Path(env.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    for folder in (xdg / "pico_studio" / "numba",
                   Path(tempfile.gettempdir()) / f"pico_studio-{os.getuid() if hasattr(os, 'getuid') else 'user'}" / "numba"):
        if _writable(folder / digest):
            return str(folder / digest)
    return None


_chosen = choose_cache_dir(os.environ)
if _chosen is not None:
    os.environ["NUMBA_CACHE_DIR"] = _chosen

import numba  # noqa: E402  (after NUMBA_CACHE_DIR is settled)

if _chosen is not None and numba.config.CACHE_DIR != _chosen:  # numba was imported before us
    numba.config.reload_config()

# (compiled function, example-arguments factory) of every kernel, in definition order
_OPTIONS: dict[str, Any] = {"cache": True, "nogil": True, "error_model": "numpy"}
_KERNELS: list[tuple[Any, Callable[[], tuple]]] = []
_HELPERS: list[Any] = []  # compiled helpers kernels call (swapped by `uncompiled` too)


F = TypeVar("F", bound=Callable[..., Any])


def kernel(example: Callable[[], tuple]) -> Callable[[F], F]:
    """Compile a function with numba (cached, nopython) and register it for `warm_up`.

    `example()` returns tiny arguments of the same types (dtype, dimensions, contiguity) as
    the real calls, so warming up compiles the very specialisation the real calls use. (Typed
    as the function itself: a kernel is called like it; `py_func(k)` is its Python.)"""

    def wrap(fn: F) -> F:
        compiled = numba.njit(**_OPTIONS)(fn)
        _KERNELS.append((compiled, example))
        return cast(F, compiled)

    return wrap


def njit(fn: F) -> F:
    """Compile a helper that kernels call (cached, nopython); warmed up through its callers."""
    compiled = numba.njit(**_OPTIONS)(fn)
    _HELPERS.append(compiled)
    return cast(F, compiled)


@contextlib.contextmanager
def uncompiled() -> Iterator[None]:
    """Within: every kernel and helper is its plain Python (`py_func`), wherever a module of
    the package holds it — the same-process peer the benchmarks time the compiled code
    against. Not thread-safe: for benchmarks and tests only."""
    kernels()
    compiled = {id(k): k for k in [k for k, _ in _KERNELS] + _HELPERS}
    swaps = []
    for mod in list(sys.modules.values()):
        if getattr(mod, "__name__", "").startswith("pico_studio"):
            for name, value in list(vars(mod).items()):
                if id(value) in compiled and hasattr(value, "py_func"):
                    swaps.append((mod, name, value))
                    setattr(mod, name, value.py_func)
    try:
        yield
    finally:
        for mod, name, value in swaps:
            setattr(mod, name, value)


def kernels() -> list[Any]:
    """Every registered kernel (after importing `KERNEL_MODULES`)."""
    for name in KERNEL_MODULES:
        importlib.import_module(name)
    return [k for k, _ in _KERNELS]


def warm_up(verbose: bool = False) -> float:
    """Compile (or load from the cache) every kernel on its example; returns seconds taken."""
    t0 = time.perf_counter()
    kernels()
    order = {name: i for i, name in enumerate(KERNEL_MODULES)}  # in the listed order
    for compiled, example in sorted(_KERNELS, key=lambda k: order.get(k[0].__module__, len(order))):
        t = time.perf_counter()
        compiled(*example())
        if verbose:
            print(f"  {compiled.__module__}.{compiled.__name__}: {time.perf_counter() - t:.2f} s", file=sys.stderr)
    return time.perf_counter() - t0


_background: threading.Thread | None = None


def warm_up_in_background() -> threading.Thread:
    """Start `warm_up` in a daemon thread (once): a cold cache compiles while the caller goes
    on; a kernel called meanwhile waits for numba's compiler lock, it never fails."""
    global _background
    if _background is None:
        _background = threading.Thread(target=warm_up, name="pico_studio-warm-up", daemon=True)
        _background.start()
    return _background


def py_func(f: Any) -> Callable:
    """The uncompiled Python of a kernel (itself under NUMBA_DISABLE_JIT=1)."""
    return getattr(f, "py_func", f)




def main() -> None:
    """`python -m pico_studio.jit`: warm the cache (./dev setup runs it)."""
    print(f"compiled {len(kernels())} kernels in {warm_up(verbose=True):.1f} s "
          f"(cache: {numba.config.CACHE_DIR or 'in memory only'})")


if __name__ == "__main__":  # run as a script this file is `__main__`: use the real module's registry
    importlib.import_module("pico_studio.jit").main()
