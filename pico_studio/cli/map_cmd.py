"""`pico-studio map info|convert`: inspect and convert global maps."""

from __future__ import annotations

import argparse
import json

from pico_studio.json_map import load_json_map


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("map", help="inspect or convert a global map (JSON or heightmap)")
    msub = p.add_subparsers(dest="map_command", metavar="ACTION", required=True)

    i = msub.add_parser("info", help="counts, bounds and warnings of a map")
    i.add_argument("file", help="a JSON map")
    i.add_argument("--json", action="store_true", help="print one JSON object")
    i.set_defaults(func=_info)


def _info(args: argparse.Namespace) -> int:
    m = load_json_map(args.file)
    x0, y0, x1, y1 = m.bounds
    info = {
        "file": args.file,
        "counts": m.counts(),
        "bounds_m": [x0, y0, x1, y1],
        "extent_m": [round(x1 - x0, 6), round(y1 - y0, 6)],
        "extra_keys": sorted(m.extra),
        "warnings": m.warnings,
    }
    if args.json:
        print(json.dumps(info))
        return 0
    print(f"{args.file}")
    print("  " + ", ".join(f"{v} {k}" for k, v in m.counts().items()))
    print(f"  extent {x1 - x0:.3g} x {y1 - y0:.3g} m, bounds x {x0:g}..{x1:g}, y {y0:g}..{y1:g}")
    for w in m.warnings:
        print(f"  warning: {w}")
    return 0
