"""Every scenario set the README names loads and checks: its maps exist, its worlds parse."""

from __future__ import annotations

from pathlib import Path

import pytest

from pico_studio.evaluation.scenarios import load_scenarios
from pico_studio.evaluation.worlds import parse_world

SETS = sorted((Path(__file__).resolve().parents[1] / "examples" / "scenarios").glob("*.yaml"))


def test_the_sets_are_there() -> None:
    names = {p.name for p in SETS}
    assert {"perception_worlds.yaml", "unseen_worlds.yaml", "held_out_worlds.yaml"} <= names


@pytest.mark.parametrize("path", SETS, ids=lambda p: p.stem)
def test_a_set_loads(path: Path) -> None:
    s = load_scenarios(path)
    assert s.scenarios
    assert len({sc.name for sc in s.scenarios}) == len(s.scenarios)  # names say which row is which
    for sc in s.scenarios:
        if sc.world is not None:
            parse_world(sc.world)
        if sc.map is not None:
            assert Path(sc.map).is_file()
