"""`pico-studio map info|convert|generate`: inspect, draw and convert global maps (JSON or
heightmap), and write a generated world as a map and a sim config to serve or run."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from pico_studio.cli import limits
from pico_studio.config import Config, load_config
from pico_studio.errors import MapError
from pico_studio.json_map import GlobalMap, convert, load_map
from pico_studio.json_map.draw import draw_map, save_png
from pico_studio.user_files import check_output


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("map", help="inspect or convert a global map (JSON or heightmap)")
    msub = p.add_subparsers(dest="map_command", metavar="ACTION", required=True)

    i = msub.add_parser(
        "info",
        help="counts, bounds and warnings of a map",
        description="Counts (points, walls, cabinets/tables, doors), bounds and extent in metres, "
        "and warnings of a JSON map or a heightmap (.png/.pgm, or its map_server .yaml).",
    )
    i.add_argument("file", help="a map: .json, .png, .pgm or map_server .yaml")
    i.add_argument("--json", action="store_true", help="print one JSON object")
    i.add_argument("--png", metavar="OUT", help="also draw the map into this PNG file")
    _common(i, "pixel size (m/px) of an image without a map_server YAML")
    i.set_defaults(func=_info)

    c = msub.add_parser(
        "convert",
        help="JSON <-> heightmap, with the round-trip IoU",
        description="Convert a map by the output's suffix: .json (vector map), or .png/.pgm "
        "(heightmap image plus a map_server .yaml beside it), or .yaml. The converted map "
        "is rasterised again and its occupied pixels compared with the original's "
        "(intersection over union with a one-pixel tolerance).",
    )
    c.add_argument("input", help="the map to convert: .json, .png, .pgm or .yaml")
    c.add_argument("output", help="the file to write: .json, .png, .pgm or .yaml")
    _common(c, "pixel size (m/px) of the image written, or of an input image without a YAML")
    c.set_defaults(func=_convert)

    g = msub.add_parser(
        "generate",
        help="write a generated world (escape, rooms, hall, cafe, ward, suite, slant) as a JSON map and a sim config",
        description="Write the seeded world KIND:SEED (escape:3, rooms:5, hall:1, cafe:2, ward:3, suite:4, slant:5: the "
        "worlds the scenario sets name) as OUT.json and, beside it, OUT_sim.json: its start pose and "
        "its walking people, for `pico-studio serve --map OUT.json --sim-config OUT_sim.json`.",
    )
    g.add_argument("world", help="KIND:SEED, e.g. ward:3")
    g.add_argument("output", help="the JSON map to write (the sim config goes beside it, *_sim.json)")
    g.add_argument("--png", metavar="OUT", help="also draw the map into this PNG file")
    g.set_defaults(func=_generate)


def _common(p: argparse.ArgumentParser, resolution_help: str) -> None:
    p.add_argument("--resolution", type=limits.RESOLUTION, metavar="R", help=resolution_help)
    p.add_argument("--config", metavar="YAML", help="config file (map.heightmap / map.raster values)")


def _config(args: argparse.Namespace) -> Config:
    return load_config(args.config) if args.config else Config()


def map_summary(m: GlobalMap, file: str) -> dict[str, Any]:
    """What `map info --json` prints."""
    x0, y0, x1, y1 = m.bounds
    out: dict[str, Any] = {
        "file": file,
        "counts": m.counts(),
        "bounds_m": [round(v, 6) for v in (x0, y0, x1, y1)],
        "extent_m": [round(x1 - x0, 6), round(y1 - y0, 6)],
        "extra_keys": sorted(m.extra),
        "warnings": m.warnings,
    }
    if isinstance(m.extra.get("heightmap"), dict):
        out["heightmap"] = m.extra["heightmap"]
    return out


def _info(args: argparse.Namespace) -> int:
    if args.png:
        check_output(args.png, MapError)
    cfg = _config(args)
    m = load_map(args.file, cfg.map.heightmap, resolution=args.resolution)
    info = map_summary(m, args.file)
    if args.png:
        save_png(draw_map(m, title=Path(args.file).name), args.png)
        info["png"] = args.png
    if args.json:
        print(json.dumps(info))
        return 0
    x0, y0, x1, y1 = m.bounds
    print(f"{args.file}")
    print("  " + ", ".join(f"{v} {k}" for k, v in m.counts().items()))
    print(f"  extent {x1 - x0:.3g} x {y1 - y0:.3g} m, bounds x {x0:.4g}..{x1:.4g}, y {y0:.4g}..{y1:.4g}")
    if "heightmap" in info:
        h = info["heightmap"]
        print(
            f"  heightmap {h['shape'][1]} x {h['shape'][0]} px at {h['resolution']:g} m/px, "
            f"frame {h['frame']}, origin ({h['origin'][0]:g}, {h['origin'][1]:g})"
        )
    if m.extra:
        print(f"  extra keys: {', '.join(sorted(m.extra))}")
    for w in m.warnings:
        print(f"  warning: {w}")
    if args.png:
        print(f"  drawn: {args.png}")
    return 0


def _outputs(dst: Path) -> list[Path]:
    """The files `convert` writes for `dst`: an image comes with its map_server YAML."""
    suffix = dst.suffix.lower()
    if suffix in (".png", ".pgm"):
        return [dst, dst.with_suffix(".yaml")]
    if suffix in (".yaml", ".yml"):
        return [dst, dst.with_suffix(".png")]
    return [dst]


def _convert(args: argparse.Namespace) -> int:
    for out in _outputs(Path(args.output)):
        check_output(out, MapError)
    cfg = _config(args)
    result = convert(args.input, args.output, resolution=args.resolution, params=cfg.map)
    chk = result.check
    print(f"{args.input} -> {', '.join(str(p) for p in result.written)}")
    print("  " + ", ".join(f"{v} {k}" for k, v in result.map.counts().items()))
    doors = f", doors IoU {chk.iou_doors:.4f}" if chk.iou_doors is not None else ""
    print(
        f"  round trip: IoU {chk.iou:.4f} (1 px tolerance; {chk.iou_strict:.4f} exact){doors}, "
        f"occupied px {chk.reference_px} -> {chk.converted_px}"
    )
    for w in result.map.warnings:
        print(f"  warning: {w}")
    return 0


def _generate(args: argparse.Namespace) -> int:
    from pico_studio.evaluation.worlds import make_world, parse_world
    from pico_studio.json_map.json_io import save_json_map
    from pico_studio.sim.sim_config import SimConfigFile, sim_config_to_dict

    try:
        parse_world(args.world)
    except ValueError as e:
        raise MapError(str(e), field="world") from None
    out = Path(args.output)
    if out.suffix.lower() != ".json":
        raise MapError("the generated map is written as JSON: name a .json file", file=out)
    sim_out = out.with_name(out.stem + "_sim.json")
    for p in (out, sim_out, *([Path(args.png)] if args.png else [])):
        check_output(p, MapError)
    w = make_world(args.world)
    save_json_map(w.map, out)
    sc = w.sim_config if w.sim_config is not None else SimConfigFile(initial_pose=w.start)
    sim_out.write_text(json.dumps(sim_config_to_dict(sc), indent=2) + "\n", encoding="utf-8")
    counts = ", ".join(f"{v} {k}" for k, v in w.map.counts().items())
    print(f"{args.world} -> {out}, {sim_out}")
    print(f"  {counts}; {len(w.map.openings())} door openings; {len(sc.objects)} moving objects")
    if args.png:
        save_png(draw_map(w.map, title=f"{args.world}"), args.png)
        print(f"  drawn: {args.png}")
    print(f"  pico-studio serve --map {out} --sim-config {sim_out}")
    return 0
