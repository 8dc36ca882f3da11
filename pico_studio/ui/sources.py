"""What the page runs on: the example maps, map loading, and making the data source.

`--source sim` (the default) runs the simulator in the chosen map; `bag:FILE`, `carmen:FILE`
and `ros` are replays / the live robot from `pico_studio.sources` (the recordings part).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from pico_studio.config import Config
from pico_studio.errors import MapError
from pico_studio.json_map import GlobalMap
from pico_studio.ui.runtime import SourceBundle, SourceFactory

EXAMPLES_DIR = Path(__file__).resolve().parents[1] / "data" / "maps"
DEFAULT_MAP = EXAMPLES_DIR / "hospital_2019.json"
MAP_SUFFIXES = (".json", ".png", ".pgm", ".yaml")


def example_maps() -> dict[str, Path]:
    """The built-in example maps by file name (simulator configs `*_sim.json` excluded; a
    heightmap with a map_server YAML is listed by its YAML)."""
    files = sorted(p for p in EXAMPLES_DIR.iterdir() if p.suffix in MAP_SUFFIXES and not p.stem.endswith("_sim"))
    with_yaml = {p.stem for p in files if p.suffix == ".yaml"}
    return {p.name: p for p in files if not (p.suffix in (".png", ".pgm") and p.stem in with_yaml)}


def sim_config_for(map_path: Path) -> Path | None:
    """The example's simulator config (`<map>_sim.json`) when there is one."""
    candidate = map_path.with_name(map_path.stem + "_sim.json")
    return candidate if candidate.exists() else None


def make_source_factory(spec: str, sim_config: str | Path | None, seed: int | None = None) -> SourceFactory:
    """A factory the Studio calls on every reset: a fresh source from the current config."""
    from pico_studio.sources import parse_source

    parsed = parse_source(spec)  # bad spellings fail here, before any server starts
    if parsed.kind == "sim":
        return _sim_factory(sim_config, seed)
    return _replay_factory(str(parsed))


def _sim_factory(sim_config: str | Path | None, seed: int | None) -> SourceFactory:
    def make(cfg: Config, global_map: GlobalMap | None) -> SourceBundle:
        from pico_studio.sim import Simulator, load_sim_config

        if global_map is None:
            raise MapError("the simulator needs a map", field="--map")
        sc = load_sim_config(sim_config) if sim_config is not None else None
        sim = Simulator(global_map, getattr(cfg, "sim", None), sc, seed=seed)
        return SourceBundle(
            source=sim, truth_pose=lambda: tuple(sim.truth.pose), truth=sim.truth, kind="sim",
            world=lambda: sim_world_segments(sim.truth), initial_pose=sim.sim_config.initial_pose,
            start_pose=tuple(float(v) for v in sim.truth.pose),  # type: ignore[arg-type]
        )

    return make


def sim_world_segments(truth: Any) -> np.ndarray:
    """The simulator's sliding doors (where they are now) and moving objects, as segments."""
    outlines = [v for v, _opened in truth.doors()] + list(truth.moving_objects())
    segs = [np.hstack([v, np.roll(v, -1, axis=0)]) for v in outlines if len(v) >= 2]
    return np.vstack(segs) if segs else np.zeros((0, 4))


def _replay_factory(spec: str) -> SourceFactory:
    def make(cfg: Config, global_map: GlobalMap | None) -> SourceBundle:
        from pico_studio.sources import open_source

        source: Any = open_source(spec, cfg.sources)
        truth = getattr(source, "truth_pose", None)
        return SourceBundle(
            source=source, truth_pose=truth if callable(truth) else (lambda: None), truth=None, kind=spec.split(":")[0]
        )

    return make
