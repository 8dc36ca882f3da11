"""Door memory's compiled loop (door_memory says when a door is remembered and why): `carry`
takes the records on by one scan, `_open` saying whether a remembered door still is.

Carrying. A door found now takes the record of the same door (middles within `same`, directions
within the angle: |u_f . u_m| >= cos_angle, as `geometry.door_matches`; of several, the one
found in most scans in a row): scans + 1, the place it was first found kept, the spread the
farthest the robot has been from there since. A door found now with no record starts one (1
scan, here, spread 0). A record no door matched now goes on only when remembered (at least
`min_scans` scans, at least `min_spread` apart) and still open.

A remembered door A -> B (zero frame) stays while

* each end lies within `reach` of a wall of the local map (point to segment: the foot
  t = clamp((P - a) . d / |d|^2, 0, 1), the distance |a + t d - P|): its jambs are still there;
* no wall crosses its inside (the two segments' crossing at s in (0.15, 0.85) along the door,
  u in [0, 1] along the wall: s = (q - p) x e / (r x e), u = (q - p) x r / (r x e), r the door,
  e the wall) and none passes within `reach` of its middle (a wall lying in its line: a door
  closed, a box pushed into it);
* the current scan's beams towards its points at a quarter, a half and three quarters do not
  end on it (within `reach` of the point) for two of the three in view: someone standing in the
  doorway, the door leaf closed. A beam ending before the point says nothing (something in
  front), nor one out of view;
* neither end is a corridor's mouth's corner now (`_mouth_corner`): the local map shows the
  wall at that end joined (within `reach`) to a wall longer than `cap_max` running on beyond the
  door's line, the wall at its other end running on beyond it to the other side
  (face_kernels._corridor_mouth, the rule that makes such a place a possible door only, asked
  from both sides of the line: the memory outlives the viewpoint). Found from a room, its
  corridor's side unseen, the mouth is a doorway in shape; once that side is seen it is none.
"""

from __future__ import annotations

import math

import numpy as np

from pico_studio.core.geometry import door_matches
from pico_studio.core.perception.face_kernels import _corridor_mouth
from pico_studio.core.perception.identify_kernels import _beam_towards
from pico_studio.jit import kernel, njit


@njit
def _segment_distance(px: float, py: float, walls: np.ndarray, w: int) -> float:
    """From P to wall w (the foot t clamped to the segment)."""
    ax, ay = walls[w, 0], walls[w, 1]
    dx, dy = walls[w, 2] - ax, walls[w, 3] - ay
    t = min(max(((px - ax) * dx + (py - ay) * dy) / max(dx * dx + dy * dy, 1e-12), 0.0), 1.0)
    return math.hypot(ax + t * dx - px, ay + t * dy - py)


@njit
def _near_a_wall(px: float, py: float, walls: np.ndarray, reach: float) -> bool:
    for w in range(walls.shape[0]):
        if _segment_distance(px, py, walls, w) <= reach:
            return True
    return False


@njit
def _closed(door: np.ndarray, walls: np.ndarray, reach: float) -> bool:
    px, py = door[0], door[1]
    rx, ry = door[2] - px, door[3] - py
    if _near_a_wall(px + 0.5 * rx, py + 0.5 * ry, walls, reach):
        return True  # a wall at its middle
    for w in range(walls.shape[0]):
        qx, qy = walls[w, 0], walls[w, 1]
        ex, ey = walls[w, 2] - qx, walls[w, 3] - qy
        den = rx * ey - ry * ex
        if abs(den) < 1e-12:
            continue
        s = ((qx - px) * ey - (qy - py) * ex) / den
        u = ((qx - px) * ry - (qy - py) * rx) / den
        if 0.15 < s < 0.85 and 0.0 <= u <= 1.0:
            return True  # a wall across it
    return False


@njit
def _stood_in(door: np.ndarray, reach: float, has_view: bool, ranges: np.ndarray, valid: np.ndarray, vx: float,
              vy: float, va: float, a0: float, inc: float) -> bool:
    if not has_view:
        return False
    hits = 0
    for f in (0.25, 0.5, 0.75):
        qx, qy = door[0] + f * (door[2] - door[0]), door[1] + f * (door[3] - door[1])
        b = _beam_towards(qx, qy, ranges.shape[0], vx, vy, va, a0, inc)
        if b < 0 or not valid[b]:
            continue
        if abs(ranges[b] - math.hypot(qx - vx, qy - vy)) <= reach:
            hits += 1
    return hits >= 2


@njit
def _mouth_corner(door: np.ndarray, walls: np.ndarray, connected: np.ndarray, lengths: np.ndarray, reach: float,
                  cap_max: float, rx: float, ry: float) -> bool:
    """Is one of the door's ends P a corridor's mouth's corner (the module docstring): a wall k
    ending within `reach` of P, joined there, and a wall within `reach` of the other end M for
    its face, `_corridor_mouth` from the robot R or from R mirrored in the door's line?"""
    for end in range(2):
        gap = np.empty(4)
        gap[0], gap[1] = door[2 * end], door[2 * end + 1]
        gap[2], gap[3] = door[2 - 2 * end], door[3 - 2 * end]
        ux, uy = gap[2] - gap[0], gap[3] - gap[1]
        length = math.hypot(ux, uy)
        if length <= 1e-12:
            return False
        ux, uy = ux / length, uy / length
        off = -uy * (rx - gap[0]) + ux * (ry - gap[1])  # R's side of the line, along its normal (-uy, ux)
        mx, my = rx + 2 * off * uy, ry - 2 * off * ux  # R mirrored in the line
        for k in range(walls.shape[0]):
            for e in range(2):
                j = connected[k, e]
                if j < 0 or math.hypot(walls[k, 2 * e] - gap[0], walls[k, 2 * e + 1] - gap[1]) > reach:
                    continue
                for f in range(walls.shape[0]):
                    if f == k or f == j or _segment_distance(gap[2], gap[3], walls, f) > reach:
                        continue
                    if _corridor_mouth(gap, walls, connected, lengths, k, f, rx, ry, cap_max) or \
                            _corridor_mouth(gap, walls, connected, lengths, k, f, mx, my, cap_max):
                        return True
    return False


@njit
def _open(door: np.ndarray, walls: np.ndarray, connected: np.ndarray, lengths: np.ndarray, reach: float,
          cap_max: float, rx: float, ry: float, has_view: bool, ranges: np.ndarray, valid: np.ndarray, vx: float,
          vy: float, va: float, a0: float, inc: float) -> bool:
    """Is a remembered door still open (the module docstring)?"""
    return _near_a_wall(door[0], door[1], walls, reach) and _near_a_wall(door[2], door[3], walls, reach) \
        and not _closed(door, walls, reach) and not _stood_in(door, reach, has_view, ranges, valid, vx, vy, va, a0, inc) \
        and not _mouth_corner(door, walls, connected, lengths, reach, cap_max, rx, ry)


def _example_carry() -> tuple:
    doors = np.array([[1.0, -0.4, 1.0, 0.4], [1.0, 1.0, 1.0, 2.0]])
    walls = np.array([[1.0, -2.0, 1.0, -0.4], [1.0, 0.4, 1.0, 2.5], [1.0, 0.4, 3.0, 0.4]])
    connected = np.array([[-1, -1], [2, -1], [1, -1]], dtype=np.int64)
    ranges = np.full(5, 3.0)
    return (doors[:1], doors, np.array([3, 4], dtype=np.int64), np.zeros((2, 2)), np.array([1.5, 1.5]), 1.0, 0.0,
            0.25, 0.95, 3, 1.0, walls, connected, 0.1, 0.35, True, ranges, np.ones(5, dtype=np.bool_), 0.0, 0.0,
            0.0, -1.0, 0.5)


@kernel(_example_carry)
def carry(doors: np.ndarray, mem: np.ndarray, mem_scans: np.ndarray, mem_first: np.ndarray, mem_spread: np.ndarray,
          rx: float, ry: float, same: float, cos_angle: float, min_scans: int, min_spread: float, walls: np.ndarray,
          connected: np.ndarray, reach: float, cap_max: float, has_view: bool, ranges: np.ndarray, valid: np.ndarray, vx: float, vy: float, va: float,
          a0: float, inc: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The records after this scan: (the rows of `mem` carried on, not found now (K,) int64;
    then for the D doors found now followed by those K: scans (D + K,) int64, first place
    (D + K, 2), spread (D + K,))."""
    d, m = doors.shape[0], mem.shape[0]
    match = door_matches(doors, mem, same, cos_angle)
    scans = np.ones(d + m, dtype=np.int64)
    first = np.empty((d + m, 2))
    spread = np.zeros(d + m)
    found = np.zeros(m, dtype=np.bool_)
    lengths = np.empty(walls.shape[0])
    for w in range(walls.shape[0]):
        lengths[w] = math.hypot(walls[w, 2] - walls[w, 0], walls[w, 3] - walls[w, 1])
    for i in range(d):
        best = -1
        for j in range(m):
            if match[i, j]:
                found[j] = True
                if best < 0 or mem_scans[j] > mem_scans[best]:
                    best = j
        if best < 0:
            first[i, 0], first[i, 1] = rx, ry
            continue
        scans[i] = mem_scans[best] + 1
        first[i, 0], first[i, 1] = mem_first[best, 0], mem_first[best, 1]
        spread[i] = max(mem_spread[best], math.hypot(rx - mem_first[best, 0], ry - mem_first[best, 1]))
    rows = np.empty(m, dtype=np.int64)
    k = 0
    for j in range(m):
        if found[j] or mem_scans[j] < min_scans or not mem_spread[j] >= min_spread \
                or not _open(mem[j], walls, connected, lengths, reach, cap_max, rx, ry, has_view, ranges, valid, vx, vy,
                             va, a0, inc):
            continue
        rows[k] = j
        scans[d + k], spread[d + k] = mem_scans[j], mem_spread[j]
        first[d + k, 0], first[d + k, 1] = mem_first[j, 0], mem_first[j, 1]
        k += 1
    return rows[:k].copy(), scans[:d + k].copy(), first[:d + k].copy(), spread[:d + k].copy()
