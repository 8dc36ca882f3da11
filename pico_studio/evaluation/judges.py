"""Behaviour outcomes judged from the session's frames: did the robot get out, which cabinets
did it visit, how many rooms (and objects) did it count — each a session observer.

    judge = EscapeJudge(sim.world.map, start=sim.now(), pose=sim.truth.pose)
    session = Session(sim, behaviour=b, observers=[judge, CabinetsVisited(b), RoomsCounted(b)])

`EscapeJudge`: the robot's true centre (the frame's truth pose) crossed one of the map's
`finish` segments, or, for a map without one, left the bounding box of all walls by at least
`ESCAPE_MARGIN`. The other two read the behaviour's own report (`result()`) and, when told the
expected answer, say whether it is right.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from pico_studio.json_map import GlobalMap

ESCAPE_MARGIN = 0.3  # m beyond the walls' bounding box counts as out (issue 7)


def _crosses(p: tuple[float, float], q: tuple[float, float], segments: np.ndarray) -> bool:
    """Does the move p -> q cross any segment (N, 4)?"""
    if len(segments) == 0:
        return False
    a, b = segments[:, 0:2], segments[:, 2:4]

    def orient(u: np.ndarray, v: np.ndarray, w: np.ndarray) -> np.ndarray:
        return (v[..., 0] - u[..., 0]) * (w[..., 1] - u[..., 1]) - (v[..., 1] - u[..., 1]) * (w[..., 0] - u[..., 0])

    P, Q = np.array(p)[None, :], np.array(q)[None, :]
    d1, d2 = orient(a, b, P), orient(a, b, Q)
    d3, d4 = orient(P, Q, a), orient(P, Q, b)
    return bool(np.any((d1 * d2 <= 0) & (d3 * d4 < 0)))


class EscapeJudge:
    """Watches the true pose and says when (if ever, seconds since `start`) the robot got out."""

    name = "escape"

    def __init__(self, global_map: GlobalMap, *, start: float = 0.0, pose: Any = None):
        self.finish = global_map.finish_segments
        walls = global_map.wall_segments.reshape(-1, 2)
        self.box = (*walls.min(axis=0), *walls.max(axis=0))
        self.start = start
        self.escaped_at: float | None = None
        self._last: tuple[float, float] | None = None
        if pose is not None:
            self.update((float(pose[0]), float(pose[1])), 0.0)

    def on_frame(self, sf: Any) -> None:
        pose = (sf.frame.truth or {}).get("pose")
        if pose is not None:
            self.update((float(pose[0]), float(pose[1])), sf.frame.time - self.start)

    def update(self, xy: tuple[float, float], t: float) -> None:
        if self.escaped_at is None:
            if len(self.finish):
                if self._last is not None and _crosses(self._last, xy, self.finish):
                    self.escaped_at = t
            else:
                x0, y0, x1, y1 = self.box
                outside = max(x0 - xy[0], xy[0] - x1, y0 - xy[1], xy[1] - y1)
                if outside >= ESCAPE_MARGIN:
                    self.escaped_at = t
        self._last = xy

    def summary(self) -> dict[str, Any]:
        escaped = self.escaped_at is not None
        return {"escaped": escaped, "escape_seconds": self.escaped_at if escaped else None}


class _Outcome:
    """A judge of what the behaviour itself reports (`result()`), read at the end."""

    def __init__(self, behaviour: Any, expected: list[int] | None = None):
        self.behaviour = behaviour
        self.expected = expected

    def on_frame(self, sf: Any) -> None:
        pass  # the behaviour keeps its own record


class CabinetsVisited(_Outcome):
    """The cabinets the behaviour reports visited, in order; right when they are `expected`."""

    name = "cabinets"

    def summary(self) -> dict[str, Any]:
        visited = list(self.behaviour.result().get("cabinets_visited", []))
        out: dict[str, Any] = {"cabinets_visited": visited}
        if self.expected is not None:
            out["cabinets_right"] = visited == list(self.expected)
        return out


class RoomsCounted(_Outcome):
    """The rooms the behaviour counted (each {"objects", "edges"}); with `expected` (a list of
    object counts, e.g. a generated world's), whether they match up to where it started."""

    name = "rooms"

    def summary(self) -> dict[str, Any]:
        rooms = list(self.behaviour.result().get("rooms", []))
        out: dict[str, Any] = {"rooms": rooms}
        if self.expected is not None:
            got, want = [r.get("objects") for r in rooms], list(self.expected)
            # the robot goes round from whichever room it meets first: the same list, rotated
            out["rooms_right"] = len(got) == len(want) and (
                not want or any(got == want[k:] + want[:k] for k in range(len(want))))
        return out
