"""Draw what the simulator knows: the map, one scan, and the ground truth visible from the pose.

    python examples/sim_truth.py [--map M] [--sim-config C] [--pose X Y A] [--out docs/sim_truth.png]

Grey: the map's walls and cabinets; dark green: doors (light when opened); blue boxes: moving
objects; orange dots: the (noisy) scan; green: visible wall pieces;
red/blue discs: convex/concave corners in view; thin purple: all door openings; thick purple:
the visible ones; the robot's collision box in black.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np

from pico_studio.core.geometry import transform_points
from pico_studio.json_map import load_map
from pico_studio.sim import Simulator, load_sim_config

ROOT = Path(__file__).resolve().parents[1]


def draw(sim: Simulator, scale: float = 100.0, margin: int = 20) -> np.ndarray:
    x0, y0, x1, y1 = sim.world.map.bounds
    w, h = int((x1 - x0) * scale) + 2 * margin, int((y1 - y0) * scale) + 2 * margin
    img = np.full((h, w, 3), 255, np.uint8)

    def px(p: np.ndarray) -> np.ndarray:
        return np.column_stack([(p[:, 0] - x0) * scale + margin, (y1 - p[:, 1]) * scale + margin]).astype(np.int32)

    def lines(segs: np.ndarray, color: tuple[int, int, int], width: int) -> None:
        for a, b in zip(px(segs[:, :2]), px(segs[:, 2:]), strict=True):
            cv2.line(img, tuple(map(int, a)), tuple(map(int, b)), color, width, cv2.LINE_AA)

    truth = sim.truth
    lines(truth.segments(), (170, 170, 170), 2)
    for outline, opened in truth.doors():
        cv2.polylines(img, [px(outline)], True, (0, 200, 0) if opened else (0, 120, 0), 2)
    for box in truth.moving_objects():
        cv2.fillPoly(img, [px(box)], (230, 160, 60))
    lines(truth.door_openings(), (200, 80, 200), 1)
    lines(truth.visible_walls(), (0, 170, 0), 3)
    lines(truth.visible_doors(), (200, 80, 200), 4)
    scan = sim.read_laser()
    if scan is not None:
        ok = (scan.ranges >= scan.range_min) & (scan.ranges <= scan.range_max)
        pts = np.column_stack([scan.ranges * np.cos(scan.angles), scan.ranges * np.sin(scan.angles)])[ok]
        for p in px(transform_points(pts, truth.pose)):
            cv2.circle(img, tuple(map(int, p)), 2, (0, 140, 255), -1)
    corners = truth.visible_corners()
    for p, convex in zip(px(corners.points), corners.convex, strict=True):
        cv2.circle(img, tuple(map(int, p)), 5, (0, 0, 220) if convex else (220, 0, 0), -1)
    hl, hw = sim.base.half_length, sim.base.half_width
    box = transform_points(np.array([[hl, hw], [-hl, hw], [-hl, -hw], [hl, -hw]]), truth.pose)
    cv2.polylines(img, [px(box)], True, (0, 0, 0), 2)
    return img


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--map", default=str(ROOT / "pico_studio" / "data" / "maps" / "hospital_2019.json"))
    ap.add_argument("--pose", type=float, nargs=3, help="x y a (default: the simulator's start)")
    ap.add_argument("--sim-config", help="the official simulator's config JSON (moving objects, ...)")
    ap.add_argument("--out", default=str(ROOT / "docs" / "sim_truth.png"))
    ap.add_argument("--scale", type=float, default=100.0, help="pixels per metre")
    args = ap.parse_args()
    sim = Simulator(
        load_map(args.map),
        sim_config=load_sim_config(args.sim_config) if args.sim_config else None,
        initial_pose=tuple(args.pose) if args.pose else None,
        seed=1,
    )
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    cv2.imwrite(args.out, draw(sim, scale=args.scale))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
