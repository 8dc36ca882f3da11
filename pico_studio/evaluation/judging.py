"""What re-judging a kept run is made of: the kept run (`KeptRun`), its result (`Judged`: per-frame
series, the run's totals, packed `Features`), and the scoring half of a re-judge (`Judging`),
fed world models by the perceiving half — in this process (`rejudge.rejudge`) or in another
(`rejudge_worker`). `rejudge` is the module to use; this one has no loop of its own, so both
the in-process re-judge and the worker processes build on it without importing each other.

**Series** (one value per frame with a new scan, `SERIES` lists them with their meaning):
wall / corner / door precision and recall of that frame (NaN when the frame has nothing to
count), the perceptor's pose error (when the simulator's truth is kept), the localised pose
error against the true pose (when there is one and a map to localise on),
`local_map.agreement` (recordings with true poses: `evaluation.agreement`),
counts (local walls, corners, doors, possible doors), per-stage ms, localisation quality and
lost. **Totals**: the run's figures (`metrics.flatten` names: ratios of sums over the run, as
`eval` reports them) and the mean counts.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, overload

import numpy as np

from pico_studio.config import Config, from_dict, to_dict
from pico_studio.core.io import Frame
from pico_studio.evaluation.agreement import AgreementObserver
from pico_studio.evaluation.diff import features
from pico_studio.evaluation.frame_score import FrameScore, Tolerances
from pico_studio.evaluation.metrics import flatten
from pico_studio.evaluation.run_score import PoseScore, TruthScorer
from pico_studio.session import SessionFrame

Pose = tuple[float, float, float]


@dataclass(frozen=True)
class Series:
    name: str
    help: str
    unit: str = ""
    needs: str = ""  # "truth" (the simulator's), "pose" (a true pose), "map" (localising), "" always


SERIES: dict[str, Series] = {s.name: s for s in (
    Series("walls.precision", "share of this frame's local-map wall length on a true wall", "", "truth"),
    Series("walls.recall", "share of the wall length in view the local map covers", "", "truth"),
    Series("corners.precision", "share of this frame's corners at a true corner", "", "truth"),
    Series("corners.recall", "share of the true corners in view detected", "", "truth"),
    Series("doors.precision", "share of this frame's doors at a true opening", "", "truth"),
    Series("doors.recall", "share of the openings in view detected", "", "truth"),
    Series("pose.error_m", "the perceptor's pose error since its zero frame", "m", "truth"),
    Series("localisation.error_m", "localised position error against the true pose", "m", "pose"),
    Series("local_map.agreement", "share of the local map near the reference map of the true poses", "", "pose"),
    Series("count.walls", "walls in the local map"),
    Series("count.corners", "corners"),
    Series("count.doors", "doors"),
    Series("count.possible_doors", "possible doors"),
    Series("localisation.quality", "localisation quality (0..1)", "", "map"),
    Series("localisation.lost", "1 while the localisation is lost", "", "map"),
    # "ms.<stage>" series are added per stage the perceptor reports (perception.STAGES, total)
)}


@dataclass
class KeptRun:
    """A run's sensor stream and truth, kept to be judged again with other configs.

    `frames`: every tick's `Frame` (laser / odometry None when nothing new came that tick);
    `truth`: per frame index with a scan, the simulator's truth then (`TruthSnapshot`), or
    None for a recording (its frames carry the true pose, if known, in `frame.truth`);
    `vertices`: the static corners (end-point error); `global_map` / `initial_pose`: what
    localisation starts from (None: no localisation)."""

    frames: list[Frame]
    truth: dict[int, Any] | None = None
    vertices: np.ndarray | None = None
    global_map: Any = None
    initial_pose: Pose | None = None
    name: str = ""
    origin: tuple[int, int] | None = None  # (keeper, index of frames[0] in its stream): `RunKeeper.kept`
    _dfield: Any = field(default=None, repr=False)  # the map's distance field, built once per field params
    _dfield_key: Any = field(default=None, repr=False)
    _blob: tuple[bytes, bytes] | None = field(default=None, repr=False, compare=False)  # for worker processes

    @property
    def scans(self) -> int:
        return sum(1 for f in self.frames if f.laser is not None)

    @property
    def has_truth(self) -> bool:
        return bool(self.truth)

    @property
    def has_true_pose(self) -> bool:
        return any((f.truth or {}).get("pose") is not None for f in self.frames)

    def distance_field(self, cfg: Config) -> Any:
        """The global map's distance field for `cfg.localisation.field` (kept between re-judges)."""
        from pico_studio.core.localisation import DistanceField

        key = cfg.localisation.field
        if self._dfield is None or self._dfield_key != key:
            self._dfield = DistanceField.from_map(self.global_map, cfg.localisation.field)
            self._dfield_key = key
        return self._dfield


@dataclass
class Judged:
    """One config's re-judged run: per-frame series, the run's totals, and why some are absent."""

    generation: int
    times: np.ndarray  # (N,) s, one per frame with a scan
    frame_index: np.ndarray  # (N,) the kept frame (tick) each row is
    series: dict[str, np.ndarray]  # name -> (N,)
    totals: dict[str, float]
    features: Sequence[dict[str, np.ndarray]]  # per row: walls, corners, doors (zero frame) and pose, for diffs
    notes: list[str]  # e.g. "no truth: scores absent"
    seconds: float  # wall time the re-judge took
    config: Config | None = None
    complete: bool = True  # False: the frames judged so far of a re-judge under way (no totals)
    cpu: float = math.nan  # CPU seconds it took (every process judging it)
    cpu_parts: tuple[float, ...] = ()  # in worker processes: CPU seconds of (perceiver, scorer)


class Features(Sequence[dict[str, np.ndarray]]):
    """Every row's walls (K, 4), corners (K, 2), doors (K, 4) in its zero frame and its pose
    (3,), packed: one array per kind and the rows' offsets into it. `features[i]` is row i's
    dict (views), as `diff.features` gives it plus "pose"; a worker process sends these few
    arrays back instead of thousands of small dicts."""

    KINDS = (("walls", 4), ("corners", 2), ("doors", 4))

    def __init__(self, arrays: dict[str, np.ndarray], offsets: dict[str, np.ndarray], pose: np.ndarray):
        self.arrays, self.offsets, self.pose = arrays, offsets, pose

    @classmethod
    def pack(cls, rows: Sequence[dict[str, np.ndarray]]) -> Features:
        arrays, offsets = {}, {}
        for kind, width in cls.KINDS:
            parts = [np.asarray(r[kind], dtype=float).reshape(-1, width) for r in rows]
            arrays[kind] = np.concatenate(parts) if parts else np.zeros((0, width))
            offsets[kind] = np.concatenate(([0], np.cumsum([len(a) for a in parts], dtype=np.int64)))
        pose = np.array([r["pose"] for r in rows], dtype=float).reshape(-1, 3)
        return cls(arrays, offsets, pose)

    def __len__(self) -> int:
        return len(self.pose)

    @overload
    def __getitem__(self, i: int) -> dict[str, np.ndarray]: ...

    @overload
    def __getitem__(self, i: slice) -> list[dict[str, np.ndarray]]: ...

    def __getitem__(self, i: int | slice) -> dict[str, np.ndarray] | list[dict[str, np.ndarray]]:
        if isinstance(i, slice):
            return [self[k] for k in range(*i.indices(len(self)))]
        if i < 0:
            i += len(self)
        if not 0 <= i < len(self):
            raise IndexError(i)
        row = {kind: self.arrays[kind][self.offsets[kind][i]:self.offsets[kind][i + 1]] for kind, _ in self.KINDS}
        row["pose"] = self.pose[i]
        return row


def validated(cfg: Config) -> Config:
    """`cfg` checked as a whole file would be (ranges, choices, cross-field rules): a tree
    built in code (`dataclasses.replace`) has had no checks. ConfigError names the field."""
    return from_dict(Config, to_dict(cfg))


def _pose(v: Any) -> Pose:
    return (float(v[0]), float(v[1]), float(v[2]))


class Cancelled(Exception):
    """The re-judge was overtaken by a newer change."""


class _Series:
    """The session observer filling one row of every series per frame with a new scan.

    `cursor.index` is the kept frame being judged (the `FramesReplay` itself in one process,
    the scoring worker's cursor when another process perceives)."""

    name = "series"

    def __init__(self, run: KeptRun, cursor: Any, scorer: TruthScorer | None,
                 localising: bool, agreement: Any) -> None:
        self.run, self.cursor, self.scorer = run, cursor, scorer
        self.localising, self.agreement = localising, agreement
        self.rows: dict[str, list[float]] = {}
        self.times: list[float] = []
        self.index: list[int] = []
        self.features: list[dict[str, np.ndarray]] = []
        self.pose = PoseScore()
        self._last: Any = None

    def _put(self, name: str, value: float) -> None:
        col = self.rows.setdefault(name, [math.nan] * (len(self.times) - 1))
        col.append(value)

    def on_frame(self, sf: SessionFrame) -> None:
        wm = sf.world_model
        if not judged_here(sf, self._last):
            return
        self._last = wm
        self.times.append(sf.frame.time)
        self.index.append(self.cursor.index)
        feats = features(wm)
        feats["pose"] = np.asarray(wm.pose, dtype=float)  # to place the zero frame on the map
        self.features.append(feats)
        if self.scorer is not None and self.cursor.index in (self.run.truth or {}):
            n = self.scorer.run.count
            self.scorer.on_frame(sf)
            if self.scorer.run.count != n and self.scorer.run.last is not None:
                self._scores(self.scorer.run.last)
        lm = wm.local_map
        self._put("count.walls", float(len(lm.walls)))
        self._put("count.corners", float(len(wm.corners)))
        self._put("count.doors", float(len(wm.doors)))
        self._put("count.possible_doors", float(len(wm.possible_doors)))
        for stage, ms in (wm.timings_ms or {}).items():
            self._put(f"ms.{stage}", float(ms))
        if self.localising:
            self._put("localisation.quality", float(wm.localisation_quality))
            self._put("localisation.lost", float(bool(wm.lost) or wm.global_pose is None))
            true = (sf.frame.truth or {}).get("pose")
            if true is not None:
                n = len(self.pose.position)
                self.pose.add(wm.global_pose, _pose(true), wm.lost)
                if len(self.pose.position) > n:
                    self._put("localisation.error_m", self.pose.position[-1])
        if self.agreement is not None:
            self.agreement.on_frame(sf)
        self._pad()

    def _scores(self, s: FrameScore) -> None:
        for name, num, den in (("walls.precision", s.wall_len_ok, s.wall_len),
                               ("walls.recall", s.truth_len_ok, s.truth_len),
                               ("corners.precision", s.corners_ok, s.corners),
                               ("corners.recall", s.truth_corners_ok, s.truth_corners),
                               ("doors.precision", s.doors_ok, s.doors),
                               ("doors.recall", s.truth_doors_ok, s.truth_doors)):
            self._put(name, num / den if den > 0 else math.nan)
        self._put("pose.error_m", s.pose_err_m)

    def _pad(self) -> None:
        """Every series as long as the rows so far (NaN where this frame gave it nothing)."""
        n = len(self.times)
        for col in self.rows.values():
            if len(col) < n:
                col.append(math.nan)

    def summary(self) -> dict[str, Any]:
        return {"frames": len(self.times)}


def judged_here(sf: SessionFrame, last: Any) -> bool:
    """Whether tick `sf` makes a row: a new scan perceived into a new world model."""
    return sf.frame.laser is not None and sf.world_model is not None and sf.world_model is not last


def is_localising(run: KeptRun, cfg: Config) -> bool:
    """Whether `cfg` localises on `run`'s map (a map with walls, localisation switched on)."""
    return run.global_map is not None and cfg.localisation.enabled and len(run.global_map.walls) > 0


def perceptor_for(run: KeptRun, cfg: Config) -> Any:
    """The perceptor judging `run` with `cfg` (localising on the run's map when it can)."""
    from pico_studio.evaluation.runner import make_perceptor

    localising = is_localising(run, cfg)
    return make_perceptor(cfg, run.global_map, run.initial_pose, localise=localising,
                          field=run.distance_field(cfg) if localising else None)


class Cursor:
    """The kept frame being judged, when the frames are not replayed here (`Judging`)."""

    index = -1


class Judging:
    """The scoring half of a re-judge: per world model of a new scan, its row of every series,
    then the totals. Fed by the session over the kept frames (`rejudge`), or by another
    process's perceptor (`rejudge_worker`): `cursor.index` says which kept frame it is."""

    def __init__(self, run: KeptRun, cfg: Config, tol: Tolerances | None = None, cursor: Any = None):
        self.run, self.cfg = run, cfg
        self.cursor = cursor if cursor is not None else Cursor()
        truth = run.truth or {}
        self.scorer = TruthScorer(lambda: truth[self.cursor.index], tol=tol, vertices=run.vertices) if truth else None
        # with the simulator's truth the walls are scored against the true geometry; agreement with
        # a reference map cast from the true poses is the figure for recordings that know only those
        self.agreement = AgreementObserver(every=1) if run.has_true_pose and not truth else None
        self.localising = is_localising(run, cfg)
        self.rows = _Series(run, self.cursor, self.scorer, self.localising, self.agreement)

    def partial(self, generation: int, seconds: float) -> Judged:
        """The series of the frames judged so far (`complete` False, no totals)."""
        rows = self.rows
        return Judged(generation, np.asarray(rows.times, dtype=float), np.asarray(rows.index, dtype=np.int64),
                      {n: np.asarray(c, dtype=float) for n, c in rows.rows.items()}, {}, list(rows.features),
                      [], seconds, self.cfg, complete=False)

    def finish(self, generation: int, seconds: float, cpu: float = math.nan) -> Judged:
        rows = self.rows
        series = {name: np.asarray(col, dtype=float) for name, col in rows.rows.items()}
        totals, notes = _totals(self.run, rows, self.scorer, self.agreement, series, self.localising)
        if self.agreement is not None:
            per = _agreement_per_frame(self.agreement, len(rows.times))
            if per is not None:
                series["local_map.agreement"] = per
        return Judged(generation, np.asarray(rows.times, dtype=float), np.asarray(rows.index, dtype=np.int64),
                      series, totals, Features.pack(rows.features), notes, seconds, self.cfg, cpu=cpu)


def _totals(run: KeptRun, rows: _Series, scorer: TruthScorer | None, agreement: Any,
            series: dict[str, np.ndarray], localising: bool) -> tuple[dict[str, float], list[str]]:
    notes: list[str] = []
    summary: dict[str, Any] = {}
    if scorer is not None:
        summary["perceptor"] = scorer.run.summary()
    else:
        notes.append("no simulator truth: wall, corner and door scores are absent (counts and stability shown)")
    if localising and rows.pose.lost:
        summary["localisation"] = rows.pose.summary()
    elif run.global_map is None:
        notes.append("no map to localise on: localisation figures are absent")
    elif not run.has_true_pose:
        notes.append("no true pose: localisation error is absent")
    totals = flatten(summary)
    if scorer is None:
        ms = series.get("ms.total")
        if ms is not None and len(ms):
            totals["perceptor.ms_per_scan"] = float(np.nanmedian(ms))
    if agreement is not None:
        totals["local_map.agreement"] = float(agreement.summary()["agreement"])
    for name in ("count.walls", "count.corners", "count.doors", "count.possible_doors"):
        col = series.get(name)
        if col is not None and len(col):
            totals[name] = float(np.nanmean(col))
    return totals, notes


def _agreement_per_frame(agreement: Any, n: int) -> np.ndarray | None:
    """Per frame agreement from the observer's kept samples (judged against the finished
    reference map), when it keeps them per frame; None otherwise."""
    per_frame = getattr(agreement, "_per_frame", None)
    samples = getattr(agreement, "_samples", None)
    if per_frame is None or samples is None or len(per_frame) != n:
        return None
    pts = np.vstack(samples) if samples else np.zeros((0, 2))
    if not len(pts):
        return np.full(n, math.nan)
    ok = agreement.reference.distance(pts) <= agreement.distance
    return np.array([float(ok[s:s + k].mean()) if k else math.nan for s, k in per_frame])


class NewestResult:
    """What both re-judgers share: `generation` (the newest asked for), `latest` (the newest
    `Judged` delivered) and the condition `_cond` guarding them, set by the subclass."""

    generation: int
    latest: Judged | None
    _cond: threading.Condition

    def wait(self, generation: int | None = None, timeout: float = 60.0) -> Judged | None:
        """Block until the result of `generation` (default the newest) is in, or `timeout`."""
        end = time.monotonic() + timeout
        with self._cond:
            while True:
                want = self.generation if generation is None else generation
                if self.latest is not None and self.latest.generation >= want:
                    return self.latest
                left = end - time.monotonic()
                if left <= 0:
                    return None
                self._cond.wait(left)
