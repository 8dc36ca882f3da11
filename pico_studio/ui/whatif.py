"""The page's what-if state, without viser: the whole run re-judged on every change, and A/B.

    w = WhatIf(studio, on_update=redraw)
    w.changed()            # a parameter changed: re-judge the whole run with studio.cfg (as B)
    w.pin_a()              # keep the current config (and its judged run) as A
    w.set_b(cfg)           # B = cfg: the studio takes it, the run is re-judged (the Tune tab's
                           #   "apply as B"; `StudioApp.set_b` also moves the sliders)
    w.swap(); w.drop_a()
    w.a, w.b               # Side(config, judged) or None; judged: rejudge.Judged
    w.table()              # [(metric, a, b, b - a)] of the whole-run totals
    w.overlay(frame)       # what B adds / loses against A at a shown frame, in the map frame

The run judged is the studio's *kept run*: the whole recording for a replay (read once), the
frames the simulator's timeline keeps (with their truth) for a simulation — snapshotted when
a change arrives, so A and B are judged on exactly the same frames. Re-judging runs in the
background, one re-judger for B and one for A: with `workers` > 1 (the default) each is a pair
of worker processes (`rejudge_worker.ProcessRejudger`: perceiving in one, localising and
scoring in the other), so the page's process (viser, the live loop) keeps its core and A and B
are judged at once; `workers=1` judges in threads of this process (`rejudge.Rejudger`). A
newer change cancels an older one, and results of an older run snapshot are dropped, so
nothing old and new is ever mixed. A worker process that dies is reported (`error`) and the
next change starts a new one.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from pico_studio.config import Config, dump_yaml
from pico_studio.core.geometry import compose, invert, transform_points, transform_segments
from pico_studio.evaluation.diff import WorldDiff, diff_arrays
from pico_studio.evaluation.rejudge import Judged, KeptRun, RunKeeper, make_rejudger, record_replay

log = logging.getLogger(__name__)
Pose = tuple[float, float, float]


@dataclass
class Side:
    """One side of the comparison: its config and its judged run (None while being judged)."""

    config: Config
    judged: Judged | None = None
    run_id: int = -1  # the run snapshot `judged` is of
    waiting: bool = False  # a re-judge of this side is asked for and not in yet
    partial: Judged | None = None  # while waiting: the frames of the new re-judge judged so far

    @property
    def shown(self) -> Judged | None:
        """What the plots show: the re-judge under way so far, else the last complete one."""
        return self.partial if self.waiting and self.partial is not None else self.judged


class WhatIf:
    def __init__(self, studio: Any, on_update: Callable[[], None] | None = None, workers: int = 2):
        self.studio = studio
        self.workers = workers  # > 1: each side judged in worker processes; 1: in this process
        self.on_update = on_update or (lambda: None)
        self.a: Side | None = None
        self.b = Side(studio.cfg)
        self.progress: tuple[int, int] = (0, 0)  # (done, total) of B's re-judge under way
        self.error: str = ""
        self._lock = threading.RLock()
        self._run: KeptRun | None = None
        self._run_id = 0
        self._run_key: Any = None
        self._workers: dict[str, Any] = {}  # side -> Rejudger or ProcessRejudger
        self._pending: dict[str, tuple[int, int]] = {}  # side -> (generation, run id) asked for
        self.keeper: RunKeeper | None = None

    # ----- the run ------------------------------------------------------------------------------
    def attach(self) -> None:
        """Keep the studio's run from its next reset on (a new source, a new keeper), and now."""
        s = self.studio
        s.observer_factories.append(self._make_keeper)
        keeper = self._make_keeper(s)
        if keeper is not None:
            s.session.observers.append(keeper)
        self._worker("b")  # started (and its compiled kernels loaded) before the first change

    def _make_keeper(self, s: Any) -> Any:
        """A fresh `RunKeeper` for the studio's new source (none for a replay: it is read whole)."""
        with self._lock:
            if hasattr(s.source, "frame_count"):  # a seek restarts the replay: the same run
                self.keeper = None
                return _Nothing()
            self._run, self._run_key = None, None
            sim = s.source if getattr(s.bundle, "kind", "") == "sim" and hasattr(s.source, "truth") else None
            ui = s.cfg.ui
            self.keeper = RunKeeper(sim, max_frames=max(1, round(ui.timeline_seconds * ui.rate_hz)))
            return self.keeper

    def kept_run(self) -> KeptRun:
        """The run to judge now (a new snapshot when the kept frames changed)."""
        s = self.studio
        with self._lock:
            if hasattr(s.source, "frame_count"):  # a recording: all of it, read once
                key: Any = ("replay", str(getattr(s.source, "name", id(s.source))), s.source.frame_count,
                            self._localising_map() is not None)
                if self._run_key != key:
                    self._new_run(record_replay(s.source, global_map=self._localising_map(), name=s.map_name), key)
            else:
                n = self.keeper.seen if self.keeper is not None else 0  # grown, or slid on once full
                key = ("live", id(self.keeper), n, id(s.global_map), self._localising_map() is not None)
                if self._run_key != key:
                    run = self.keeper.kept(self._localising_map()) if self.keeper is not None else KeptRun([])
                    self._new_run(run, key)
            assert self._run is not None
            return self._run

    def _localising_map(self) -> Any:
        m = self.studio.global_map
        return m if m is not None and len(m.walls) and self.studio.cfg.localisation.enabled else None

    def _new_run(self, run: KeptRun, key: Any) -> None:
        old = self._run
        if old is not None and old.global_map is run.global_map:  # the distance field stays valid
            run._dfield, run._dfield_key = old._dfield, old._dfield_key
        self._run, self._run_key = run, key
        self._run_id += 1

    # ----- changes --------------------------------------------------------------------------
    def changed(self) -> None:
        """The studio's config changed (or the run grew): re-judge B, and A on a new snapshot."""
        self._judge("b", self.studio.cfg)

    def set_b(self, cfg: Config) -> None:
        """Make `cfg` the current config (B): the studio takes it; the run is re-judged."""
        self.studio.set_config(cfg)
        self.changed()

    def pin_a(self) -> None:
        """Keep the current config as A (with its judged run, when it is of this snapshot)."""
        cfg = self.studio.cfg
        with self._lock:
            judged = self.b.judged if self.b.judged is not None and self.b.judged.config == cfg else None
            self.a = Side(cfg, judged, self.b.run_id)
        if judged is None or self.a.run_id != self._run_id or self.b.waiting:
            self._judge("a", cfg)
        self.on_update()

    def drop_a(self) -> None:
        with self._lock:
            self.a = None
        self.on_update()

    def swap(self) -> None:
        """A becomes the current config (B) and B is pinned as A."""
        with self._lock:
            if self.a is None:
                return
            a, b = self.a, self.b
            self.a, self.b = Side(b.config, b.judged, b.run_id), Side(a.config, a.judged, a.run_id)
            # the workers' pending re-judges belong to the other side now: judge both afresh
            self._pending.clear()
        self.studio.set_config(self.b.config)
        if self.a.waiting or self.b.waiting:
            self.a.waiting = self.b.waiting = False
            self.changed()
            self._judge("a", self.a.config)
        self.on_update()

    def export(self, side: str) -> str:
        """The YAML of side "a" or "b"."""
        chosen = self.a if side == "a" else self.b
        if chosen is None:
            raise ValueError("no config A pinned")
        return dump_yaml(chosen.config)

    def _judge(self, side: str, cfg: Config) -> None:
        run = self.kept_run()
        with self._lock:
            run_id = self._run_id
            target = self.b if side == "b" else self.a
            if target is None:
                return
            if side == "b":
                self.b = Side(cfg, self.b.judged if self.b.run_id == run_id and self.b.config == cfg else None,
                              self.b.run_id)
                target = self.b
            worker = self._worker(side)
        if worker.run is not run:
            worker.set_run(run)
        gen = worker.submit(cfg)  # a ConfigError (bad value) names the field; nothing is judged
        with self._lock:
            self._pending[side] = (gen, run_id)
            target.waiting = True
        if side == "b" and self.a is not None and self.a.run_id != run_id:
            self._judge("a", self.a.config)  # A on the same frames as B

    def _worker(self, side: str) -> Any:
        w = self._workers.get(side)
        if w is None:
            w = make_rejudger(KeptRun([]), workers=self.workers,
                              on_result=lambda j, s=side: self._on_result(s, j),  # type: ignore[misc]
                              on_progress=lambda g, d, t, s=side: self._on_progress(s, g, d, t),  # type: ignore[misc]
                              on_error=lambda g, e, s=side: self._on_error(s, g, e),  # type: ignore[misc]
                              on_partial=(lambda j: self._on_partial(j)) if side == "b" else None)
            self._workers[side] = w
        return w

    def _on_result(self, side: str, judged: Judged) -> None:
        with self._lock:
            gen, run_id = self._pending.get(side, (-1, -1))
            if judged.generation != gen:
                return
            target = self.b if side == "b" else self.a
            if target is None:
                return
            target.judged, target.run_id, target.waiting, target.partial = judged, run_id, False, None
            if side == "b":
                self.progress = (self.progress[1], self.progress[1])
            self.error = ""
        self.on_update()

    def _on_partial(self, judged: Judged) -> None:
        with self._lock:
            gen, _ = self._pending.get("b", (-1, -1))
            if judged.generation != gen or not self.b.waiting:
                return
            self.b.partial = judged
        self.on_update()

    def _on_progress(self, side: str, gen: int, done: int, total: int) -> None:
        if side == "b":
            self.progress = (done, total)

    def _on_error(self, side: str, gen: int, e: Exception) -> None:
        log.warning("re-judging %s failed: %s", side, e)
        with self._lock:
            self.error = f"re-judging {side.upper()} failed: {type(e).__name__}: {e}"
            target = self.b if side == "b" else self.a
            if target is not None and self._pending.get(side, (-1, -1))[0] == gen:
                target.waiting, target.partial = False, None  # the last complete judge stays shown
        self.on_update()

    def wait(self, timeout: float = 60.0) -> bool:
        """Block until B (and A, when pinned) are judged on the newest snapshot (tests, bench)."""
        import time

        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if self.settled():
                return True
            time.sleep(0.02)
        return self.settled()

    def settled(self) -> bool:
        with self._lock:
            sides = [self.b] + ([self.a] if self.a is not None else [])
            if self.b.judged is not None and self.b.judged.config != self.studio.cfg:
                return False  # the current config is not judged yet (its change is on its way)
            return all(s.judged is not None and not s.waiting and s.run_id == self._run_id for s in sides)

    def close(self) -> None:
        with self._lock:
            workers = list(self._workers.values())
            self._workers.clear()
            self._pending.clear()
        for w in workers:
            w.close()

    def set_workers(self, workers: int) -> None:
        """Judge in `workers` processes (1: threads of this process) from the next change on."""
        self.close()
        with self._lock:
            self.workers = workers
            for side in (self.a, self.b):
                if side is not None:
                    side.waiting, side.partial = False, None

    # ----- what the page shows ------------------------------------------------------------------
    @property
    def comparable(self) -> bool:
        """A and B both judged on the same frames."""
        a, b = self.a, self.b
        return a is not None and a.judged is not None and b.judged is not None and a.run_id == b.run_id

    def table(self) -> list[tuple[str, float | None, float | None, float | None]]:
        """(metric, A, B, B - A) for every whole-run total either side has (None: absent)."""
        b = self.b.judged.totals if self.b.judged is not None else {}
        a = self.a.judged.totals if self.a is not None and self.a.judged is not None and self.comparable else {}
        rows = []
        for name in sorted(set(a) | set(b)):
            va, vb = a.get(name), b.get(name)
            rows.append((name, va, vb, vb - va if va is not None and vb is not None else None))
        return rows

    def row_at(self, time: float) -> int | None:
        """The judged row (scan) shown at source time `time`: the last one at or before it."""
        j = self.b.judged
        if j is None or not len(j.times):
            return None
        k = int(np.searchsorted(j.times, time + 1e-9)) - 1
        return max(k, 0)

    def diff_at(self, time: float) -> WorldDiff | None:
        """What B's judged world model adds and loses against A's at `time` (same zero frame)."""
        if not self.comparable:
            return None
        k = self.row_at(time)
        assert self.a is not None and self.a.judged is not None and self.b.judged is not None
        if k is None or k >= len(self.a.judged.features) or k >= len(self.b.judged.features):
            return None
        return diff_arrays(self.a.judged.features[k], self.b.judged.features[k])

    def overlay(self, time: float, robot_in_map: Pose | None) -> dict[str, np.ndarray]:
        """The diff at `time` in the map frame, placed like B's judged world model there (its
        zero frame put by the robot's pose in the map): {"walls_added": (K, 4), ...}."""
        d = self.diff_at(time)
        if d is None or robot_in_map is None:
            return {}
        k = self.row_at(time)
        assert k is not None and self.b.judged is not None
        pose = self.b.judged.features[k].get("pose")
        if pose is None:
            return {}
        z = compose(robot_in_map, invert((float(pose[0]), float(pose[1]), float(pose[2]))))
        out: dict[str, np.ndarray] = {}
        for name in ("walls_added", "walls_lost", "doors_added", "doors_lost"):
            out[name] = transform_segments(getattr(d, name), z)
        for name in ("corners_added", "corners_lost"):
            out[name] = transform_points(getattr(d, name), z)
        return out


class _Nothing:
    """The observer a replay gets (its run is the whole file, read when judged)."""

    name = "nothing"

    def on_frame(self, sf: Any) -> None:
        pass

    def summary(self) -> dict[str, Any]:
        return {}
