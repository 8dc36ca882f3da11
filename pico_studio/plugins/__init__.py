"""Bring your own code: segmenters, door detectors, perceptors and behaviours as plugins.

    from dataclasses import dataclass
    import numpy as np
    from pico_studio.plugins import param, segmenter

    @dataclass(frozen=True)
    class MyParams:
        split: float = param(0.05, lo=0.005, hi=0.5, unit="m", help="split tolerance")

    @segmenter("mine", MyParams, help="my split-and-merge")
    def mine(points: np.ndarray, params: MyParams) -> list[tuple[int, int]]:
        ...  # one cluster's points (N, 2), robot frame -> (first, last) inclusive pairs

Load it with `--plugin my_stage.py` (any command), `load_plugin(...)`, or install a package
with an entry point in the group `pico_studio.plugins`. Its parameters appear in the config
tree as `perception.plugins.mine.split` (behaviours: `behaviour.plugins.<name>`): sliders,
YAML, validation, `config defaults` and tuning all see them; `perception.scan.segmenter:
mine` selects it. See docs/PLUGINS.md.
"""

from __future__ import annotations

from pico_studio.config.spec import param
from pico_studio.core.perception.plugin_hooks import emit, warn
from pico_studio.plugins.declare import behaviour, door_detector, perceptor, segmenter
from pico_studio.plugins.loader import (
    ENTRY_POINT_GROUP,
    changed,
    load_entry_points,
    load_plugin,
    load_plugins,
    reload,
    specs,
    unload,
)
from pico_studio.plugins.rebase import rebase
from pico_studio.plugins.registry import Plugin, Stage, loaded

__all__ = [
    "ENTRY_POINT_GROUP",
    "Plugin",
    "Stage",
    "behaviour",
    "changed",
    "door_detector",
    "emit",
    "load_entry_points",
    "load_plugin",
    "load_plugins",
    "loaded",
    "param",
    "perceptor",
    "rebase",
    "reload",
    "segmenter",
    "specs",
    "unload",
    "warn",
]
