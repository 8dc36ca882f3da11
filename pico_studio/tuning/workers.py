"""`--workers K`: K local processes on one study, and the study's progress while they run.

Each worker is a fresh interpreter (the `spawn` start method: no forked numba or viser state)
that opens the storage itself and runs trials until the study is full (`study.run_worker`).
The journal file's lock, or the database, keeps the trials apart; the parent only watches.
"""

from __future__ import annotations

import multiprocessing as mp
import time
from collections.abc import Callable
from concurrent.futures import Future, ProcessPoolExecutor

import optuna

from pico_studio.tuning.study import StudySpec, counted, open_study, run_worker


def _worker(spec: StudySpec, worker: int) -> list[int]:
    return run_worker(spec, worker)


class Workers:
    """K background processes on one study; `poll()` says how many trials it holds."""

    def __init__(self, spec: StudySpec, k: int, *, first_worker: int = 0):
        self.spec = spec
        self._study: optuna.Study | None = None
        from pico_studio import plugins  # each worker loads the plugins this process has

        self.pool = ProcessPoolExecutor(max_workers=k, mp_context=mp.get_context("spawn"),
                                        initializer=plugins.load_plugins, initargs=(plugins.specs(),))
        self.futures: list[Future[list[int]]] = [
            self.pool.submit(_worker, spec, first_worker + w) for w in range(k)]

    def done(self) -> bool:
        return all(f.done() for f in self.futures)

    def poll(self) -> int:
        if self._study is None:
            self._study = open_study(self.spec, create=False)[0]
        return counted(self._study)

    def error(self) -> str | None:
        """The first crash of a finished worker, as one line (None if none crashed)."""
        for f in self.futures:
            if f.done() and not f.cancelled() and f.exception() is not None:
                e = f.exception()
                return f"{type(e).__name__}: {e}".splitlines()[0]
        return None

    def results(self) -> list[list[int]]:
        """The trial numbers each worker ran (re-raises a worker's crash)."""
        return [f.result() for f in self.futures]

    def stop(self) -> None:
        """Stop starting trials: cancel what has not begun and end the processes."""
        for f in self.futures:
            f.cancel()
        for p in list(getattr(self.pool, "_processes", {}).values()):
            p.terminate()  # our own children only
        self.pool.shutdown(wait=True, cancel_futures=True)

    def close(self) -> None:
        self.pool.shutdown(wait=True)


def run_workers(spec: StudySpec, k: int, *, on_progress: Callable[[int], None] | None = None,
                interval: float = 0.5) -> list[list[int]]:
    """Run the study with `k` processes (in this process when k == 1) until it is full."""
    if k <= 1:
        return [run_worker(spec, 0, on_trial=on_progress)]
    workers = Workers(spec, k)
    try:
        while not workers.done():
            if on_progress is not None:
                on_progress(workers.poll())
            time.sleep(interval)
        return workers.results()
    except BaseException:
        workers.stop()
        raise
    finally:
        workers.close()
