"""`--source sim|bag:FILE|carmen:FILE|ros`: parse the spelling and open the source.

The simulator is built by the caller (it needs a map and the sim config), so
`open_source` handles the recordings and the live robot and says so for `sim`.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from pico_studio.config.sources_params import SourcesParams
from pico_studio.errors import SourceError

SourceKind = Literal["sim", "bag", "carmen", "ros"]
SOURCE_HELP = (
    "where frames come from: sim (the simulator), bag:FILE (a ROS 1 bag), "
    "carmen:FILE (a CARMEN log, plain or .gz), ros (the live robot via its ROS 1 master)"
)


@dataclass(frozen=True)
class SourceSpec:
    kind: SourceKind
    path: Path | None = None

    def __str__(self) -> str:
        return f"{self.kind}:{self.path}" if self.path is not None else self.kind


def parse_source(text: str) -> SourceSpec:
    """`sim`, `ros`, `bag:FILE`, `carmen:FILE`; a bare FILE is guessed from its name."""
    kind, sep, rest = text.partition(":")
    if not sep:
        if text in ("sim", "ros"):
            return SourceSpec(text)  # type: ignore[arg-type]
        guessed = _guess_kind(text)
        if guessed is None:
            raise SourceError(
                f"unknown source {text!r}; use sim, ros, bag:FILE or carmen:FILE", field="--source"
            )
        return SourceSpec(guessed, Path(text))
    if kind not in ("bag", "carmen"):
        raise SourceError(
            f"unknown source kind {kind!r} in {text!r}; use sim, ros, bag:FILE or carmen:FILE",
            field="--source",
        )
    if not rest:
        raise SourceError(f"{kind}: needs a file, e.g. {kind}:recording.{_EXT[kind]}", field="--source")
    return SourceSpec(kind, Path(rest))  # type: ignore[arg-type]


_EXT = {"bag": "bag", "carmen": "log.gz"}


def _guess_kind(text: str) -> SourceKind | None:
    name = text.lower()
    if name.endswith((".bag", ".bag.active")):
        return "bag"
    if name.endswith((".log", ".log.gz", ".clf", ".clf.gz")):
        return "carmen"
    return None


def open_source(spec: SourceSpec | str, params: SourcesParams | None = None):  # noqa: ANN201
    """The opened source: a `Replay` for bag/carmen, a `LiveRosSource` for ros."""
    if isinstance(spec, str):
        spec = parse_source(spec)
    params = params or SourcesParams()
    if spec.kind == "bag":
        from pico_studio.sources.bag import open_bag

        return open_bag(_existing(spec), params)
    if spec.kind == "carmen":
        from pico_studio.sources.carmen import open_carmen

        return open_carmen(_existing(spec), params)
    if spec.kind == "ros":
        from pico_studio.sources.ros_live import LiveRosSource

        return LiveRosSource(params)
    raise SourceError("the simulator is built from a map and the sim config, not here", field="--source")


def _existing(spec: SourceSpec) -> Path:
    assert spec.path is not None
    if not spec.path.is_file():
        raise SourceError(f"no such {spec.kind} file", file=spec.path, field="--source")
    return spec.path
