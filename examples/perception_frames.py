"""Draw a few perceived frames of the real recordings (and one simulated) with OpenCV.

Each panel is one frame in the robot frame (x up, y left, the robot at the centre): laser
points grey, the current map blue, the local map green, corners (red convex, orange
concave), spike corners magenta, doors thick cyan, possible doors thin yellow.

    python examples/perception_frames.py            # writes docs/perception_*.png
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from pico_studio.config import Config, with_value
from pico_studio.core.geometry import invert, transform_points, transform_segments
from pico_studio.core.perception import Perceptor
from pico_studio.core.world_model import WorldModel
from pico_studio.sources import open_bag, open_carmen

ROOT = Path(__file__).resolve().parents[1]
REC = ROOT / "tests" / "data" / "recordings"
SIZE = 420


def panel(wm: WorldModel, title: str, span: float) -> np.ndarray:
    img = np.full((SIZE, SIZE, 3), 255, np.uint8)
    scale = SIZE / (2 * span)

    def px(p: np.ndarray) -> np.ndarray:  # robot frame (x fwd, y left) -> image (x up)
        p = np.asarray(p, dtype=float).reshape(-1, 2)
        return np.column_stack([SIZE / 2 - p[:, 1] * scale, SIZE / 2 - p[:, 0] * scale]).round().astype(np.int32)

    to_robot = invert(tuple(wm.pose))

    def lines(segs: np.ndarray, color: tuple[int, int, int], width: int, zero_frame: bool) -> None:
        segs = np.asarray(segs, dtype=float).reshape(-1, 4)
        if zero_frame:
            segs = transform_segments(segs, to_robot)
        for s in segs:
            a, b = px(s[0:2])[0], px(s[2:4])[0]
            cv2.line(img, tuple(map(int, a)), tuple(map(int, b)), color, width, cv2.LINE_AA)

    for p in px(wm.points):
        cv2.circle(img, tuple(map(int, p)), 1, (110, 110, 110), -1)
    lines(wm.local_map.walls, (80, 190, 80), 5, True)
    lines(wm.current_map, (200, 90, 20), 2, False)
    lines(wm.possible_doors, (0, 210, 230), 1, True)
    lines(wm.doors, (230, 200, 0), 4, True)
    corners = transform_points(np.asarray(wm.corners).reshape(-1, 2), to_robot)
    for c, convex in zip(px(corners), wm.corner_convex, strict=True):
        cv2.circle(img, tuple(map(int, c)), 5, (30, 30, 220) if convex else (0, 140, 255), 2, cv2.LINE_AA)
    for c in px(wm.spike_corners):
        cv2.drawMarker(img, tuple(map(int, c)), (200, 0, 200), cv2.MARKER_TILTED_CROSS, 8, 1)
    cv2.drawMarker(img, (SIZE // 2, SIZE // 2), (0, 0, 0), cv2.MARKER_TRIANGLE_UP, 12, 2)
    cv2.putText(img, title, (6, 16), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (0, 0, 0), 1, cv2.LINE_AA)
    info = f"{len(wm.current_map)} walls, {len(wm.local_map.walls)} local, {len(wm.corners)} corners, {len(wm.doors)} doors"
    cv2.putText(img, info, (6, SIZE - 8), cv2.FONT_HERSHEY_SIMPLEX, 0.4, (60, 60, 60), 1, cv2.LINE_AA)
    cv2.rectangle(img, (0, 0), (SIZE - 1, SIZE - 1), (0, 0, 0), 1)
    return img


def frames(replay, params, picks: list[int]) -> list[tuple[int, WorldModel]]:
    p = Perceptor(params)
    out = []
    for i in range(replay.frame_count):
        f = replay.frame(i)
        wm = p.step(f.laser, f.odometry)
        if i in picks:
            out.append((i, wm))
    return out


def main() -> None:
    cfg = Config()
    bag = open_bag(REC / "pico_real_2019-05-07.bag")
    picks = [40, 120, 230]
    row1 = [panel(wm, f"PICO bag, scan {i}", 3.0) for i, wm in frames(bag, cfg.perception, picks)]
    intel_cfg = with_value(with_value(cfg, "perception.merge.keep_radius", 6.0), "perception.locate.jump_distance", 2.0)
    intel = open_carmen(REC / "intel-corrected.log.gz")
    picks = [150, 450, 800]
    row2 = [panel(wm, f"Intel lab, scan {i}", 8.0) for i, wm in frames(intel, intel_cfg.perception, picks)]
    out = ROOT / "docs" / "perception_real_frames.png"
    cv2.imwrite(str(out), np.vstack([np.hstack(row1), np.hstack(row2)]))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
