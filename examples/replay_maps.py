"""Draw the two real recordings as maps: every scan placed at its pose.

    .venv/bin/python examples/replay_maps.py [OUT_DIR]     # default docs/

* `recordings_intel.png`: the Intel Research Lab CARMEN log, each FLASER scan at its
  corrected pose (black points), the corrected path (blue) and the ODOM lines' odometry
  (red; in this corrected log it stays within ~0.25 m of the corrected path). A
  crisp map is the check that the 180 degree beam layout (-90 deg .. +89 deg, 1 deg steps,
  counter-clockwise) is right: a mirrored or shifted fan smears every wall.
* `recordings_pico.png`: the real PICO bag (no odometry: the robot stood still), all 243
  scans in the robot frame, the robot at the centre.
"""

from __future__ import annotations

import sys
from pathlib import Path

import cv2
import numpy as np

from pico_studio.core.geometry import transform_points
from pico_studio.sources import open_bag, open_carmen

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "recordings"


def scan_points(scan, max_range: float) -> np.ndarray:
    r = scan.ranges
    ok = np.isfinite(r) & (r > scan.range_min) & (r < min(scan.range_max, max_range))
    a = scan.angles[ok]
    return np.column_stack([r[ok] * np.cos(a), r[ok] * np.sin(a)])


class Canvas:
    """World metres -> pixels, y up."""

    def __init__(self, lo: np.ndarray, hi: np.ndarray, px_per_m: float, margin: int = 20):
        self.lo, self.scale, self.margin = lo, px_per_m, margin
        size = np.ceil((hi - lo) * px_per_m).astype(int) + 2 * margin
        self.h, self.w = int(size[1]), int(size[0])
        self.img = np.full((self.h, self.w, 3), 255, np.uint8)

    def px(self, xy: np.ndarray) -> np.ndarray:
        p = (xy - self.lo) * self.scale + self.margin
        return np.column_stack([p[:, 0], self.h - p[:, 1]]).astype(np.int32)

    def dots(self, xy: np.ndarray, colour: tuple[int, int, int]) -> None:
        p = self.px(xy)
        ok = (p[:, 0] >= 0) & (p[:, 0] < self.w) & (p[:, 1] >= 0) & (p[:, 1] < self.h)
        self.img[p[ok, 1], p[ok, 0]] = colour

    def path(self, xy: np.ndarray, colour: tuple[int, int, int], width: int = 2) -> None:
        cv2.polylines(self.img, [self.px(xy).reshape(-1, 1, 2)], False, colour, width, cv2.LINE_AA)

    def text(self, s: str, row: int) -> None:
        cv2.putText(self.img, s, (10, 22 * row), cv2.FONT_HERSHEY_SIMPLEX, 0.55, (0, 0, 0), 1, cv2.LINE_AA)


def intel(out: Path) -> None:
    replay = open_carmen(DATA / "intel-corrected.log.gz")
    frames = [replay.frame(i) for i in range(replay.frame_count)]
    points = np.vstack([transform_points(scan_points(f.laser, 20.0), f.truth["pose"]) for f in frames])
    truth = np.array([f.truth["pose"][:2] for f in frames])
    odom = np.array([(o.x, o.y) for o in replay.recording.odometry])
    lo, hi = np.percentile(points, 0.2, axis=0) - 1, np.percentile(points, 99.8, axis=0) + 1
    c = Canvas(lo, hi, 25.0)
    c.dots(points, (40, 40, 40))
    c.path(truth, (220, 120, 0), 3)
    c.path(odom, (0, 0, 220), 1)
    c.text(f"intel-corrected.log.gz: {replay.frame_count} scans at the corrected pose", 1)
    c.text("blue: corrected path   red: raw odometry", 2)
    cv2.imwrite(str(out / "recordings_intel.png"), c.img)


def pico(out: Path) -> None:
    replay = open_bag(DATA / "pico_real_2019-05-07.bag")
    points = np.vstack([scan_points(replay.frame(i).laser, 10.0) for i in range(replay.frame_count)])
    lo, hi = points.min(axis=0) - 0.3, points.max(axis=0) + 0.3
    lo, hi = np.minimum(lo, -0.5), np.maximum(hi, 0.5)
    c = Canvas(lo, hi, 120.0)
    c.dots(points, (40, 40, 40))
    centre = c.px(np.zeros((1, 2)))[0]
    tip = c.px(np.array([[0.3, 0.0]]))[0]
    cv2.arrowedLine(c.img, tuple(int(v) for v in centre), tuple(int(v) for v in tip), (220, 120, 0), 2, tipLength=0.3)
    c.text(f"pico_real_2019-05-07.bag: {replay.frame_count} scans x 1081 beams, robot frame", 1)
    cv2.imwrite(str(out / "recordings_pico.png"), c.img)


if __name__ == "__main__":
    target = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "docs"
    target.mkdir(parents=True, exist_ok=True)
    intel(target)
    pico(target)
    print(f"wrote {target / 'recordings_intel.png'} and {target / 'recordings_pico.png'}")
