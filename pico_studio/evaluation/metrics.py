"""Every figure a run can be judged by, under one flat dotted name, and the default objective.

    flat = flatten(result)                  # {"walls.precision": 0.97, "doors.f1": ..., ...}
    flat["perception_score"]                # the documented default objective (0..1, higher better)
    METRICS["doors.recall"].help

`flatten` reads the summary dicts the evaluation writes (`RunScore.summary()` keys at the top
level or under "perceptor", `PoseScore.summary()` under "localisation", a behaviour run's
outcome) and returns only the metrics it finds, as floats.

**perception_score** = mean(wall F1, corner F1, door F1, convexity accuracy): one number that
rewards seeing the walls, corners and doors that are there and nothing else, with each of the
four kinds of structure weighing the same. F1 = 2PR / (P + R) (0 when both are 0).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Metric:
    name: str
    help: str
    higher_is_better: bool
    needs_truth: bool = True


def _m(name: str, help: str, higher: bool = True, truth: bool = True) -> Metric:  # noqa: A002
    return Metric(name, help, higher, truth)


METRICS: dict[str, Metric] = {m.name: m for m in (
    _m("walls.precision", "share of the local map's wall length on a true wall"),
    _m("walls.recall", "share of the truly visible wall length the local map covers"),
    _m("walls.f1", "harmonic mean of wall precision and recall"),
    _m("corners.precision", "share of detected corners at a true corner"),
    _m("corners.recall", "share of the true corners in view detected"),
    _m("corners.f1", "harmonic mean of corner precision and recall"),
    _m("corners.convexity", "share of matched corners whose convex/concave property is right"),
    _m("doors.precision", "share of detected doors at a true opening"),
    _m("doors.recall", "share of the openings in view (both jambs seen) detected"),
    _m("doors.f1", "harmonic mean of door precision and recall"),
    _m("map_doors.precision", "share of the localised robot's map-confirmed doors at a true opening"),
    _m("map_doors.recall", "share of the openings in view that a map-confirmed door found"),
    _m("endpoint_error_m", "mean distance of a wall end to the nearest true corner, m", higher=False),
    _m("localisation.pose_error_m.median", "median localised position error, m", higher=False),
    _m("localisation.pose_error_m.max", "largest localised position error, m", higher=False),
    _m("localisation.heading_error_rad.median", "median localised heading error, rad", higher=False),
    _m("localisation.heading_error_rad.max", "largest localised heading error, rad", higher=False),
    _m("localisation.lost_fraction", "share of frames the localisation was lost", higher=False),
    _m("perceptor.ms_per_scan", "median perceptor time per scan, ms", higher=False, truth=False),
    _m("perception_score", "mean of wall F1, corner F1, door F1 and convexity accuracy (0..1)"),
    _m("behaviour.success", "1 when the behaviour ended done (escaped, rooms / cabinets right when judged)"),
    _m("behaviour.collisions", "collisions during the behaviour run", higher=False),
    _m("behaviour.sim_seconds", "simulated seconds the behaviour run took", higher=False),
)}

DEFAULT_OBJECTIVE = "perception_score"

# RunScore.summary() key -> metric name
_RUN_KEYS = {
    "wall_precision": "walls.precision",
    "wall_recall": "walls.recall",
    "corner_precision": "corners.precision",
    "corner_recall": "corners.recall",
    "convexity_accuracy": "corners.convexity",
    "door_precision": "doors.precision",
    "door_recall": "doors.recall",
    "map_door_precision": "map_doors.precision",
    "map_door_recall": "map_doors.recall",
    "endpoint_error_m": "endpoint_error_m",
    "ms_per_scan": "perceptor.ms_per_scan",
}


def f1(p: float, r: float) -> float:
    return 2 * p * r / (p + r) if p + r > 0 else 0.0


def flatten(summary: dict[str, Any]) -> dict[str, float]:
    """The metrics found in `summary` (see the module docstring), as floats."""
    out: dict[str, float] = {}
    run = summary.get("perceptor") if isinstance(summary.get("perceptor"), dict) else summary
    if run is not None and "wall_precision" in run:
        for key, name in _RUN_KEYS.items():
            if isinstance(run.get(key), (int, float)):
                out[name] = float(run[key])
        for kind in ("walls", "corners", "doors"):
            out[f"{kind}.f1"] = f1(out[f"{kind}.precision"], out[f"{kind}.recall"])
        out["perception_score"] = perception_score(out)
    loc = summary.get("localisation")
    if isinstance(loc, dict):
        for key in ("pose_error_m", "heading_error_rad"):
            for stat in ("median", "max"):
                v = (loc.get(key) or {}).get(stat)
                if v is not None:
                    out[f"localisation.{key}.{stat}"] = float(v)
        if loc.get("lost_fraction") is not None:
            out["localisation.lost_fraction"] = float(loc["lost_fraction"])
    if "behaviour" in summary and "state" in summary:
        out.update(behaviour_metrics(summary))
    return out


def behaviour_metrics(summary: dict[str, Any]) -> dict[str, float]:
    """A behaviour run's outcome as metrics: success (ended done, escaped / rooms right when
    judged), collisions, simulated seconds."""
    ok = summary.get("state") == "done"
    if summary.get("behaviour") == "escape-room":
        ok = ok and bool(summary.get("escaped"))
    for key in ("rooms_right", "cabinets_right"):
        if key in summary:
            ok = ok and bool(summary[key])
    return {"behaviour.success": float(ok), "behaviour.collisions": float(summary.get("collisions", 0)),
            "behaviour.sim_seconds": float(summary.get("sim_seconds", 0.0))}


def perception_score(flat: dict[str, float]) -> float:
    """mean(wall F1, corner F1, door F1, convexity accuracy) of flattened metrics."""
    parts = (flat["walls.f1"], flat["corners.f1"], flat["doors.f1"], flat["corners.convexity"])
    return float(sum(parts) / len(parts))
