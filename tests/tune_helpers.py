"""Shared by the tune tests: small real scenario sets and the CLI run in-process or apart."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from pico_studio.cli import main

ROOT = Path(__file__).resolve().parents[1]
MAPS = ROOT / "pico_studio" / "data" / "maps"


def scenario_file(folder: Path, *, poses: int = 2, names: tuple[str, ...] = ("hospital_2019",)) -> Path:
    """A scenario set over built-in maps: `poses` random free poses each."""
    lines = [f"name: tiny-{len(names)}", "scenarios:"]
    for i, n in enumerate(names):
        lines.append(f"  - {{name: {n}, map: {MAPS / (n + '.json')}, seed: {i}, poses: {poses}, frames: 10}}")
    p = folder / f"scenarios-{len(names)}-{poses}.yaml"
    p.write_text("\n".join(lines) + "\n")
    return p


def bad_config(folder: Path) -> Path:
    """A deliberately bad start: walls need 40 sightings and 1.5 m to show."""
    p = folder / "bad.yaml"
    p.write_text("perception:\n  merge:\n    confirm_hits: 40\n    min_length: 1.5\n")
    return p


def tune(capsys, *args: str) -> tuple[int, dict | None, str]:
    """Run `pico-studio tune ARGS --json` in this process: (exit code, JSON or None, stderr)."""
    code = main(["tune", *args, "--json"])
    out, err = capsys.readouterr()
    return code, (json.loads(out) if code == 0 else None), err


def tune_process(*args: str) -> subprocess.Popen:
    """`pico-studio tune ARGS --json` as a separate process (as on another machine)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONWARNINGS="ignore")
    return subprocess.Popen([sys.executable, "-m", "pico_studio", "tune", *args, "--json"], cwd=ROOT,
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
