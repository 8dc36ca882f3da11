"""`pico-studio serve`: the web UI on a map, simulated (default) or on a recording / the robot."""

from __future__ import annotations

import argparse
import logging
import threading
import time
from pathlib import Path

from pico_studio.cli import limits
from pico_studio.cli.plugin_args import add_plugin_argument
from pico_studio.core.behaviours.registry import behaviour_help


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("serve", help="open the interactive web UI (default: the hospital example, simulated)")
    p.add_argument("--map", help="a JSON map or heightmap image (default: the built-in hospital_2019.json)")
    p.add_argument("--sim-config", help="simulator config JSON (initial pose, moving objects, ...)")
    p.add_argument("--config", help="a (partial) config YAML to start from")
    p.add_argument("--behaviour", default="wander", help="what drives the robot: " + behaviour_help() + " | teleop (default wander)")
    p.add_argument("--source", default="sim", help="sim (default), bag:FILE, carmen:FILE or ros (a replay drives nothing: behaviours are ignored)")
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1: this machine only)")
    p.add_argument("--port", type=limits.PORT, default=8080, help="port (default 8080)")
    p.add_argument("--seed", type=limits.SEED, default=None, help="simulator random seed")
    p.add_argument("--export-dir", default="pico_studio_exports", help="where 'Export config' saves YAML files")
    p.add_argument("--paused", action="store_true", help="start paused")
    p.add_argument("--workers", type=limits.WORKERS, default=2,
                   help="the What-if tab's re-judge: 2 or more (default 2) perceives and scores in two processes "
                   "beside the page's own (a second core); 1 in a thread of the page's process")
    add_plugin_argument(p)
    p.set_defaults(func=_serve)


def build_app(args: argparse.Namespace, *, verbose: bool = True):  # -> StudioApp
    """The Studio and its page from parsed arguments (also used by the tests and benchmarks)."""
    from pico_studio.config import load_config
    from pico_studio.json_map import load_map
    from pico_studio.ui.app import StudioApp
    from pico_studio.ui.runtime import Studio
    from pico_studio.ui.sources import DEFAULT_MAP, make_source_factory, sim_config_for

    cfg = load_config(args.config)
    simulated = args.source == "sim"
    # a recording has no map of its own: only the one asked for (the example is the sim's)
    map_path = Path(args.map) if args.map else (DEFAULT_MAP if simulated else None)
    global_map = load_map(map_path, cfg.map) if map_path is not None else None
    sim_config = args.sim_config if args.sim_config else (sim_config_for(map_path) if simulated and not args.map else None)
    factory = make_source_factory(args.source, sim_config, args.seed)
    # the page's title: the map, or a recording's file name (not its whole path)
    name = map_path.name if map_path is not None else Path(args.source.partition(":")[2] or args.source).name
    studio = Studio(cfg, global_map, factory, behaviour=args.behaviour, map_name=name)
    studio.playing = not args.paused
    return StudioApp(studio, host=args.host, port=args.port, export_dir=args.export_dir, verbose=verbose,
                     workers=getattr(args, "workers", 2))


def _serve(args: argparse.Namespace) -> int:
    from pico_studio import jit

    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(name)s: %(message)s")
    logging.getLogger("websockets").setLevel(logging.WARNING)  # not a line per tab
    app = build_app(args, verbose=False)
    # the compiled loops load from numba's cache (warm: about a second) or compile (cold: the
    # first start after an install or update) in a background thread started once the page is
    # up (every module is imported by then: no import races); the loop is held until they are
    # ready, so no tick holds the page while the compiler runs. (A cold simulator compiles its
    # raycast for its first scan inside build_app: a few seconds more before the URL.)
    play, app.studio.playing = app.studio.playing, False
    app.start()
    print(f"pico-studio: serving {app.studio.map_name} at {app.url}  (Ctrl-C stops)", flush=True)
    warm = jit.warm_up_in_background()
    threading.Thread(target=_play_when_warm, args=(app, warm, play), daemon=True).start()
    try:
        while True:
            time.sleep(3600)
    finally:
        app.stop()


def _play_when_warm(app, warm: threading.Thread, play: bool) -> None:  # noqa: ANN001 (a StudioApp)
    warm.join(timeout=1.5)
    if warm.is_alive():
        print("pico-studio: compiling the fast paths (first start after an install or update; cached "
              "afterwards): the robot starts when that is done", flush=True)
        warm.join()
        print("pico-studio: fast paths compiled", flush=True)
    if play and not app.studio.playing:
        app.studio.playing = True  # the loop ticks again; its redraw turns the button to "Pause"
