"""The README's door tables from a scenario set's scores: per family (scenario names without
their trailing number) the mean and, in brackets, the worst world, and the whole set pooled
over doors (every door counted once, not every world); or one row per world.

    pico-studio eval --scenarios examples/scenarios/perception_worlds.yaml --workers 2 --json > worlds.json
    python examples/door_figures.py worlds.json            # per family
    python examples/door_figures.py worlds.json --worlds   # per world
"""

from __future__ import annotations

import argparse
import json
import re
from collections import defaultdict
from typing import Any

COLUMNS = [  # (heading, summary key): the worst world is the lowest
    ("own door P", "door_precision"),
    ("own door R", "door_recall"),
    ("map door R", "map_door_recall"),
    ("map door P", "map_door_precision"),
    ("convexity", "convexity_accuracy"),
]


def family(name: str) -> str:
    """`cafe17` -> `cafe`, `h2021_s0` -> `h2021`, `rest3` -> `rest`."""
    return re.sub(r"(_s)?\d+$", "", name) or name


def _summary(result: dict[str, Any]) -> dict[str, Any]:
    s = result.get("summary", {})
    return s.get("perceptor", s)  # a whole run nests the perceptor's scores


def _cell(values: list[float]) -> str:
    if not values:
        return "-"
    mean, worst = f"{sum(values) / len(values):.3f}", f"{min(values):.3f}"
    return mean if worst == mean else f"{mean} ({worst})"


def pooled(rows: list[dict[str, Any]]) -> tuple[float, float]:
    """Own door precision and recall over every door of `rows` (detected, visible)."""
    det = sum(r.get("doors_detected") or 0 for r in rows)
    vis = sum(r.get("doors_visible") or 0 for r in rows)
    tp = sum((r.get("door_precision") or 0.0) * (r.get("doors_detected") or 0) for r in rows)
    tv = sum((r.get("door_recall") or 0.0) * (r.get("doors_visible") or 0) for r in rows)
    return (tp / det if det else float("nan"), tv / vis if vis else float("nan"))


def family_table(scenarios: dict[str, Any]) -> str:
    groups: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for name, result in scenarios.items():
        groups[family(name)].append(_summary(result))
    out = ["| worlds | n | " + " | ".join(h for h, _ in COLUMNS) + " | end points (cm, worst) |",
           "|---|---|" + "---|" * (len(COLUMNS) + 1)]
    for fam, rows in groups.items():
        cells = [_cell([r[k] for r in rows if r.get(k) is not None]) for _, k in COLUMNS]
        ep = [100 * r["endpoint_error_m"] for r in rows if r.get("endpoint_error_m") is not None]
        worst = f"{max(ep):.1f}" if ep else "-"
        out.append(f"| {fam} | {len(rows)} | " + " | ".join(cells) + f" | {worst} |")
    p, r = pooled([_summary(v) for v in scenarios.values()])
    out.append(f"\nAll {len(scenarios)} pooled over doors: own door precision {p:.3f}, recall {r:.3f}.")
    return "\n".join(out)


def world_table(scenarios: dict[str, Any]) -> str:
    out = ["| world | " + " | ".join(h for h, _ in COLUMNS) + " | end points (cm) | wall P |",
           "|---|" + "---|" * (len(COLUMNS) + 2)]
    for name, result in scenarios.items():
        s = _summary(result)
        cells = ["-" if s.get(k) is None else f"{s[k]:.3f}" for _, k in COLUMNS]
        ep = "-" if s.get("endpoint_error_m") is None else f"{100 * s['endpoint_error_m']:.1f}"
        wp = "-" if s.get("wall_precision") is None else f"{s['wall_precision']:.3f}"
        out.append(f"| {name} | " + " | ".join(cells) + f" | {ep} | {wp} |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    ap.add_argument("scores", help="the output of `pico-studio eval --scenarios FILE --json`")
    ap.add_argument("--worlds", action="store_true", help="one row per world instead of per family")
    args = ap.parse_args(argv)
    with open(args.scores, encoding="utf-8") as f:
        scenarios = json.load(f)["scenarios"]
    print(world_table(scenarios) if args.worlds else family_table(scenarios))


if __name__ == "__main__":
    main()
