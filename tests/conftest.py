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
