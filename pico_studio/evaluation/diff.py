"""World-model A/B diff: the walls, corners and doors that config B adds or loses against A.

Both world models come from the same sensor stream (the drive is recorded once), so they
share the perceptor's zero frame and are compared there directly; the page places the result
like the rest of B's world model. Pure functions of numpy arrays, no truth needed.

Matching is the scoring's (`frame_score`), with A standing in for the truth:
- **walls** (length-weighted): a wall of B is *added* when less than `min_share` of its length
  lies within `wall_distance` of an A wall within `wall_angle` of its direction (the share
  `frame_score.covered` measures for wall precision); a wall of A is *lost* the other way round;
- **corners**: matched one to one, nearest first, within `corner_distance`; unmatched B
  corners are added, unmatched A corners lost;
- **doors**: a door matches when the middles are within `door_distance` and the directions
  within `door_angle`; a B door matching no A door is added, an A door matching no B door lost.

A vs A is empty by construction: every wall covers itself, every corner and door pairs with itself.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pico_studio.evaluation.frame_score import (
    Tolerances,
    _samples,  # the scoring's own sampling along segments, so the diff weighs length as it does
    covered,
    doors_match,
    match_points,
)

KINDS = ("walls", "corners", "doors")


@dataclass(frozen=True)
class DiffTolerances:
    """How close counts as the same feature in A and B (the scoring's tolerances by default)."""

    match: Tolerances = field(default_factory=Tolerances)
    min_share: float = 0.5  # a wall is the same when at least this share of its length is covered


SAME = DiffTolerances()


@dataclass
class WorldDiff:
    """What B adds and loses against A, as arrays in the (shared) zero frame."""

    walls_added: np.ndarray  # (K, 4) B's walls
    walls_lost: np.ndarray  # (K, 4) A's walls
    corners_added: np.ndarray  # (K, 2)
    corners_lost: np.ndarray  # (K, 2)
    doors_added: np.ndarray  # (K, 4)
    doors_lost: np.ndarray  # (K, 4)

    def counts(self) -> dict[str, int]:
        """{"walls_added": n, "walls_lost": n, ...} (the `compare --json` "diff" keys)."""
        return {f"{k}_{w}": len(getattr(self, f"{k}_{w}")) for k in KINDS for w in ("added", "lost")}

    @property
    def empty(self) -> bool:
        return not any(self.counts().values())


def wall_shares(walls: np.ndarray, against: np.ndarray, tol: DiffTolerances = SAME) -> np.ndarray:
    """(W,) the share of each wall's length within the tolerances of a wall of `against`."""
    walls = np.asarray(walls, dtype=float).reshape(-1, 4)
    against = np.asarray(against, dtype=float).reshape(-1, 4)
    if len(walls) == 0:
        return np.zeros(0)
    pts, owner, weight = _samples(walls, tol.match.sample_step)
    d = walls[:, 2:4] - walls[:, 0:2]
    dirs = d / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-12)[:, None]
    ok = covered(pts, dirs[owner], against, tol.match)
    length = np.bincount(owner, weights=weight, minlength=len(walls))
    on = np.bincount(owner, weights=np.where(ok, weight, 0.0), minlength=len(walls))
    return np.where(length > 0, on / np.maximum(length, 1e-12), 1.0)


def diff_walls(a: np.ndarray, b: np.ndarray, tol: DiffTolerances = SAME) -> tuple[np.ndarray, np.ndarray]:
    """(added: B's walls not in A, lost: A's walls not in B), each (K, 4)."""
    a = np.asarray(a, dtype=float).reshape(-1, 4)
    b = np.asarray(b, dtype=float).reshape(-1, 4)
    return b[wall_shares(b, a, tol) < tol.min_share], a[wall_shares(a, b, tol) < tol.min_share]


def diff_corners(a: np.ndarray, b: np.ndarray, tol: DiffTolerances = SAME) -> tuple[np.ndarray, np.ndarray]:
    """(added, lost) corners, each (K, 2): those left over after pairing A and B one to one."""
    a = np.asarray(a, dtype=float).reshape(-1, 2)
    b = np.asarray(b, dtype=float).reshape(-1, 2)
    pairs = match_points(a, b, tol.match.corner_distance)
    keep_a = np.ones(len(a), dtype=bool)
    keep_b = np.ones(len(b), dtype=bool)
    for i, j in pairs:
        keep_a[i] = keep_b[j] = False
    return b[keep_b], a[keep_a]


def diff_doors(a: np.ndarray, b: np.ndarray, tol: DiffTolerances = SAME) -> tuple[np.ndarray, np.ndarray]:
    """(added, lost) doors, each (K, 4): a door of one side that matches none of the other's."""
    a = np.asarray(a, dtype=float).reshape(-1, 4)
    b = np.asarray(b, dtype=float).reshape(-1, 4)
    m = doors_match(b, a, tol.match)  # (B, A)
    return b[~m.any(axis=1)] if len(b) else b, a[~m.any(axis=0)] if len(a) else a


def diff_arrays(a: dict[str, np.ndarray], b: dict[str, np.ndarray], tol: DiffTolerances = SAME) -> WorldDiff:
    """The diff of two feature sets {"walls": (W, 4), "corners": (C, 2), "doors": (D, 4)}."""
    wa, wl = diff_walls(a.get("walls", np.zeros((0, 4))), b.get("walls", np.zeros((0, 4))), tol)
    ca, cl = diff_corners(a.get("corners", np.zeros((0, 2))), b.get("corners", np.zeros((0, 2))), tol)
    da, dl = diff_doors(a.get("doors", np.zeros((0, 4))), b.get("doors", np.zeros((0, 4))), tol)
    return WorldDiff(wa, wl, ca, cl, da, dl)


def features(wm: Any) -> dict[str, np.ndarray]:
    """A world model's walls, corners and doors in its zero frame (empty for None)."""
    if wm is None:
        return {"walls": np.zeros((0, 4)), "corners": np.zeros((0, 2)), "doors": np.zeros((0, 4))}
    return {
        "walls": np.asarray(wm.local_map.walls, dtype=float).reshape(-1, 4),
        "corners": np.asarray(wm.corners, dtype=float).reshape(-1, 2),
        "doors": np.asarray(wm.doors, dtype=float).reshape(-1, 4),
    }


def diff_world_models(a: Any, b: Any, tol: DiffTolerances = SAME) -> WorldDiff:
    """What world model `b` adds and loses against `a` (same sensor stream, same zero frame)."""
    return diff_arrays(features(a), features(b), tol)
