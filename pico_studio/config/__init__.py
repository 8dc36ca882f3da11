"""One typed config tree: every parameter declared once with default, range, unit, meaning.

    from pico_studio.config import Config, load_config, dump_yaml, with_value
    cfg = load_config("tuned.yaml")          # partial files merge over defaults
    cfg = with_value(cfg, "map.heightmap.resolution", 0.05)
    merged = merge_config(cfg, text)         # an import over tuned values: .config, .changed
"""

from __future__ import annotations

from pathlib import Path

from pico_studio.config.io import (
    Change,
    Merged,
    changed_params,
    changes,
    dump_yaml,
    from_dict,
    get_value,
    load_yaml,
    loads_yaml,
    merge,
    merge_yaml,
    save_yaml,
    to_dict,
    with_value,
)
from pico_studio.config.spec import (
    ParamInfo,
    ParamSpec,
    SectionInfo,
    param,
    params,
    section,
    walk,
)
from pico_studio.config.tree import Config

__all__ = [
    "Change",
    "Config",
    "Merged",
    "ParamInfo",
    "ParamSpec",
    "SectionInfo",
    "changed_params",
    "changes",
    "dump_yaml",
    "from_dict",
    "get_value",
    "load_config",
    "loads_config",
    "merge",
    "merge_config",
    "merge_yaml",
    "param",
    "params",
    "save_yaml",
    "section",
    "to_dict",
    "walk",
    "with_value",
]


def load_config(path: str | Path | None = None) -> Config:
    """The defaults, or a (partial) YAML file merged over them."""
    return Config() if path is None else load_yaml(Config, path)


def loads_config(text: str, *, file: str | None = None) -> Config:
    return loads_yaml(Config, text, file=file)


def merge_config(current: Config, text: str, *, file: str | None = None) -> Merged[Config]:
    """YAML text merged over the current (tuned) values: the page's import. `.changed` lists
    the parameters it changed; everything the file leaves out keeps its current value."""
    return merge_yaml(current, text, file=file)
