"""`--plugin PATH.py|MODULE` (repeatable) for every command that runs or shows the config.

Each command's `register` adds the option with one line, `add_plugin_argument(parser)`;
`cli.main` calls `load_requested(args)` before dispatching, so the plugins' stages and their
parameters exist before any config is read. Installed packages' `pico_studio.plugins` entry
points load too (unless `PICO_STUDIO_NO_ENTRY_POINTS` is set). A plugin that fails to import
is a `PluginError`: one line naming its file and line, exit 2.
"""

from __future__ import annotations

import argparse
import importlib.metadata
import os
from typing import Any

ENTRY_POINT_GROUP = "pico_studio.plugins"  # = pico_studio.plugins.ENTRY_POINT_GROUP


def add_plugin_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--plugin", action="append", default=[], metavar="PATH.py|MODULE",
        help="load user code (segmenters, door detectors, perceptors, behaviours) first; repeatable",
    )


def load_requested(args: argparse.Namespace) -> list[Any]:
    """The installed entry points, then every `--plugin` of the command line, in order.
    Without either nothing is imported: commands that need no core stay quick to start."""
    requested = list(getattr(args, "plugin", None) or [])
    installed = not os.environ.get("PICO_STUDIO_NO_ENTRY_POINTS") and bool(
        importlib.metadata.entry_points(group=ENTRY_POINT_GROUP))
    if not requested and not installed:
        return []
    from pico_studio import plugins

    out = plugins.load_entry_points() if installed else []
    return out + plugins.load_plugins(requested)
