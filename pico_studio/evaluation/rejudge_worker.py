"""Re-judging in worker processes: the page's process stays free, and both cores work.

    worker = ProcessRejudger(run, on_result=show, on_progress=bar)   # starts two processes
    worker.submit(cfg_b)       # as `rejudge.Rejudger`: cancels a re-judge under way
    worker.wait()              # the newest generation's `Judged`, the same as `rejudge(run, cfg_b)`
    worker.close()

One re-judge is a pipeline over two spawned processes (the 'spawn' context: no forked copy of
the page's threads and sockets):

    page ──run (once), config per change──▶ perceiver ──per scan: a slim world model──▶ scorer
      ▲                               (perceive, sequential over frames)   (localise, score) │
      └──────── progress, partial series, the judged run (compact numpy arrays) ───────────┘

The perceptor is sequential over frames, but nothing it does depends on what comes after it:
localisation reads the world model and never feeds back into the perceptor, and scoring a
frame needs only its world model and its truth. So the scorer process localises and scores
frame k while the perceiver perceives frame k + 1, and a re-judge takes about as long as
perceiving alone (the same answers: `tests/test_rejudge.py` compares every series, total and
feature with `rejudge` in one process). The kept frames (laser, odometry) and, for the
scorer, the kept truth are pickled once per run and sent to both processes (the scorer's
through the perceiver, so they arrive before the first config judged on them); a change
sends only the config. A later snapshot of the same timeline (the page's simulation, grown
or slid on) sends only its new frames (`extension`). Each process warms the numba cache
(`jit.warm_up`) and loads the page's plugins once, when it starts.

**Generations** as in `Rejudger`: `submit` takes the next one and writes it to a value shared
with the processes; the perceiver checks it between frames and stops a stale re-judge at once
(the processes stay up, with the run), the scorer drops a stale one's rows, and this side
delivers only results of the newest generation, so old and new never mix.

**A process that dies** (killed, out of memory) is noticed by its sentinel: `on_error` is called
with `WorkerDied` naming it and its exit code, the other one is stopped, and the next `submit`
starts both afresh (sending the run again). A config that fails validation is refused by
`submit` (`ConfigError` naming the field) before anything is sent.
"""

from __future__ import annotations

import logging
import math
import multiprocessing
import pickle
import threading
import time
from collections.abc import Callable
from dataclasses import replace
from multiprocessing.connection import Connection, wait
from typing import Any

from pico_studio.config import Config, from_dict, to_dict
from pico_studio.core.world_model import LocalMap, WorldModel
from pico_studio.evaluation.frame_score import Tolerances
from pico_studio.evaluation.judging import (
    Cancelled,
    Features,
    Judged,
    Judging,
    KeptRun,
    NewestResult,
    is_localising,
    validated,
)
from pico_studio.session import Session, SessionFrame
from pico_studio.sources.frames import FramesReplay

log = logging.getLogger(__name__)
BATCH = 16  # world models per message from the perceiver to the scorer (fewer, larger sends)


class WorkerDied(RuntimeError):
    """A re-judging worker process ended without being asked to."""


class RejudgeFailed(RuntimeError):
    """A re-judge raised in a worker process (the message is the worker's exception)."""


# ----- what goes between the processes -----------------------------------------------------------


def run_bytes(run: KeptRun) -> tuple[bytes, bytes]:
    """`run` pickled for the workers, once per run (kept on the run: A's and B's workers share
    it): the perceiver's (the frames alone) and the scorer's (the frames, the kept truth, the map
    to localise on). The distance field stays behind: the scorer builds its own, once per run."""
    if run._blob is None:
        perceiving = KeptRun(run.frames, name=run.name)
        judging = replace(run, _dfield=None, _dfield_key=None, _blob=None)
        run._blob = (pickle.dumps(perceiving, protocol=pickle.HIGHEST_PROTOCOL),
                     pickle.dumps(judging, protocol=pickle.HIGHEST_PROTOCOL))
    return run._blob


def extension(sent: KeptRun | None, run: KeptRun) -> tuple[int, int] | None:
    """(frames of `sent` gone from the front, frames of `run` the workers have already) when
    `run` is a later snapshot of the same `RunKeeper` as `sent` (a timeline that grew or slid
    on: `KeptRun.origin`, the same frame objects), else None: send it whole."""
    if sent is None or run.origin is None or sent.origin is None or run.origin[0] != sent.origin[0]:
        return None
    drop = run.origin[1] - sent.origin[1]
    have = len(sent.frames) - drop
    if drop < 0 or not 0 < have <= len(run.frames) or run.frames[have - 1] is not sent.frames[-1]:
        return None
    return drop, have


def extension_bytes(sent: KeptRun, run: KeptRun, have: int) -> tuple[bytes, bytes]:
    """What the workers need to turn `sent` into `run`: the perceiver's new frames, and the
    scorer's new frames with their truth, and the rest of the run (the map only when it changed)."""
    new = run.frames[have:]
    truth = None if run.truth is None else {i - have: t for i, t in run.truth.items() if i >= have}
    same_map = run.global_map is sent.global_map
    scorer = {"frames": new, "truth": truth, "vertices": run.vertices, "initial_pose": run.initial_pose,
              "name": run.name, "origin": run.origin, "same_map": same_map,
              "global_map": None if same_map else run.global_map}
    return (pickle.dumps(new, protocol=pickle.HIGHEST_PROTOCOL),
            pickle.dumps(scorer, protocol=pickle.HIGHEST_PROTOCOL))


def _extended(old: KeptRun, drop: int, ext: dict[str, Any]) -> KeptRun:
    """The scorer's run slid on: `old` without its first `drop` frames, plus the new ones."""
    have = len(old.frames) - drop
    truth = None
    if ext["truth"] is not None:
        truth = {i - drop: t for i, t in (old.truth or {}).items() if i >= drop}
        truth.update({have + j: t for j, t in ext["truth"].items()})
    run = KeptRun(old.frames[drop:] + ext["frames"], truth, ext["vertices"],
                  old.global_map if ext["same_map"] else ext["global_map"], ext["initial_pose"], name=ext["name"],
                  origin=ext["origin"])
    if ext["same_map"]:  # the distance field stays valid
        run._dfield, run._dfield_key = old._dfield, old._dfield_key
    return run


def _slim(wm: WorldModel, points: bool) -> tuple[Any, ...]:
    """What localising and scoring read of a world model (a fraction of pickling it whole):
    `Localiser.fill` (scan points, pose, local map, doors), `Judging`'s series, the truth
    scorer and the agreement (points only when one of them needs them)."""
    return (wm.time, wm.pose, wm.zero_pose, wm.local_map.walls, wm.local_map.endpoint_property, wm.corners,
            wm.corner_convex, wm.doors, wm.possible_doors, wm.possible_door_kind, wm.global_pose,
            wm.localisation_quality, wm.lost, wm.timings_ms, wm.points if points else None)


def _unslim(t: tuple[Any, ...]) -> WorldModel:
    (time_, pose, zero, walls, props, corners, convex, doors, possible, kinds, global_pose, quality, lost, ms,
     pts) = t
    wm = WorldModel(time=time_, pose=pose, zero_pose=zero, local_map=LocalMap(walls, props), corners=corners,
                    corner_convex=convex, doors=doors, possible_doors=possible, possible_door_kind=kinds,
                    global_pose=global_pose, localisation_quality=quality, lost=lost, timings_ms=ms)
    if pts is not None:
        wm.points = pts
    return wm


def _packed(judged: Judged) -> Judged:
    """`judged` as it is sent back: features as a few packed arrays, no config (the page has it)."""
    feats = judged.features if isinstance(judged.features, Features) else Features.pack(judged.features)
    return replace(judged, features=feats, config=None)


# ----- the processes -----------------------------------------------------------------------------


def _start_process(plugin_specs: list[str]) -> None:
    """Once per worker process: the page's plugins (a config may name their stages), and the
    compiled kernels loaded from the numba cache (not on the first frame of the first judge)."""
    from pico_studio import plugins
    from pico_studio.jit import warm_up

    plugins.load_plugins(plugin_specs)
    warm_up()


def _config(tree: dict[str, Any], plugin_specs: list[str]) -> Config:
    """The config sent as its plain tree (a plugin's section class is rebuilt when the plugin
    loads, so it does not pickle): the page's plugins loaded first, then the tree read as the
    page validated it (`rejudge.validated`: the same round trip, the same config)."""
    from pico_studio import plugins

    plugins.load_plugins(plugin_specs)  # any loaded on the page since this process started
    return from_dict(Config, tree)


def _perceiver_main(commands: Connection, out: Connection, generation: Any, plugin_specs: list[str]) -> None:
    """Perceive (and localise) every kept frame with each config asked for; the world models
    of new scans go to the scorer in batches."""
    _start_process(plugin_specs)
    run: KeptRun | None = None
    try:
        while True:
            msg = commands.recv()
            if msg[0] == "stop":
                out.send(("stop",))
                return
            if msg[0] == "run":  # its own frames, then the scorer's run, passed on (in order before
                run = pickle.loads(commands.recv_bytes())  # the first config judged on it)
                out.send(("run", msg[1]))
                out.send_bytes(commands.recv_bytes())
                continue
            if msg[0] == "extend":  # the same timeline slid on: only its new frames
                assert run is not None
                run = KeptRun(run.frames[msg[2]:] + pickle.loads(commands.recv_bytes()), name=run.name)
                out.send(msg)
                out.send_bytes(commands.recv_bytes())
                continue
            _, gen, tree, specs, progress_every = msg
            if gen != generation.value or run is None:
                continue  # overtaken before it started
            out.send(("start", gen, tree, specs, progress_every))
            try:
                _perceive(run, _config(tree, specs), gen, out, generation)
            except Exception as e:  # a bug in one config's run must not stop the worker
                out.send(("error", gen, f"{type(e).__name__}: {e}"))
    except (EOFError, BrokenPipeError, OSError):
        return  # the page or the scorer went away


def _perceive(run: KeptRun, cfg: Config, gen: int, out: Connection, generation: Any) -> None:
    """The perceptor alone over the kept frames (the scorer localises: localisation reads the
    world model and never feeds back into the perceptor, so it can run beside it)."""
    from pico_studio.evaluation.runner import make_perceptor

    c0 = time.process_time()
    replay = FramesReplay(run.frames)
    session = Session(replay, perceptor=make_perceptor(cfg))
    points = is_localising(run, cfg) or (run.has_true_pose and not run.truth)  # localising, the agreement
    batch: list[tuple[int, int, tuple[Any, ...] | None]] = []
    last: Any = None
    k = -1
    for k, sf in enumerate(session.frames()):
        if generation.value != gen:
            out.send(("cancelled", gen))
            return
        if sf.frame.laser is None or sf.world_model is None:
            continue
        # a new scan was perceived: a new world model, or (a failed step) the previous one again,
        # which is localised again as `LocalisingPerceptor` does, but makes no new row
        batch.append((k, replay.index, _slim(sf.world_model, points) if sf.world_model is not last else None))
        last = sf.world_model
        if len(batch) >= BATCH:
            out.send(("rows", gen, k, batch))
            batch = []
    out.send(("rows", gen, k, batch))
    out.send(("end", gen, time.process_time() - c0))


def _scorer_main(inp: Connection, results: Connection, generation: Any, tol: Tolerances | None,
                 partial_seconds: float, plugin_specs: list[str]) -> None:
    """Score the perceiver's world models as they come; progress, partial series and the
    judged run go back to the page."""
    _start_process(plugin_specs)
    run: KeptRun | None = None
    job: _Job | None = None
    try:
        while True:
            msg = inp.recv()
            kind = msg[0]
            if kind == "stop":
                return
            if kind == "run":
                run = pickle.loads(inp.recv_bytes())
                job = None
                continue
            if kind == "extend":
                assert run is not None
                run = _extended(run, msg[2], pickle.loads(inp.recv_bytes()))
                job = None
                continue
            if kind == "start":
                assert run is not None
                try:
                    job = _Job(run, msg[1], _config(msg[2], msg[3]), tol, msg[4], partial_seconds)
                except Exception as e:
                    results.send(("error", msg[1], f"{type(e).__name__}: {e}"))
                continue
            if job is None or msg[1] != job.gen:
                continue
            if generation.value != job.gen:  # overtaken: the perceiver stops too
                job = None
                continue
            if kind == "rows":
                job.rows(msg[2], msg[3], results)
            elif kind == "end":
                results.send(("progress", job.gen, job.total, job.total))
                results.send(("result", job.gen, _packed(job.finish(msg[2]))))
                job = None
            elif kind == "error":
                results.send(("error", job.gen, msg[2]))
                job = None
            else:  # "cancelled"
                job = None
    except (EOFError, BrokenPipeError, OSError):
        return  # the perceiver (or the page) went away


def _localiser(run: KeptRun, cfg: Config) -> Any:
    """The localisation stage `perceptor_for` would wrap round the perceptor."""
    from pico_studio.core.localisation import Localiser

    return Localiser(cfg.localisation, run.global_map, run.initial_pose, run.distance_field(cfg))


class _Job:
    """The scorer's side of one generation."""

    def __init__(self, run: KeptRun, gen: int, cfg: Config, tol: Tolerances | None, progress_every: int,
                 partial_seconds: float):
        self.run, self.gen = run, gen
        self.judging = Judging(run, cfg, tol)
        self.localiser = _localiser(run, cfg) if self.judging.localising else None
        self.last: WorldModel | None = None
        self.total = len(run.frames)
        self.progress_every = max(int(progress_every), 1)
        self.partial_seconds = partial_seconds
        self.t0, self.c0 = time.perf_counter(), time.process_time()
        self.next_progress = self.progress_every
        self.next_partial = self.t0 + partial_seconds

    def rows(self, tick: int, batch: list[tuple[int, int, tuple[Any, ...] | None]], results: Connection) -> None:
        cursor, frames, on_frame = self.judging.cursor, self.run.frames, self.judging.rows.on_frame
        for k, index, slim in batch:
            cursor.index = index
            wm = self.last if slim is None else _unslim(slim)
            if self.localiser is not None:
                self.localiser.fill(wm)
            self.last = wm
            on_frame(SessionFrame(k, frames[index], wm, None))
        done = tick + 1
        if done >= self.next_progress and done < self.total:
            results.send(("progress", self.gen, done - done % self.progress_every, self.total))
            self.next_progress = done - done % self.progress_every + self.progress_every
        if time.perf_counter() >= self.next_partial:
            results.send(("partial", self.gen, _packed(self.judging.partial(self.gen, time.perf_counter() - self.t0))))
            self.next_partial = time.perf_counter() + self.partial_seconds

    def finish(self, perceiver_cpu: float) -> Judged:
        mine = time.process_time() - self.c0
        judged = self.judging.finish(self.gen, time.perf_counter() - self.t0, perceiver_cpu + mine)
        return replace(judged, cpu_parts=(perceiver_cpu, mine))


# ----- the page's side ---------------------------------------------------------------------------


class ProcessRejudger(NewestResult):
    """`rejudge.Rejudger`'s interface (`submit`, `set_run`, `wait`, `close`, `latest`,
    `generation`, `running`, `progress_every`), judging in two worker processes (see the module
    doc). The callbacks are called from this side's reader thread."""

    def __init__(self, run: KeptRun, *, on_result: Callable[[Judged], None] | None = None,
                 on_progress: Callable[[int, int, int], None] | None = None,
                 on_error: Callable[[int, Exception], None] | None = None, tol: Tolerances | None = None,
                 on_partial: Callable[[Judged], None] | None = None, partial_seconds: float = 1.0):
        self.run = run
        self.on_result, self.on_progress, self.on_error = on_result, on_progress, on_error
        self.on_partial = on_partial
        self.tol = tol
        self.partial_seconds = partial_seconds if on_partial is not None else math.inf
        self.progress_every = 100  # frames between progress reports
        self.generation = 0
        self.latest: Judged | None = None
        self.failed: tuple[int, Exception] | None = None  # the newest failure: (generation, why)
        self.running = False
        self._ctx = multiprocessing.get_context("spawn")
        self._shared = self._ctx.RawValue("q", 0)  # the newest generation, read by the processes
        self._cond = threading.Condition()
        self._pending: tuple[int, Config] | None = None
        self._jobs: dict[int, tuple[Config, float]] = {}  # generation -> (config, when submitted)
        self._procs: tuple[Any, Any] | None = None
        self._commands: Connection | None = None
        self._run_sent: KeptRun | None = None
        self.sent = {"whole": 0, "extend": 0}  # how runs went to the processes: whole, or the new frames
        self._closed = False
        self._start()
        self._sender = threading.Thread(target=self._send_loop, name="rejudge-send", daemon=True)
        self._sender.start()

    @property
    def pids(self) -> tuple[int, int] | None:
        """(perceiver, scorer) process ids, None while none are running."""
        procs = self._procs
        return (procs[0].pid, procs[1].pid) if procs is not None else None

    # ----- the processes --------------------------------------------------------------------
    def _start(self) -> None:
        from pico_studio import plugins

        ctx, specs = self._ctx, plugins.specs()
        commands_in, commands = ctx.Pipe(duplex=False)
        rows_in, rows_out = ctx.Pipe(duplex=False)
        results_in, results_out = ctx.Pipe(duplex=False)
        perceiver = ctx.Process(target=_perceiver_main, args=(commands_in, rows_out, self._shared, specs),
                                name="pico_studio-rejudge-perceive", daemon=True)
        scorer = ctx.Process(target=_scorer_main,
                             args=(rows_in, results_out, self._shared, self.tol, self.partial_seconds, specs),
                             name="pico_studio-rejudge-score", daemon=True)
        perceiver.start()
        scorer.start()
        for end in (commands_in, rows_out, rows_in, results_out):  # the children hold these now: an
            end.close()  # end closed by a dying process is then seen as EOF by the other
        self._procs, self._commands, self._run_sent = (perceiver, scorer), commands, None
        threading.Thread(target=self._read_loop, args=(results_in, perceiver, scorer), name="rejudge-read",
                         daemon=True).start()

    def _stop_processes(self, procs: tuple[Any, Any], seconds: float = 1.0) -> None:
        """Join both within `seconds` (they were asked to stop), then terminate what is left (a
        process still loading its kernels reads the stop only when done: no need to wait)."""
        end = time.monotonic() + seconds
        for p in procs:
            p.join(timeout=max(0.0, end - time.monotonic()))
        for p in procs:
            if p.is_alive():
                p.terminate()
                p.join(timeout=2.0)

    # ----- Rejudger's interface -------------------------------------------------------------
    def submit(self, cfg: Config) -> int:
        """Queue `cfg` (validated now), cancelling a re-judge under way; its generation."""
        cfg = validated(cfg)
        with self._cond:
            self.generation += 1
            self._shared.value = self.generation  # the processes stop the one under way now
            self._pending = (self.generation, cfg)
            self._jobs = {self.generation: (cfg, time.perf_counter())}
            self.running = True
            self._cond.notify_all()
            return self.generation

    def set_run(self, run: KeptRun) -> None:
        """Judge another kept run from the next submit on (a run under way is cancelled)."""
        with self._cond:
            self.run = run
            self.generation += 1
            self._shared.value = self.generation
            self._pending = None
            self._jobs.clear()
            self.latest = None
            self.running = False
            self._cond.notify_all()

    def close(self) -> None:
        with self._cond:
            self._closed = True
            self.generation += 1
            self._shared.value = self.generation
            self._cond.notify_all()
            procs, commands = self._procs, self._commands
            self._procs = self._commands = None
        self._sender.join(timeout=10.0)
        if commands is not None:
            try:
                commands.send(("stop",))
            except OSError:
                pass
            commands.close()
        if procs is not None:
            self._stop_processes(procs)

    def result(self, gen: int, timeout: float | None = None,
               cancelled: Callable[[], bool] | None = None) -> Judged:
        """The judged run of generation `gen` (headless use: `compare`, `rejudge(workers=2)`):
        blocks until it is in; raises its failure (`RejudgeFailed`, `WorkerDied`), `Cancelled`
        when `cancelled()` turns true or a newer generation overtook it, TimeoutError after
        `timeout` s."""
        end = math.inf if timeout is None else time.monotonic() + timeout
        while True:
            judged = self.wait(gen, timeout=0.05)
            if judged is not None:
                if judged.generation != gen:
                    raise Cancelled
                return judged
            failed = self.failed
            if failed is not None and failed[0] == gen:
                raise failed[1]
            if (cancelled is not None and cancelled()) or self.generation != gen:
                raise Cancelled
            if time.monotonic() > end:
                raise TimeoutError(f"re-judging took over {timeout} s")

    # ----- threads --------------------------------------------------------------------------
    def _send_loop(self) -> None:
        """Sends the newest config (and the run first, when it is new to the processes)."""
        from pico_studio import plugins

        while True:
            with self._cond:
                while self._pending is None and not self._closed:
                    self._cond.wait()
                if self._closed:
                    return
                assert self._pending is not None
                (gen, cfg), run = self._pending, self.run
                self._pending = None
                if self._procs is None:
                    self._start()
                commands, sent, fresh = self._commands, self._run_sent, self._run_sent is not run
                self._run_sent = run
            assert commands is not None
            try:
                slid = extension(sent, run) if fresh else None
                if slid is not None:
                    assert sent is not None
                    perceiving, judging = extension_bytes(sent, run, slid[1])
                    commands.send(("extend", id(run), slid[0]))
                    self.sent["extend"] += 1
                elif fresh:
                    perceiving, judging = run_bytes(run)
                    commands.send(("run", id(run)))
                    self.sent["whole"] += 1
                if fresh:
                    commands.send_bytes(perceiving)
                    commands.send_bytes(judging)
                commands.send(("judge", gen, to_dict(cfg), plugins.specs(), self.progress_every))
            except OSError:
                pass  # the processes died: the reader reports it; the next submit starts them again

    def _read_loop(self, results: Connection, perceiver: Any, scorer: Any) -> None:
        while True:
            ready = wait([results, perceiver.sentinel, scorer.sentinel])
            if results in ready:
                try:
                    msg = results.recv()
                except (EOFError, OSError):
                    msg = None
                if msg is not None:
                    try:
                        self._dispatch(msg)
                    except Exception:  # a callback failing must not end the reader (nor the judging)
                        log.exception("a re-judge callback failed")
                    continue
            results.close()
            self._died(perceiver, scorer)
            return

    def _died(self, perceiver: Any, scorer: Any) -> None:
        with self._cond:
            if self._closed or self._procs is None or self._procs[0] is not perceiver:
                return  # closed, or already replaced
            self._procs, self._commands, self._run_sent = None, None, None
            gen, was_running = self.generation, self.running
            self.running = False
            self._jobs.clear()
            self._cond.notify_all()
        for p in (perceiver, scorer):
            if p.is_alive():
                p.terminate()
        self._stop_processes((perceiver, scorer))
        dead = [f"{p.name} (pid {p.pid}, exit code {p.exitcode})" for p in (perceiver, scorer) if p.exitcode]
        err = WorkerDied(f"the re-judging worker {' and '.join(dead) or 'process'} stopped"
                         + (" mid-re-judge" if was_running else "") + "; the next change starts a new one")
        self.failed = (gen, err)
        if self.on_error is not None:
            try:
                self.on_error(gen, err)
            except Exception:
                log.exception("a re-judge callback failed")

    def _dispatch(self, msg: tuple[Any, ...]) -> None:
        kind, gen = msg[0], msg[1]
        with self._cond:
            job = self._jobs.get(gen) if gen == self.generation else None
        if job is None:
            return  # a stale generation's: never shown with the newest
        cfg, submitted = job
        if kind == "progress":
            if self.on_progress is not None:
                self.on_progress(gen, msg[2], msg[3])
        elif kind == "partial":
            if self.on_partial is not None:
                self.on_partial(replace(msg[2], config=cfg))
        elif kind == "result":
            judged = replace(msg[2], config=cfg, seconds=time.perf_counter() - submitted)
            with self._cond:
                if gen != self.generation:  # overtaken while it came: drop it
                    return
                self.latest = judged
                self.running = False
                self._jobs.pop(gen, None)
                self._cond.notify_all()
            if self.on_result is not None:
                self.on_result(judged)
        elif kind == "error":
            with self._cond:
                self.running = False
                self._jobs.pop(gen, None)
                self._cond.notify_all()
            self.failed = (gen, RejudgeFailed(msg[2]))
            if self.on_error is not None:
                self.on_error(gen, self.failed[1])


def rejudge_in_workers(run: KeptRun, cfg: Config, *, generation: int = 0, tol: Tolerances | None = None,
                       cancelled: Callable[[], bool] | None = None,
                       progress: Callable[[int, int], None] | None = None,
                       partial: Callable[[Judged], None] | None = None, partial_seconds: float = 1.0) -> Judged:
    """`rejudge(run, cfg, workers=2)`: one re-judge in two processes started for it."""
    worker = ProcessRejudger(run, tol=tol, on_progress=(lambda g, d, t: progress(d, t)) if progress is not None else None,
                             on_partial=partial, partial_seconds=partial_seconds)
    try:
        return replace(worker.result(worker.submit(cfg), cancelled=cancelled), generation=generation)
    finally:
        worker.close()
