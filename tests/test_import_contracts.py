"""The layer rules in pyproject.toml's [tool.importlinter] really fail when one is broken.

`./dev test` runs `lint-imports` on the tree; here a copy of the package gets one forbidden
import at a time, and the checker must reject it and name the contract.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LINT_IMPORTS = Path(sys.executable).with_name("lint-imports")

pytestmark = pytest.mark.skipif(not LINT_IMPORTS.exists(), reason="import-linter not installed")


def _copy_tree(tmp_path: Path) -> Path:
    shutil.copytree(ROOT / "pico_studio", tmp_path / "pico_studio",
                    ignore=shutil.ignore_patterns("__pycache__", "data"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    return tmp_path


def _lint(tree: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    return subprocess.run([str(LINT_IMPORTS), "--no-cache"], cwd=tree, env=env,
                          capture_output=True, text=True, timeout=120)


def _add_import(tree: Path, module: str, line: str) -> None:
    path = tree / (module.replace(".", "/") + ".py")
    path.write_text(path.read_text() + f"\n{line}\n")


def test_the_tree_keeps_every_contract(tmp_path: Path) -> None:
    result = _lint(_copy_tree(tmp_path))
    assert result.returncode == 0, result.stdout + result.stderr


@pytest.mark.parametrize(("module", "line", "contract"), [
    ("pico_studio.core.geometry", "import pico_studio.sim.world  # noqa", "core knows neither"),
    ("pico_studio.json_map.model", "import pico_studio.core.io  # noqa", "maps are read"),
    ("pico_studio.config.spec", "import pico_studio.json_map  # noqa", "the ground floor"),
    ("pico_studio.sim.laser", "import viser  # noqa", "only ui imports viser"),
    ("pico_studio.ui.colour", "import pico_studio.cli  # noqa", "layers from cli on top"),
])
def test_a_forbidden_import_fails_its_contract(tmp_path: Path, module: str, line: str,
                                               contract: str) -> None:
    tree = _copy_tree(tmp_path)
    _add_import(tree, module, line)
    result = _lint(tree)
    assert result.returncode != 0
    broken = result.stdout.split("Broken contracts", 1)[-1]
    assert contract in broken, result.stdout


def test_test_modules_do_not_import_each_other() -> None:
    """Shared helpers live in helper modules (sim_helpers.py, perception_scenes.py, ...):
    importing a test module would also collect its tests twice and tie the two together."""
    tests = {p.stem for p in (ROOT / "tests").glob("test_*.py")}
    offenders = []
    for path in sorted((ROOT / "tests").glob("*.py")):
        for n, line in enumerate(path.read_text().splitlines(), 1):
            words = line.replace(",", " ").split()
            if len(words) >= 2 and words[0] in ("from", "import") and (
                    words[1] in tests or words[1].removeprefix("tests.") in tests):
                offenders.append(f"{path.name}:{n}: {line.strip()}")
    assert offenders == []
