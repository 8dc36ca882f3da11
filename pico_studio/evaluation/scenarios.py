"""Scenario sets: a YAML file listing runs to judge the perceptor, localisation and
behaviours by, so that `eval --scenarios FILE` scores them all and a tuner can optimise over
them.

    name: builtin                      # optional; default the file's stem
    defaults: {seed: 0, dt: 0.05}      # optional; merged under every scenario
    scenarios:
      - name: hospital_2019            # every scenario needs a unique name
        map: ../maps/hospital_2019.json   # or world: escape|rooms|hall|cafe|ward|suite|slant:SEED (generated)
        sim_config: ../maps/hospital_2019_sim.json   # optional, the official sim's JSON
        heightmap: true                # optional: drawn into a heightmap image and read back
                                       #   first (as a .png of it would load; walls its outlines)
        poses: 20                      # the eval method: K random free poses, each turned
        frames: 20                     #   for `frames` scans (default 20) and scored
      - name: hospital_tour
        map: ../maps/hospital_2019.json
        behaviour: hospital:0,2        # a behaviour run of `seconds` (default the
        seconds: 120                   #   behaviour's own limit), judged by its outcome
        localise: true                 # localise on the map; report the pose error
      - name: a_bag
        recording: bag:../recordings/run.bag   # or carmen:FILE: replayed with its truth
        map: ../maps/hospital_2019.json        # (optional: a map to localise on)

Paths are relative to the YAML file. Bad input is a `ConfigError` naming the file and the
field (`scenarios[2].poses`): unknown keys (with "did you mean"), missing files, a scenario
with neither a map, a world nor a recording, bad numbers.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Iterator
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from pico_studio.core.behaviours.registry import behaviour_name, is_behaviour
from pico_studio.errors import ConfigError
from pico_studio.evaluation.worlds import GENERATORS, parse_world
from pico_studio.user_files import parse_yaml, read_text


@dataclass(frozen=True)
class Scenario:
    name: str
    map: str | None = None  # a JSON map or heightmap image (absolute path)
    world: str | None = None  # a generated world: KIND:SEED (worlds.GENERATORS)
    sim_config: str | None = None  # the official simulator's JSON (absolute path)
    seed: int = 0
    seconds: float | None = None  # None: the behaviour's default (10 s for a plain run)
    dt: float = 0.05
    behaviour: str | None = None  # a behaviour spec (registry), or None
    poses: int | None = None  # the eval method: K random free poses
    recording: str | None = None  # bag:FILE | carmen:FILE (absolute path)
    localise: bool = False
    frames: int = 20  # scans per pose (the eval method)
    turn: float = 0.4  # rad/s at each pose (the eval method)
    clearance: float = 0.4  # m of free space around each pose (the eval method)
    heightmap: bool = False  # the map or world as a heightmap image shows it (json_map.convert.as_heightmap)

    @property
    def method(self) -> str:
        """poses | behaviour | recording | run (a plain scored run of `seconds`)."""
        if self.recording is not None:
            return "recording"
        if self.poses is not None:
            return "poses"
        if self.behaviour is not None:
            return "behaviour"
        return "run"


@dataclass(frozen=True)
class ScenarioSet:
    name: str
    path: Path | None
    scenarios: list[Scenario] = field(default_factory=list)

    def __iter__(self) -> Iterator[Scenario]:
        return iter(self.scenarios)

    def __len__(self) -> int:
        return len(self.scenarios)

    def select(self, names: list[str]) -> ScenarioSet:
        """The set with only the named scenarios (unknown names: ConfigError)."""
        known = {s.name: s for s in self.scenarios}
        for n in names:
            if n not in known:
                raise ConfigError(f"no scenario {n!r}{_did_you_mean(n, list(known))}", file=self.path)
        return replace(self, scenarios=[known[n] for n in names])


_KEYS = [f.name for f in fields(Scenario)]
_TOP = ["name", "defaults", "scenarios"]


def _did_you_mean(key: str, options: list[str]) -> str:
    close = difflib.get_close_matches(key, options, n=1, cutoff=0.5)
    return f"; did you mean '{close[0]}'?" if close else f"; known: {', '.join(options)}"


def load_scenarios(path: str | Path) -> ScenarioSet:
    """Read and check a scenario-set YAML file (see the module docstring)."""
    p = Path(path)
    data = parse_yaml(read_text(p, ConfigError, "a scenario-set YAML file"), ConfigError, p)
    return scenarios_from_dict(data, file=p)


def scenarios_from_dict(data: Any, *, file: Path | None = None) -> ScenarioSet:
    """The checked set from parsed YAML; paths are relative to `file`'s folder."""
    base = file.parent if file is not None else Path.cwd()
    if not isinstance(data, dict):
        raise ConfigError("must be a mapping with a 'scenarios' list", file=file)
    for key in data:
        if key not in _TOP:
            raise ConfigError(f"unknown key{_did_you_mean(str(key), _TOP)}", file=file, field=str(key))
    defaults = data.get("defaults") or {}
    if not isinstance(defaults, dict):
        raise ConfigError("must be a mapping of scenario fields", file=file, field="defaults")
    items = data.get("scenarios")
    if not isinstance(items, list) or not items:
        raise ConfigError("must be a non-empty list of scenarios", file=file, field="scenarios")
    out: list[Scenario] = []
    for k, item in enumerate(items):
        where = f"scenarios[{k}]"
        if not isinstance(item, dict):
            raise ConfigError("must be a mapping of scenario fields", file=file, field=where)
        merged = {**defaults, **item}
        s = _scenario(merged, base, file, where if "name" not in item else f"{where} ({item['name']})")
        if any(o.name == s.name for o in out):
            raise ConfigError(f"duplicate scenario name {s.name!r}", file=file, field=f"{where}.name")
        out.append(s)
    name = data.get("name") or (file.stem if file is not None else "scenarios")
    return ScenarioSet(str(name), file, out)


def _scenario(d: dict[str, Any], base: Path, file: Path | None, where: str) -> Scenario:
    def fail(key: str, message: str) -> ConfigError:
        return ConfigError(message, file=file, field=f"{where}.{key}")

    for key in d:
        if key not in _KEYS:
            raise fail(str(key), f"unknown key{_did_you_mean(str(key), _KEYS)}")
    if not isinstance(d.get("name"), str) or not d["name"].strip():
        raise fail("name", "every scenario needs a name (text)")
    kw: dict[str, Any] = {"name": d["name"].strip()}
    for key in ("map", "sim_config"):
        if d.get(key) is not None:
            kw[key] = _existing(d[key], base, fail, key)
    if d.get("world") is not None:
        try:
            parse_world(str(d["world"]))
        except ValueError as e:
            raise fail("world", str(e)) from None
        kw["world"] = str(d["world"])
    if d.get("recording") is not None:
        source, sep, rest = str(d["recording"]).partition(":")
        if not sep or source not in ("bag", "carmen") or not rest:
            raise fail("recording", f"must be bag:FILE or carmen:FILE, got {d['recording']!r}")
        kw["recording"] = f"{source}:{_existing(rest, base, fail, 'recording')}"
    if d.get("behaviour") is not None:
        spec = str(d["behaviour"])
        if not is_behaviour(spec):
            from pico_studio.core.behaviours.registry import BEHAVIOURS

            raise fail("behaviour", f"unknown behaviour {behaviour_name(spec)!r}"
                       f"{_did_you_mean(behaviour_name(spec), list(BEHAVIOURS))}")
        kw["behaviour"] = spec
    numbers: list[tuple[str, type, float | None]] = [
        ("seed", int, None), ("poses", int, 1), ("frames", int, 1),
        ("seconds", float, 0.0), ("dt", float, 1e-6), ("turn", float, None), ("clearance", float, 0.0),
    ]
    for key, number, lo in numbers:
        if d.get(key) is not None:
            kw[key] = _number(d[key], number, lo, fail, key)
    for key in ("localise", "heightmap"):
        if d.get(key) is not None:
            if not isinstance(d[key], bool):
                raise fail(key, f"must be true or false, got {d[key]!r}")
            kw[key] = d[key]
    s = Scenario(**kw)
    if s.map is None and s.world is None and s.recording is None:
        raise ConfigError(f"needs a map, a world ({', '.join(f'{k}:SEED' for k in GENERATORS)}) or a "
                          "recording (bag:FILE, carmen:FILE)",
                          file=file, field=where)
    if s.map is not None and s.world is not None:
        raise fail("world", "give a map or a world, not both")
    if s.recording is not None and (s.poses is not None or s.behaviour is not None):
        raise fail("recording", "a recording is replayed as it is: no poses or behaviour with it")
    if s.poses is not None and s.behaviour is not None:
        raise fail("poses", "the poses method turns the robot on the spot: no behaviour with it")
    if s.localise and s.map is None and s.world is None:
        raise fail("localise", "localising needs a map (or a world) to localise on")
    if s.heightmap and s.map is None and s.world is None:
        raise fail("heightmap", "only a map or a world is drawn into a heightmap")
    return s


def _existing(text: Any, base: Path, fail: Any, key: str) -> str:
    p = Path(str(text)).expanduser()
    p = p if p.is_absolute() else base / p
    if not p.is_file():
        raise fail(key, f"no such file: {p}")
    return str(p.resolve())


def _number(v: Any, kind: type, lo: float | None, fail: Any, key: str) -> Any:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or (kind is int and not float(v).is_integer()):
        raise fail(key, f"must be {'an integer' if kind is int else 'a number'}, got {v!r}")
    if not math.isfinite(float(v)):
        raise fail(key, f"must be finite, got {v!r}")
    if lo is not None and v < lo:
        raise fail(key, f"must be at least {lo:g}, got {v!r}")
    return kind(v)
