"""Shared by the plugin tests: a clean plugin registry per test, and plugin files in tmp."""

from __future__ import annotations

import sys
import textwrap
from pathlib import Path

from pico_studio import plugins

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "plugins" / "my_stages.py"
EXAMPLE_CONFIG = ROOT / "examples" / "plugins" / "use_my_stages.yaml"
PLUGIN_PKG = ROOT / "tests" / "data" / "plugin_pkg"


def unload_all() -> None:
    """Forget every loaded plugin (and the modules a test imported as plugins)."""
    for p in plugins.loaded():
        plugins.unload(p.key)
        if p.origin != "file":
            sys.modules.pop(p.module_name, None)


def write_plugin(directory: Path, name: str, body: str) -> Path:
    path = directory / name
    path.write_text(textwrap.dedent(body), encoding="utf-8")
    return path


def install_dist_info(site: Path, package_dir: Path, module: str, entry_name: str, version: str = "0.1.0") -> None:
    """What `pip install` leaves behind, written by hand (no network, no build): the
    package's files and a .dist-info with its entry point, in a directory on sys.path."""
    import shutil

    shutil.copytree(package_dir / module, site / module)
    info = site / f"{module}-{version}.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(
        f"Metadata-Version: 2.1\nName: {module.replace('_', '-')}\nVersion: {version}\n", encoding="utf-8")
    (info / "entry_points.txt").write_text(f"[pico_studio.plugins]\n{entry_name} = {module}\n", encoding="utf-8")
