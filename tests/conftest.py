"""Shared fixtures: paths to the real maps and recordings copied into the project."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
MAPS = ROOT / "pico_studio" / "data" / "maps"
RECORDINGS = ROOT / "tests" / "data" / "recordings"


@pytest.fixture
def maps_dir() -> Path:
    return MAPS


@pytest.fixture
def recordings_dir() -> Path:
    return RECORDINGS


@pytest.fixture(scope="session", autouse=True)
def _compiled_kernels() -> None:
    """Compile (or load from numba's cache) every compiled loop once per test session, so no
    test pays the compile time (pico_studio/jit.py)."""
    from pico_studio.jit import warm_up

    warm_up()
