"""`pico-studio config defaults|check`: the config tree as YAML, and validating a file."""

from __future__ import annotations

import argparse

from pico_studio.cli.plugin_args import add_plugin_argument
from pico_studio.config import Config, changed_params, dump_yaml, load_config


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("config", help="print the default config or check a config file")
    csub = p.add_subparsers(dest="config_command", metavar="ACTION", required=True)

    d = csub.add_parser("defaults", help="print the full default config as commented YAML")
    d.add_argument("--no-comments", action="store_true", help="values only")
    add_plugin_argument(d)
    d.set_defaults(func=_defaults)

    c = csub.add_parser("check", help="validate a (partial) config YAML file")
    c.add_argument("file", help="the YAML file to check")
    add_plugin_argument(c)
    c.set_defaults(func=_check)


def _defaults(args: argparse.Namespace) -> int:
    print(dump_yaml(Config(), comments=not args.no_comments), end="")
    return 0


def _check(args: argparse.Namespace) -> int:
    cfg = load_config(args.file)
    changed = changed_params(cfg)
    print(f"{args.file}: OK ({len(changed)} value(s) differ from the defaults)")
    for p in changed:
        print(f"  {p.path}: {p.value!r} (default {p.spec.default!r})")
    return 0
