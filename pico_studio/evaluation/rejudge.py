"""Re-judging a kept run with another config: the whole timeline re-perceived, re-localised
and re-scored, frame by frame, through the one loop.

    run = record_sim(sim, cfg, behaviour, seconds=120)          # the sensor stream, kept once
    run = record_replay(open_source("bag:x.bag", cfg.sources))  # ... or a whole recording
    judged = rejudge(run, cfg)                                  # Judged: per-frame series, totals
    judged.series["doors.recall"]                               # (N,) one value per scan, NaN
    judged.totals["perception_score"]                           #   where there is nothing to count

    worker = Rejudger(run, on_result=show, on_progress=bar)     # in the background:
    worker.submit(cfg_b)     # cancels a re-judge under way; results carry their generation
    worker = make_rejudger(run, workers=2, on_result=show)      # ... in two worker processes
    judged = rejudge(run, cfg, workers=2)                       # one re-judge in two processes

With `workers` > 1 the frames are perceived in one worker process while another localises and
scores them (`rejudge_worker`: the same answers; this process stays free); `workers=1` is this
process (the re-judge in the caller's thread, `Rejudger` in a thread of its own).

The sensor data of a `KeptRun` is fixed (the drive was recorded once), so two configs judged
on it differ only by what the perceptor and localisation make of the same scans. The run goes
through `Session` over a `sources.frames.FramesReplay` of the kept frames, with the truth of
each frame (a simulator's `kept_truth.TruthSnapshot`, or a recording's true pose) given to the
scorers as the frame comes.

The series and totals are `judging`'s (`SERIES` lists the series with their meaning).

**Bad input**: a config that fails validation is refused (`ConfigError` naming the field)
before anything is re-judged. A change arriving mid-re-judge cancels it: the worker checks
its generation between frames and a result is delivered only for the newest one, so old
and new results never mix.
"""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from collections.abc import Callable
from typing import Any

from pico_studio.config import Config
from pico_studio.core.io import Frame
from pico_studio.evaluation.frame_score import Tolerances
from pico_studio.evaluation.judging import (  # noqa: F401  (re-exported: `rejudge` is the module to use)
    SERIES,
    Cancelled,
    Features,
    Judged,
    Judging,
    KeptRun,
    NewestResult,
    Pose,
    Series,
    _pose,
    is_localising,
    judged_here,
    perceptor_for,
    validated,
)
from pico_studio.evaluation.metrics import METRICS
from pico_studio.session import Session, SessionFrame
from pico_studio.sources.frames import FramesReplay

log = logging.getLogger(__name__)

# ----- keeping a run ---------------------------------------------------------------------------


class RunKeeper:
    """A session observer keeping what a re-judge needs of a run as it goes: every frame and,
    with a simulator, the truth of every scan (`kept_truth.TruthSnapshot`); the newest
    `max_frames` of them when bounded (the page's timeline length).

        keeper = RunKeeper(sim)
        Session(sim, perceptor=p, behaviour=b, observers=[keeper]).run(60)
        run = keeper.kept(global_map, start)     # a KeptRun of what is kept now"""

    name = "kept_run"

    def __init__(self, sim: Any = None, max_frames: int | None = None):
        from pico_studio.evaluation.frame_score import static_vertices

        self.sim = sim
        self.vertices = static_vertices(sim) if sim is not None else None
        self._form = sim.params.odometry.form if sim is not None else ""
        self._kept: deque[tuple[Frame, Any]] = deque(maxlen=max_frames)
        self.seen = 0  # frames kept since the start (the index of the next one in the keeper's stream)

    def on_frame(self, sf: SessionFrame) -> None:
        from pico_studio.evaluation.kept_truth import TruthSnapshot

        truth = TruthSnapshot(self.sim.truth, self._form) if self.sim is not None and sf.frame.laser is not None else None
        self._kept.append((sf.frame, truth))
        self.seen += 1

    def __len__(self) -> int:
        return len(self._kept)

    def clear(self) -> None:
        self.seen += len(self._kept) + 1  # a later run shares no frames with an earlier one
        self._kept.clear()

    def kept(self, global_map: Any = None, initial_pose: Pose | None = None, name: str = "") -> KeptRun:
        """The frames kept now as a `KeptRun` (localised on `global_map` from `initial_pose`,
        default the first kept true pose, when a map is given). Its `origin` places its frames
        in this keeper's stream, so a worker holding an earlier snapshot needs only the new ones."""
        kept = list(self._kept)
        frames = [f for f, _ in kept]
        truth = {i: t for i, (_, t) in enumerate(kept) if t is not None} if self.sim is not None else None
        if global_map is not None and initial_pose is None:
            initial_pose = next((_pose(f.truth["pose"]) for f in frames if (f.truth or {}).get("pose") is not None),
                                None)
        return KeptRun(frames, truth, self.vertices, global_map, initial_pose if global_map is not None else None,
                       name=name, origin=(id(self), self.seen - len(kept)))

    def summary(self) -> dict[str, Any]:
        return {"frames": len(self._kept)}


def record_sim(sim: Any, cfg: Config, behaviour: Any, *, seconds: float, dt: float = 0.05,
               localise: bool = False, initial_pose: Pose | None = None, perceptor: Any = None,
               name: str = "simulation") -> KeptRun:
    """Drive `sim` with `behaviour` for `seconds` keeping every frame and the truth of every
    scan. Without a `perceptor` the drive does not depend on any config judged later; a
    behaviour that steers by the world model needs one (the drive then is that config's)."""
    keeper = RunKeeper(sim)
    start = _pose(sim.truth.pose) if initial_pose is None else initial_pose
    session = Session(sim, perceptor=perceptor, behaviour=behaviour, observers=[keeper])
    for _ in session.frames(until=sim.now() + seconds, dt=dt):
        if getattr(behaviour, "done", False):
            break
    return keeper.kept(sim.world.map if localise else None, start, name=name)


def record_replay(replay: Any, *, seconds: float | None = None, global_map: Any = None,
                  name: str = "") -> KeptRun:
    """Every frame of a recording (`sources.Replay`: a bag, a CARMEN log), up to `seconds`
    after its first; localised on `global_map` from the first true pose when both are there."""
    frames: list[Frame] = []
    t0 = None
    for i in range(replay.frame_count):
        f = replay.frame(i)
        t0 = f.time if t0 is None else t0
        if seconds is not None and f.time - t0 > seconds + 1e-9:
            break
        frames.append(f)
    start = next((_pose(f.truth["pose"]) for f in frames if (f.truth or {}).get("pose") is not None), None)
    return KeptRun(frames, None, None, global_map if start is not None else None,
                   start if global_map is not None else None, name=name)


# ----- judging ----------------------------------------------------------------------------------


def rejudge(run: KeptRun, cfg: Config, *, generation: int = 0, tol: Tolerances | None = None,
            cancelled: Callable[[], bool] | None = None,
            progress: Callable[[int, int], None] | None = None, progress_every: int = 100,
            partial: Callable[[Judged], None] | None = None, partial_seconds: float = 1.0,
            workers: int = 1) -> Judged:
    """Re-perceive, re-localise and re-score every frame of `run` with `cfg` (validated first).

    `cancelled()` is asked between frames; when true the judge stops with `Cancelled`.
    `progress(done, total)` is called every `progress_every` frames (ticks) and at the end;
    `partial(judged)` every `partial_seconds` with the series of the frames judged so far
    (`complete` False, no totals), so a long run's plots fill in as it goes.

    `workers` > 1: perceived in one worker process and scored in another at the same time
    (`rejudge_worker`; the same answers, the processes started for this call and stopped
    after it: to judge one run many times keep a `rejudge_worker.ProcessRejudger`)."""
    cfg = validated(cfg)
    if workers > 1:
        from pico_studio.evaluation.rejudge_worker import rejudge_in_workers

        return rejudge_in_workers(run, cfg, generation=generation, tol=tol, cancelled=cancelled, progress=progress,
                                  partial=partial, partial_seconds=partial_seconds)
    t0, c0 = time.perf_counter(), time.thread_time()
    replay = FramesReplay(run.frames)
    judging = Judging(run, cfg, tol, cursor=replay)
    session = Session(replay, perceptor=perceptor_for(run, cfg), observers=[judging.rows])
    total = len(run.frames)
    next_partial = t0 + partial_seconds
    for k, _ in enumerate(session.frames()):
        if cancelled is not None and cancelled():
            raise Cancelled
        if progress is not None and (k + 1) % progress_every == 0:
            progress(k + 1, total)
        if partial is not None and time.perf_counter() >= next_partial:
            partial(judging.partial(generation, time.perf_counter() - t0))
            next_partial = time.perf_counter() + partial_seconds
    if progress is not None:
        progress(total, total)
    return judging.finish(generation, time.perf_counter() - t0, time.thread_time() - c0)


def higher_is_better(name: str) -> bool:
    """Whether a larger value of total or series `name` is better (counts: neither; True)."""
    m = METRICS.get(name)
    if m is not None:
        return m.higher_is_better
    return not (name.endswith("error_m") or name.startswith("ms.") or name.endswith("lost")
                or name.endswith("ms_per_scan"))


# ----- in the background -----------------------------------------------------------------------


class Rejudger(NewestResult):
    """Re-judges a kept run in a background thread whenever `submit(cfg)` is called.

    A submit while a re-judge is under way cancels it (it stops at the next frame) and starts
    the new one: each submit takes the next *generation*; `on_result(judged)` is called only
    for a re-judge of the newest generation that ran to the end, and `on_progress(generation,
    done, total)` as it goes. `latest` is the newest finished `Judged`. A config that fails
    validation raises `ConfigError` from `submit` and cancels nothing."""

    def __init__(self, run: KeptRun, *, on_result: Callable[[Judged], None] | None = None,
                 on_progress: Callable[[int, int, int], None] | None = None,
                 on_error: Callable[[int, Exception], None] | None = None, tol: Tolerances | None = None,
                 on_partial: Callable[[Judged], None] | None = None):
        self.run = run
        self.on_result, self.on_progress, self.on_error = on_result, on_progress, on_error
        self.on_partial = on_partial
        self.tol = tol
        self.progress_every = 100  # frames between progress reports
        self.generation = 0
        self.latest: Judged | None = None
        self.running = False
        self._pending: Config | None = None
        self._cond = threading.Condition()
        self._closed = False
        self._thread = threading.Thread(target=self._loop, name="rejudge", daemon=True)
        self._thread.start()

    def submit(self, cfg: Config) -> int:
        """Queue `cfg` (validated now), cancelling a re-judge under way; its generation."""
        cfg = validated(cfg)
        with self._cond:
            self.generation += 1
            self._pending = cfg
            self._cond.notify_all()
            return self.generation

    def set_run(self, run: KeptRun) -> None:
        """Judge another kept run from the next submit on (a run under way is cancelled)."""
        with self._cond:
            self.run = run
            self.generation += 1
            self._pending = None
            self.latest = None
            self._cond.notify_all()

    def close(self) -> None:
        with self._cond:
            self._closed = True
            self.generation += 1
            self._cond.notify_all()
        self._thread.join(timeout=10.0)

    def _loop(self) -> None:
        while True:
            with self._cond:
                while self._pending is None and not self._closed:
                    self._cond.wait()
                if self._closed:
                    return
                cfg, gen, run = self._pending, self.generation, self.run
                self._pending = None
                self.running = True
            assert cfg is not None
            try:
                judged = rejudge(run, cfg, generation=gen, tol=self.tol,
                                 cancelled=lambda g=gen: self.generation != g,  # type: ignore[misc]
                                 progress=lambda d, t, g=gen: self._progress(g, d, t),  # type: ignore[misc]
                                 progress_every=self.progress_every,
                                 partial=self._partial if self.on_partial is not None else None)
            except Cancelled:
                continue
            except Exception as e:  # a bug in one config's run must not stop the worker
                with self._cond:
                    self.running = False
                _call(self.on_error, gen, e)
                continue
            finally:
                with self._cond:
                    self.running = self._pending is not None
            with self._cond:
                if gen != self.generation:  # overtaken after its last frame: drop it
                    continue
                self.latest = judged
                self._cond.notify_all()
            _call(self.on_result, judged)

    def _partial(self, judged: Judged) -> None:
        if self.on_partial is not None and judged.generation == self.generation:
            self.on_partial(judged)

    def _progress(self, gen: int, done: int, total: int) -> None:
        if self.on_progress is not None and gen == self.generation:
            self.on_progress(gen, done, total)


def _call(callback: Callable[..., None] | None, *args: Any) -> None:
    """A re-judger's callback, whose failure is logged and never ends the re-judger's thread
    (a thread that died would leave every later change unjudged)."""
    if callback is None:
        return
    try:
        callback(*args)
    except Exception:
        log.exception("a re-judge callback failed")


def make_rejudger(run: KeptRun, *, workers: int = 2, **kw: Any) -> Any:
    """A background re-judger of `run`: in worker processes (`ProcessRejudger`) when `workers`
    > 1, else a thread in this process (`rejudge.Rejudger`, as before)."""
    if workers > 1:
        from pico_studio.evaluation.rejudge_worker import ProcessRejudger

        return ProcessRejudger(run, **kw)
    kw.pop("partial_seconds", None)
    return Rejudger(run, **kw)
