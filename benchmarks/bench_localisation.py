"""Localisation quality and cost, on the simulator with its ground truth.

For hospital_2019 and restaurant_2024 (with the moving object of its sim config) the robot
follows a scripted route of waypoints through free space for 3 simulated minutes at 20 Hz
with uncertain odometry; halfway it is kicked 0.5 m and 20 deg (kidnapped: the odometry does
not see it). Reported per map: time to the first fix from the prior, median / max position
and heading error while tracking (the 10 s after the kick excluded), when the kick was
flagged and when it was recovered, and the cost per step (median and 95th percentile of
tracking steps; searches, which run only when lost, separately). Then the wrong-map case:
the restaurant world localised on the hospital map must stay lost.

    .venv/bin/python benchmarks/bench_localisation.py [--seconds 180] [--gain-error 0.002]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import time
from pathlib import Path

import numpy as np

from pico_studio.config import Config, with_value
from pico_studio.core.geometry import compose, relative, wrap_angle
from pico_studio.core.localisation import Localiser
from pico_studio.core.localisation.inputs import odometry_pose
from pico_studio.jit import uncompiled
from pico_studio.json_map import load_json_map
from pico_studio.sim import Simulator, load_sim_config

MAPS = Path(__file__).resolve().parents[1] / "pico_studio" / "data" / "maps"
DT = 0.05

ROUTES: dict[str, dict] = {
    "hospital_2019": {
        "sim_config": None,
        "start": (3.5, 0.5, math.pi / 2),
        # corridor, the right room through its door, the top-left and left rooms, back
        "waypoints": [(3.5, 5.4), (5.5, 5.4), (5.5, 3.0), (5.5, 5.4), (3.5, 5.4), (1.5, 5.6),
                      (1.2, 3.1), (1.2, 1.0), (3.5, 1.6), (3.5, 0.5)],
    },
    "restaurant_2024": {
        "sim_config": "restaurant_2024_sim.json",
        "start": None,  # the sim config's initial pose
        "waypoints": [(5.4, 3.4), (5.4, 0.8), (3.5, 0.8), (5.4, 0.8), (5.4, 3.4), (3.2, 3.6),
                      (1.5, 3.6), (1.5, 0.9), (1.5, 3.6), (3.2, 3.6), (6.0, 3.5)],
    },
}


class RouteFollower:
    """Drive through the waypoints on the true pose (a test harness, not a behaviour)."""

    def __init__(self, waypoints: list[tuple[float, float]], speed: float = 0.4):
        self.waypoints, self.speed, self.k = waypoints, speed, 0

    def command(self, pose: tuple[float, float, float]) -> tuple[float, float, float]:
        wx, wy = self.waypoints[self.k % len(self.waypoints)]
        if math.hypot(wx - pose[0], wy - pose[1]) < 0.1:
            self.k += 1
            wx, wy = self.waypoints[self.k % len(self.waypoints)]
        local = relative(pose, (wx, wy, 0.0))
        dist = math.hypot(local[0], local[1])
        v = min(self.speed, dist) / max(dist, 1e-9)
        turn = float(wrap_angle(math.atan2(wy - pose[1], wx - pose[0]) - pose[2]))
        if abs(turn) > 0.5:  # turn on the spot first: the footprint is long sideways
            v = 0.0
        return local[0] * v, local[1] * v, float(np.clip(2.0 * turn, -1.0, 1.0))


def kicked_pose(sim: Simulator, rng: np.random.Generator) -> tuple[float, float, float]:
    """The true pose moved 0.5 m (in a free direction) and turned 20 deg."""
    pose = sim.truth.pose
    for a in rng.permutation(16) * (2 * math.pi / 16):
        cand = (pose[0] + 0.5 * math.cos(a), pose[1] + 0.5 * math.sin(a),
                float(wrap_angle(pose[2] + math.radians(20))))
        if not sim.base.collides(cand, sim.world.segments()).any() and _clear(sim, pose, cand):
            return cand
    raise RuntimeError("no free place to kick the robot to")


def _clear(sim: Simulator, a: tuple, b: tuple, margin: float = 0.3) -> bool:
    from pico_studio.core.geometry import point_segment_distance
    pts = np.linspace(a[:2], b[:2], 11)
    return bool(point_segment_distance(pts[-1:], sim.world.segments()).min() > margin)


def run(name: str, *, seconds: float, gain_error: float, kick_at: float | None, seed: int = 0,
        localise_on: str | None = None) -> dict:
    route = ROUTES[name]
    cfg = Config()
    cfg = with_value(cfg, "sim.odometry.gain_error", gain_error)
    cfg = with_value(cfg, "sim.odometry.random_offset", True)  # the odometry frame starts anywhere
    cfg = with_value(cfg, "sim.odometry.uncertain", True)
    world_map = load_json_map(MAPS / f"{name}.json")
    sim_config = load_sim_config(MAPS / route["sim_config"]) if route["sim_config"] else None
    if sim_config is not None:
        sim_config = dataclasses.replace(sim_config, uncertain_odom=True)
    sim = Simulator(world_map, cfg.sim, sim_config, seed=seed, initial_pose=route["start"])
    start = sim.truth.pose
    odom_start = sim.truth.odometry_pose
    dead_reckoning = 0.0  # worst error of odometry alone (from the true start), before the kick
    global_map = load_json_map(MAPS / f"{localise_on or name}.json")
    loc = Localiser(cfg.localisation, global_map, initial_pose=start)
    follower = RouteFollower(route["waypoints"])
    rng = np.random.default_rng(seed)

    rows = []  # t, pos err, head err, lost, ms, searched
    track: list[tuple[tuple, tuple | None, bool]] = []  # true pose, estimate, lost
    odom = None
    kicked_t = None
    steps = int(round(seconds / DT))
    for _ in range(steps):
        sim.send_base_reference(*follower.command(sim.truth.pose))
        sim.advance(DT)
        t = sim.now()
        if kicked_t is None:
            dr = compose(start, relative(odom_start, sim.truth.odometry_pose))
            dead_reckoning = max(dead_reckoning, math.hypot(dr[0] - sim.truth.pose[0], dr[1] - sim.truth.pose[1]))
        if kick_at is not None and kicked_t is None and t >= kick_at:
            sim.base.pose = kicked_pose(sim, rng)
            kicked_t = t
        laser = sim.read_laser()
        odom = odometry_pose(odom, sim.read_odometry())
        if laser is None or odom is None:
            continue
        r = loc.step(laser.points, odom)
        true = sim.truth.pose
        track.append((true, r.pose, r.lost))
        if r.pose is None:
            rows.append((t, math.nan, math.nan, r.lost, loc.last_ms, r.searched))
        else:
            rows.append((t, math.hypot(r.pose[0] - true[0], r.pose[1] - true[1]),
                         abs(float(wrap_angle(r.pose[2] - true[2]))), r.lost, loc.last_ms, r.searched))
    out = summarise(name, rows, kicked_t, sim, gain_error, localise_on)
    out["odometry_alone_max_error_m"] = round(dead_reckoning, 3)
    out["_track"] = track
    out["_map"] = global_map
    return out


def summarise(name, rows, kicked_t, sim, gain_error, localise_on) -> dict:
    t = np.array([r[0] for r in rows])
    pos = np.array([r[1] for r in rows])
    head = np.array([r[2] for r in rows])
    lost = np.array([r[3] for r in rows])
    ms = np.array([r[4] for r in rows])
    searched = np.array([r[5] for r in rows])
    out: dict = {"map": name, "localised_on": localise_on or name, "gain_error": gain_error,
                 "sim_seconds": round(float(t[-1]), 2), "distance_m": round(sim.truth.distance, 1),
                 "collisions": sim.truth.collisions, "lost_fraction": round(float(lost.mean()), 3)}
    found = np.flatnonzero(~lost)
    out["first_fix_s"] = round(float(t[found[0]]), 2) if len(found) else None
    if localise_on:
        out["ever_found"] = bool(len(found))
        out["ms_per_step_median"] = round(float(np.median(ms)), 2)
        out["ms_per_step_max"] = round(float(ms.max()), 1)
        return out
    tracking = ~lost & np.isfinite(pos)
    if kicked_t is not None:
        tracking &= ~((t >= kicked_t) & (t < kicked_t + 10.0))
        after = t >= kicked_t
        flagged = np.flatnonzero(after & lost)
        out["kick_flagged_after_s"] = round(float(t[flagged[0]] - kicked_t), 2) if len(flagged) else None
        if len(flagged):
            rec = np.flatnonzero((t > t[flagged[0]]) & ~lost & (pos < 0.1))
            out["kick_recovered_after_s"] = round(float(t[rec[0]] - kicked_t), 2) if len(rec) else None
        else:
            out["kick_recovered_after_s"] = None
    out["pose_error_m"] = {"median": round(float(np.median(pos[tracking])), 4),
                           "max": round(float(pos[tracking].max()), 4)}
    out["heading_error_deg"] = {"median": round(math.degrees(float(np.median(head[tracking]))), 3),
                                "max": round(math.degrees(float(head[tracking].max())), 3)}
    plain = tracking & ~searched
    out["ms_per_step"] = {"median": round(float(np.median(ms[plain])), 2),
                          "p95": round(float(np.percentile(ms[plain]), 95) if False else float(np.percentile(ms[plain], 95)), 2)}
    out["ms_per_search_step"] = {"median": round(float(np.median(ms[searched])), 1) if searched.any() else None,
                                 "count": int(searched.sum())}
    return out


def draw(global_map, track, path: Path, scale: float = 100.0) -> None:
    """The map (walls black, objects grey), the true path (green) and the estimates (blue;
    red while lost), the kick as a jump in the green path."""
    import cv2

    x0, y0, x1, y1 = global_map.bounds
    margin = 0.3
    h, w = int((y1 - y0 + 2 * margin) * scale), int((x1 - x0 + 2 * margin) * scale)
    img = np.full((h, w, 3), 255, np.uint8)

    def px(x: float, y: float) -> tuple[int, int]:
        return int((x - x0 + margin) * scale), int(h - (y - y0 + margin) * scale)

    for poly in global_map.objects:
        for s in global_map.segments_of(poly):
            cv2.line(img, px(*s[:2]), px(*s[2:]), (170, 170, 170), 2, cv2.LINE_AA)
    for poly in global_map.doors:
        for s in global_map.segments_of(poly):
            cv2.line(img, px(*s[:2]), px(*s[2:]), (0, 160, 230), 2, cv2.LINE_AA)
    for s in global_map.wall_segments:
        cv2.line(img, px(*s[:2]), px(*s[2:]), (0, 0, 0), 2, cv2.LINE_AA)
    for (t0, _, _), (t1, _, _) in zip(track, track[1:], strict=False):
        if math.hypot(t1[0] - t0[0], t1[1] - t0[1]) < 0.2:  # not across the kick
            cv2.line(img, px(*t0[:2]), px(*t1[:2]), (60, 180, 60), 3, cv2.LINE_AA)
    for (t0, _, _), (t1, _, _) in zip(track, track[1:], strict=False):
        if math.hypot(t1[0] - t0[0], t1[1] - t0[1]) >= 0.2:  # the kick: from, to
            cv2.arrowedLine(img, px(*t0[:2]), px(*t1[:2]), (0, 0, 230), 2, cv2.LINE_AA, tipLength=0.25)
    for k, (_, est, lost) in enumerate(track):
        if est is not None and (lost or k % 4 == 0):
            cv2.circle(img, px(*est[:2]), 2, (0, 0, 230) if lost else (200, 80, 0), -1, cv2.LINE_AA)
    cv2.putText(img, "true path (green), estimate (blue; red while lost), kick (red arrow)", (8, 20),
                cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
    path.parent.mkdir(parents=True, exist_ok=True)
    cv2.imwrite(str(path), img)


def kick_trials(name: str, *, kicks: int, seed: int = 0) -> dict:
    """Kick after kick: drive 3-8 s, kick 0.5 m and +-20 deg, watch 10 s. Counts how many
    were flagged, how many recovered (not lost, error < 10 cm) within 10 s and how fast, and
    steps that claimed a fix more than 10 cm off (the step right after a kick, before the
    flag can rise, excepted)."""
    route = ROUTES[name]
    cfg = with_value(with_value(Config(), "sim.odometry.uncertain", True), "sim.odometry.random_offset", True)
    world_map = load_json_map(MAPS / f"{name}.json")
    sim_config = load_sim_config(MAPS / route["sim_config"]) if route["sim_config"] else None
    sim = Simulator(world_map, cfg.sim, sim_config, seed=seed, initial_pose=route["start"])
    loc = Localiser(cfg.localisation, world_map, initial_pose=sim.truth.pose)
    follower = RouteFollower(route["waypoints"])
    rng = np.random.default_rng(seed)
    odom = None

    def drive(seconds: float) -> list[tuple[bool, float]]:
        nonlocal odom
        out = []
        for _ in range(int(round(seconds / DT))):
            sim.send_base_reference(*follower.command(sim.truth.pose))
            sim.advance(DT)
            laser = sim.read_laser()
            odom = odometry_pose(odom, sim.read_odometry())
            if laser is None or odom is None:
                continue
            r = loc.step(laser.points, odom)
            t = sim.truth.pose
            err = math.inf if r.pose is None else math.hypot(r.pose[0] - t[0], r.pose[1] - t[1])
            out.append((r.lost, err))
        return out

    drive(5.0)
    flagged = recovered = false_fix = 0
    times = []
    for _ in range(kicks):
        drive(float(rng.uniform(3.0, 8.0)))
        pose = sim.truth.pose
        turn = math.radians(20) * float(rng.choice([-1.0, 1.0]))
        for a in rng.permutation(16) * (2 * math.pi / 16):
            cand = (pose[0] + 0.5 * math.cos(a), pose[1] + 0.5 * math.sin(a), float(wrap_angle(pose[2] + turn)))
            if _clear(sim, pose, cand):
                sim.base.pose = cand
                break
        after = drive(10.0)
        lost = [x[0] for x in after]
        if True in lost:
            flagged += 1
            first = lost.index(True)
            ok = [j for j in range(first, len(after)) if not after[j][0] and after[j][1] < 0.1]
            if ok:
                recovered += 1
                times.append(ok[0] * DT)
        false_fix += sum(1 for lo, e in after[1:] if not lo and e > 0.1)
    return {"map": name, "kicks": kicks, "flagged": flagged, "recovered_within_10s": recovered,
            "recovery_s_median": round(float(np.median(times)), 2) if times else None,
            "recovery_s_max": round(float(np.max(times)), 2) if times else None,
            "steps_with_a_wrong_fix": false_fix}


def cost(name: str, *, seconds: float = 20.0, repeats: int = 5, seed: int = 0, python_steps: int = 45) -> dict:
    """Cost per step on recorded frames: the same scans replayed `repeats` times through a
    fresh localiser; per step the median over the repeats, then the median and 95th
    percentile over the steps. A lost-recovery search (1 m box, any heading) likewise. The
    first `python_steps` steps once more with every compiled loop as its Python
    (`jit.uncompiled`): their CPU cost, and the largest pose difference (the same answers)."""
    from pico_studio.core.localisation.tracker import _search_around

    route = ROUTES[name]
    cfg = with_value(with_value(Config(), "sim.odometry.uncertain", True), "sim.odometry.random_offset", True)
    world_map = load_json_map(MAPS / f"{name}.json")
    sim_config = load_sim_config(MAPS / route["sim_config"]) if route["sim_config"] else None
    sim = Simulator(world_map, cfg.sim, sim_config, seed=seed, initial_pose=route["start"])
    follower = RouteFollower(route["waypoints"])
    frames, odom = [], None
    for _ in range(int(round(seconds / DT))):
        sim.send_base_reference(*follower.command(sim.truth.pose))
        sim.advance(DT)
        laser = sim.read_laser()
        odom = odometry_pose(odom, sim.read_odometry())
        if laser is not None and odom is not None:
            frames.append((laser.points, odom))
    start = sim.truth.pose
    times = np.zeros((repeats, len(frames)))
    cpu = np.zeros((repeats, len(frames)))  # CPU time: less disturbed by other jobs on the machine
    poses = []
    for r in range(repeats):
        loc = Localiser(cfg.localisation, world_map, initial_pose=route["start"] or (6.0, 3.5, 3.14))
        for k, (pts, o) in enumerate(frames):
            t0, c0 = time.perf_counter(), time.process_time()
            res = loc.step(pts, o)
            times[r, k] = (time.perf_counter() - t0) * 1000
            cpu[r, k] = (time.process_time() - c0) * 1000
            if r == 0:
                poses.append(res.pose)
    per_step = np.median(times, axis=0)[5:]  # the first steps search from the prior
    per_step_cpu = np.median(cpu, axis=0)[5:]
    # the peer: the same steps with every compiled loop as its Python (first `python_steps`)
    slow_cpu, diff = [], 0.0
    with uncompiled():
        loc = Localiser(cfg.localisation, world_map, initial_pose=route["start"] or (6.0, 3.5, 3.14))
        for k, (pts, o) in enumerate(frames[:python_steps]):
            c0 = time.process_time()
            res = loc.step(pts, o)
            slow_cpu.append((time.process_time() - c0) * 1000)
            if (res.pose is None) != (poses[k] is None):
                diff = math.inf
            elif res.pose is not None:
                diff = max(diff, float(np.abs(np.subtract(res.pose, poses[k])).max()))
    search_ms = []
    pts = frames[-1][0]
    for _ in range(repeats):
        t0 = time.perf_counter()
        _search_around(loc.lmap, pts, start, cfg.localisation.search.lost_radius, cfg.localisation)
        search_ms.append((time.perf_counter() - t0) * 1000)
    return {"map": name, "steps": len(frames), "repeats": repeats,
            "ms_per_step_median": round(float(np.median(per_step)), 2),
            "ms_per_step_p95": round(float(np.percentile(per_step, 95)), 2),
            "cpu_ms_per_step_median": round(float(np.median(per_step_cpu)), 2),
            "cpu_ms_per_step_p95": round(float(np.percentile(per_step_cpu, 95)), 2),
            "cpu_ms_per_step_py_func": round(float(np.median(slow_cpu[5:])), 2),
            "compiled_speedup": round(float(np.median(slow_cpu[5:]) / np.median(per_step_cpu[: python_steps - 5])), 1),
            "same_poses_as_py_func_within": diff,
            "ms_per_recovery_search_median": round(float(np.median(search_ms)), 1)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seconds", type=float, default=180.0)
    ap.add_argument("--gain-error", type=float, default=0.002, help="odometry wheel-gain error (sim default 0.002)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--png-dir", default="", help="draw each run's map and paths here (e.g. docs)")
    ap.add_argument("--cost-only", action="store_true", help="only the cost per step")
    ap.add_argument("--kicks", type=int, default=10, help="kicks per map in the repeated-kick trial (0: none)")
    args = ap.parse_args()
    t0 = time.perf_counter()
    costs = [cost(name, seed=args.seed) for name in ROUTES]
    for c in costs:
        print(json.dumps(c))
    if args.cost_only:
        return
    results = []
    for name in ROUTES:
        results.append(run(name, seconds=args.seconds, gain_error=args.gain_error,
                           kick_at=args.seconds / 2, seed=args.seed))
    results.append(run("restaurant_2024", seconds=min(args.seconds, 60.0), gain_error=args.gain_error,
                       kick_at=None, seed=args.seed, localise_on="hospital_2019"))
    if args.kicks:
        results += [kick_trials(name, kicks=args.kicks, seed=args.seed + 1) for name in ROUTES]
    for r in results[:2]:
        if args.png_dir:
            path = Path(args.png_dir) / f"localisation_{r['map']}.png"
            draw(r["_map"], r["_track"], path)
            print(f"# drawn {path}")
    results = [{k: v for k, v in r.items() if not k.startswith("_")} for r in results]
    if args.json:
        print(json.dumps(results, indent=1))
    else:
        for r in results:
            print(json.dumps(r))
    print(f"# {time.perf_counter() - t0:.1f} s wall")


if __name__ == "__main__":
    main()
