"""`pico-studio render`: the page's top-down view drawn headless into a video or an image.

    pico-studio render --map examples/maps/hospital_2019.json --to 20 --out run.mp4
    pico-studio render --source bag:run.bag --from 2 --to 5 --out replay.gif
    pico-studio render --source carmen:intel.log --map intel.png --to 60 --out last.png

One image per perceived frame (a scan) in the window, the same layers, colours and draw
order as the web page (`pico_studio.ui.render`, OpenCV only); .png keeps the last one.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from pico_studio.cli import limits
from pico_studio.cli.plugin_args import add_plugin_argument

DEFAULT_SIM_SECONDS = 20.0


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("render", help="draw the page's top-down view of a run or a recording into .mp4, .gif or .png")
    p.add_argument("--map", help="a JSON map or heightmap image; alone: simulated in it")
    p.add_argument("--source", default="sim", help="sim (default, needs --map), bag:FILE or carmen:FILE")
    p.add_argument("--sim-config", help="simulator config JSON (initial pose, moving objects, ...)")
    p.add_argument("--config", help="a (partial) config YAML")
    p.add_argument("--behaviour", default="wander", help="what drives a simulated robot (as for serve)")
    p.add_argument("--seed", type=limits.SEED, default=None, help="simulator random seed")
    p.add_argument("--from", dest="t_from", type=limits.SECONDS, default=0.0, help="start, seconds from the beginning (default 0)")
    p.add_argument("--to", dest="t_to", type=limits.SECONDS, default=None,
                   help=f"end, seconds from the beginning (default: the recording's end; {DEFAULT_SIM_SECONDS:g} s simulated)")
    p.add_argument("--width", type=limits.PIXELS, default=900, help="image width in pixels (default 900)")
    p.add_argument("--fps", type=limits.FPS, default=None, help="video frame rate (default: the control rate, ui.rate_hz)")
    p.add_argument("--out", required=True, help="FILE.mp4, FILE.gif or FILE.png")
    add_plugin_argument(p)
    p.set_defaults(func=_render)


def _render(args: argparse.Namespace) -> int:
    from pico_studio.config import load_config
    from pico_studio.errors import UserError
    from pico_studio.json_map import load_map
    from pico_studio.progress import Progress
    from pico_studio.ui.clock import is_replay
    from pico_studio.ui.render import FORMATS, render_run
    from pico_studio.ui.runtime import Studio
    from pico_studio.ui.sources import make_source_factory

    out = Path(args.out)
    if out.suffix.lower() not in FORMATS:
        raise UserError(f"write .mp4, .gif or .png, not {out.suffix or 'no suffix'}", field="--out")
    for name, v in (("--from", args.t_from), ("--to", args.t_to), ("--fps", args.fps)):
        if v is not None and (not math.isfinite(v) or v < 0):
            raise UserError(f"must be a finite number >= 0, got {v}", field=name)
    if args.t_to is not None and args.t_to < args.t_from:
        raise UserError(f"--to {args.t_to:g} is before --from {args.t_from:g}", field="--to")
    if not 64 <= args.width <= 8192:
        raise UserError(f"must be between 64 and 8192 pixels, got {args.width}", field="--width")
    simulated = args.source == "sim"
    if simulated and not args.map:
        raise UserError("simulating needs a map: give --map, or --source bag:FILE / carmen:FILE", field="--map")
    cfg = load_config(args.config)
    global_map = load_map(args.map, cfg.map) if args.map else None
    factory = make_source_factory(args.source, args.sim_config, args.seed)
    behaviour = args.behaviour if simulated else "stop"
    studio = Studio(cfg, global_map, factory, behaviour=behaviour, map_name=Path(args.map or args.source).name)
    studio.playing = False
    t_to = args.t_to
    if t_to is None:
        if is_replay(studio.source):
            t0, t1 = studio.source.time_span
            t_to = t1 - t0
        else:
            t_to = DEFAULT_SIM_SECONDS
    with Progress(total=max(t_to - args.t_from, 0.0), label=f"rendering {out.name}", unit="s") as bar:
        n = render_run(studio, out, t_from=args.t_from, t_to=t_to, width=args.width, fps=args.fps, progress=bar.set)
    print(f"pico-studio: wrote {out} ({n} frame{'s' if n != 1 else ''}, {args.t_from:g}..{t_to:g} s)")
    return 0
