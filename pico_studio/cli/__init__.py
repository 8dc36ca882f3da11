"""The `pico-studio` command: one module per command group, each with `register(subparsers)`.

User errors (`pico_studio.errors.UserError`) print one clear line to stderr and exit 2;
anything else is a bug and keeps its traceback.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from pico_studio import __version__
from pico_studio.cli import config_cmd, eval_cmd, map_cmd, render_cmd, run_cmd, serve_cmd, tune_cmd
from pico_studio.cli.plugin_args import load_requested
from pico_studio.errors import UserError

COMMAND_MODULES = [map_cmd, config_cmd, run_cmd, eval_cmd, serve_cmd, render_cmd, tune_cmd]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="pico-studio",
        description="Interactive debugger for the PICO robot's laser perception and world model.",
    )
    parser.add_argument("--version", action="version", version=f"pico-studio {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module in COMMAND_MODULES:
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as e:  # argparse refused an argument (ranges: cli/limits.py); --help exits as usual
        if e.code in (0, None):
            raise
        return e.code if isinstance(e.code, int) else 2
    try:
        load_requested(args)  # user code first: its stages and parameters exist for the config
        return int(args.func(args) or 0)
    except UserError as e:
        print(f"pico-studio: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
