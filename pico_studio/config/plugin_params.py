"""Where user code (plugins) meets the config tree: live choice lists and plugin areas.

Config is the ground floor, so it cannot know which plugins exist; it holds two registries
that the layers above fill in:

- `LiveChoices`: the names a choice parameter accepts, the built-ins declared here plus the
  ones registered at run time (`perception.scan.segmenter` accepts a plugin segmenter once
  core's `register_segmenter` added its name). Sliders, YAML validation, `describe()` and the
  tuning search space read the list when they need it, so they see plugins like built-ins.
- `PluginArea`: a dynamic section (`perception.plugins`, `behaviour.plugins`) holding one
  sub-section per loaded plugin, declared by the plugin's own `param()` dataclass. Its class
  is rebuilt when a plugin is added or removed; `walk`, `from_dict`, `with_value`, YAML and
  `config defaults` treat the result like any other section.

    SEGMENTER_NAMES = LiveChoices(("split_merge", "angle", "ransac"))
    plugins: PluginSections = plugin_area(PERCEPTION_PLUGINS, "Loaded plugins' parameters")
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any, overload

_SECTION = "pico_studio.section"
_AREA = "pico_studio.plugin_area"


class LiveChoices(Sequence[str]):
    """An ordered, growing list of names: the built-ins first, then the registered ones."""

    def __init__(self, builtin: Sequence[str]):
        self.builtin: tuple[str, ...] = tuple(builtin)
        self._names: list[str] = list(builtin)

    def add(self, name: str) -> None:
        if name not in self._names:
            self._names.append(name)

    def remove(self, name: str) -> None:
        """Forget a registered name (a built-in stays)."""
        if name in self._names and name not in self.builtin:
            self._names.remove(name)

    @overload
    def __getitem__(self, i: int) -> str: ...
    @overload
    def __getitem__(self, i: slice) -> Sequence[str]: ...
    def __getitem__(self, i: int | slice) -> str | Sequence[str]:
        return self._names[i]

    def __len__(self) -> int:
        return len(self._names)

    def __iter__(self) -> Iterator[str]:
        return iter(tuple(self._names))

    def __contains__(self, name: object) -> bool:
        return name in self._names

    def __repr__(self) -> str:
        return f"LiveChoices({tuple(self._names)!r})"


@dataclass(frozen=True)
class PluginSections:
    """Base of a plugin area's (rebuilt) class: one section field per loaded plugin."""

    _area = "perception"  # overridden per rebuilt class

    def get(self, name: str) -> Any:
        """The named plugin's params, or None when it has none here."""
        return getattr(self, name, None)

    def __reduce__(self) -> tuple[Any, ...]:
        # pickled by value: a worker process (spawn) that loaded the same plugins rebuilds it
        # on its own classes (they are made per process, so they cannot be found by name)
        values = {f.name: {g.name: getattr(getattr(self, f.name), g.name)
                           for g in dataclasses.fields(getattr(self, f.name))}
                  for f in dataclasses.fields(self)}
        return (_restore, (self._area, values))


def _restore(area_name: str, values: dict[str, dict[str, Any]]) -> PluginSections:
    area = AREAS[area_name]
    missing = [n for n in values if n not in area.names()]
    if missing:
        raise ValueError(f"{area_name}.plugins: {', '.join(missing)} not loaded in this process; "
                         "load the same plugins first (pico_studio.plugins.load_plugins(specs))")
    cls = area.current_class()
    return cls(**{n: area.params_class(n)(**v) for n, v in values.items()})


class PluginArea:
    """The plugins of one area by name -> (params dataclass, meaning), and the class built
    from them. Names are Python identifiers (they are config keys and field names)."""

    def __init__(self, name: str):
        self.name = name
        self._sections: dict[str, tuple[type, str]] = {}
        self._cls: type[PluginSections] = PluginSections
        self._version = 0

    def add(self, name: str, params_cls: type, help: str) -> None:  # noqa: A002
        if not name.isidentifier():
            raise ValueError(f"plugin name {name!r} must be a Python identifier (letters, digits, _)")
        if not dataclasses.is_dataclass(params_cls):
            raise TypeError(f"parameters of plugin {name!r} must be a dataclass, got {params_cls!r}")
        self._sections[name] = (params_cls, help)
        self._rebuild()

    def remove(self, name: str) -> None:
        if self._sections.pop(name, None) is not None:
            self._rebuild()

    def names(self) -> list[str]:
        return list(self._sections)

    def params_class(self, name: str) -> type:
        return self._sections[name][0]

    def current_class(self) -> type[PluginSections]:
        return self._cls

    def _rebuild(self) -> None:
        self._version += 1
        fields = [
            (n, cls, dataclasses.field(default_factory=cls, metadata={_SECTION: help}))
            for n, (cls, help) in self._sections.items()
        ]
        qualname = f"_{self.name.title().replace('_', '')}Plugins{self._version}"
        cls = dataclasses.make_dataclass(qualname, fields, bases=(PluginSections,), frozen=True,
                                         namespace={"_area": self.name})
        cls.__module__ = __name__
        self._cls = cls


PERCEPTION_PLUGINS = PluginArea("perception")
BEHAVIOUR_PLUGINS = PluginArea("behaviour")
AREAS = {a.name: a for a in (PERCEPTION_PLUGINS, BEHAVIOUR_PLUGINS)}


def plugin_area(area: PluginArea, help: str) -> Any:  # noqa: A002
    """Declare a section field whose class is the area's current one."""
    return dataclasses.field(default_factory=lambda: area.current_class()(),
                             metadata={_SECTION: help, _AREA: area})


def section_class(f: dataclasses.Field[Any]) -> Any:
    """The dataclass a section field holds: its factory, or a plugin area's current class."""
    area = f.metadata.get(_AREA)
    return area.current_class() if area is not None else f.default_factory
