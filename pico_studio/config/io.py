"""Build, validate, change and save config trees: YAML in and out, one value at a time.

All of it is derived from the declarations (`spec.param` / `spec.section`): unknown keys are
rejected with a "did you mean", out-of-range values name the field and the allowed range,
and partial files merge over the defaults — or, with `merge` / `merge_yaml`, over any current
values, reporting what changed (the page's import keeps every tuned value the file leaves out).
"""

from __future__ import annotations

import copy
import dataclasses
import difflib
from pathlib import Path
from typing import Any, Generic, TypeVar

import yaml

from pico_studio.config.plugin_params import PluginSections, section_class
from pico_studio.config.spec import ParamInfo, ParamSpec, SectionInfo, coerce, params, walk
from pico_studio.errors import ConfigError, short
from pico_studio.user_files import parse_yaml, read_text

T = TypeVar("T")


# parameters that moved or went: an old file (a page export names every parameter) still
# loads — a moved value is read at its new place, a gone one dropped — and a dict given to
# `from_dict` directly is told where they are now
MOVED = {
    **{f"sim.truth.{k}": f"map.openings.{k}" for k in (
        "door_min_width", "door_max_width", "max_wall_thickness", "mouth_probe", "mouth_wall_length", "mouth_margin")},
    "localisation.combined.jamb_confirm_distance": None,  # the map's openings confirm doors now
}


def _moved(path: str) -> str | None:
    if path not in MOVED:
        return None
    new = MOVED[path]
    if new is None:
        return "no such parameter any more (the map's door openings, map.openings, confirm doors now): remove it"
    return f"moved to {new}"


def _did_you_mean(key: str, options: list[str]) -> str:
    close = difflib.get_close_matches(key, options, n=1, cutoff=0.5)
    return f"; did you mean '{close[0]}'?" if close else f"; known keys: {', '.join(options)}"


def from_dict(cls: type[T], data: Any, *, file: str | Path | None = None, prefix: str = "") -> T:
    """A section of type `cls` from a (partial) nested dict, validated; missing keys default."""
    here = prefix.rstrip(".") or "(top level)"
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise ConfigError(f"must be a mapping of keys to values, got {short(data)}", file=file, field=here)
    fields = {f.name: f for f in dataclasses.fields(cls)}  # type: ignore[arg-type]
    kwargs: dict[str, Any] = {}
    for key, value in data.items():
        path = f"{prefix}{key}"
        if key not in fields:
            moved = _moved(path)
            if moved:
                raise ConfigError(moved, file=file, field=path)
            what = "no plugin of that name is loaded (--plugin FILE.py)" if issubclass(cls, PluginSections) else "unknown key"
            raise ConfigError(what + (_did_you_mean(str(key), list(fields)) if fields else ""), file=file, field=path)
        f = fields[key]
        if "pico_studio.section" in f.metadata:
            kwargs[key] = from_dict(section_class(f), value, file=file, prefix=path + ".")
        else:
            kwargs[key] = _coerce(f.metadata["pico_studio.param"], value, file=file, field=path)
    obj = cls(**kwargs)
    _check(obj, file=file, prefix=prefix)
    return obj


def _coerce(spec: ParamSpec, value: Any, *, file: str | Path | None, field: str) -> Any:
    """`spec.coerce` with its ValueError as a ConfigError; an integer too large for a float
    (a 400-digit seed: `float()` overflows before the range check) is out of range too."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 2**63:
        digits = len(str(abs(value)))
        raise ConfigError(
            f"a {digits}-digit number is out of range; allowed {spec.lo:g} .. {spec.hi:g}"
            if spec.lo is not None and spec.hi is not None else f"a {digits}-digit number is too large",
            file=file, field=field,
        )
    if isinstance(value, (list, dict, set, tuple)) or (
        isinstance(value, str) and len(value) > 200 and spec.kind != "str"
    ):  # spec.coerce prints the value in full: a YAML alias bomb would never finish printing
        wanted = {"bool": "true or false", "choice": "one of " + ", ".join(spec.choices or ()),
                  "str": "a string"}.get(spec.kind, "a number")
        raise ConfigError(f"must be {wanted}, got {short(value)}", file=file, field=field)
    try:
        return coerce(spec, value)
    except (ValueError, OverflowError) as e:
        raise ConfigError(str(e), file=file, field=field) from None


def _check(obj: Any, *, file: str | Path | None, prefix: str) -> None:
    """The declared orderings (`below=` / `at_most=` a sibling), then the section's own
    cross-field `check()` (if it has one): it returns problems."""
    for field, problem in ordering_problems(obj):
        raise ConfigError(problem, file=file, field=f"{prefix}{field}")
    check = getattr(obj, "check", None)
    if check is None:
        return
    for field, problem in check():
        raise ConfigError(problem, file=file, field=f"{prefix}{field}")


def ordering_problems(obj: Any) -> list[tuple[str, str]]:
    """(field, problem) for each parameter of section `obj` not below / at most the sibling
    its declaration names."""
    problems = []
    for f in dataclasses.fields(obj):
        spec = f.metadata.get("pico_studio.param")
        if spec is None or spec.upper is None:
            continue
        other, strict = spec.upper
        mine, theirs = getattr(obj, f.name), getattr(obj, other)
        if mine >= theirs if strict else mine > theirs:
            problems.append((f.name, f"must be {'below' if strict else 'at most'} {other} ({theirs:g}), got {mine:g}"))
    return problems


def to_dict(obj: Any) -> dict[str, Any]:
    """Nested plain dict of every value (sections as dicts)."""
    out: dict[str, Any] = {}
    for f in dataclasses.fields(obj):
        v = getattr(obj, f.name)
        out[f.name] = to_dict(v) if dataclasses.is_dataclass(v) else v
    return out


def load_yaml(cls: type[T], path: str | Path) -> T:
    """Read a (partial) YAML file over the defaults of `cls`."""
    p = Path(path)
    return loads_yaml(cls, read_text(p, ConfigError, "a config YAML"), file=p)


def loads_yaml(cls: type[T], text: str, *, file: str | Path | None = None) -> T:
    """YAML text over the defaults of `cls` (the same merge as an import over tuned values)."""
    return merge_yaml(cls(), text, file=file).config


def dump_yaml(obj: Any, *, comments: bool = True) -> str:
    """YAML text of the whole tree; with comments each value carries its meaning and range."""
    lines: list[str] = []
    for item in walk(obj):
        depth = item.path.count(".")
        indent = "  " * depth
        name = item.path.rsplit(".", 1)[-1]
        if isinstance(item, SectionInfo):
            if comments:
                lines.append(f"{indent}# {item.help}")
            lines.append(f"{indent}{name}:")
        else:
            value = yaml.safe_dump(item.value, default_flow_style=True).strip()
            if value.endswith("\n..."):
                value = value[: -len("\n...")]
            value = value.removesuffix("...").strip()
            line = f"{indent}{name}: {value}"
            if comments:
                line += f"  # {item.spec.describe()}"
            lines.append(line)
    return "\n".join(lines) + "\n"


def save_yaml(obj: Any, path: str | Path, *, comments: bool = True) -> Path:
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(dump_yaml(obj, comments=comments), encoding="utf-8")
    return p


def get_value(obj: Any, path: str) -> Any:
    for part in path.split("."):
        obj = getattr(obj, part)
    return obj


def with_value(obj: T, path: str, value: Any) -> T:
    """A copy of the tree with one parameter changed, validated like a file would be."""
    info = {p.path: p for p in params(obj)}.get(path)
    if info is None:
        raise ConfigError(_moved(path) or "unknown parameter" + _did_you_mean(path, [p.path for p in params(obj)]), field=path)
    new_value = _coerce(info.spec, value, file=None, field=path)
    return _replace_path(obj, path.split("."), new_value, prefix="")


def _replace_path(obj: Any, parts: list[str], value: Any, prefix: str) -> Any:
    head = parts[0]
    if len(parts) == 1:
        new = dataclasses.replace(obj, **{head: value})
    else:
        child = _replace_path(getattr(obj, head), parts[1:], value, prefix + head + ".")
        new = dataclasses.replace(obj, **{head: child})
    _check(new, file=None, prefix=prefix)
    return new


def changed_params(obj: Any) -> list[ParamInfo]:
    """The parameters whose value differs from the declared default."""
    return [p for p in params(obj) if p.value != p.spec.default]


@dataclasses.dataclass(frozen=True)
class Change:
    """One parameter an import (or any edit) changed: its path, the value before and after."""

    path: str
    old: Any
    new: Any


@dataclasses.dataclass(frozen=True)
class Merged(Generic[T]):
    """A config tree after merging a (partial) file over it, and what that changed."""

    config: T
    changed: list[Change]


def merge(base: T, data: Any, *, file: str | Path | None = None) -> Merged[T]:
    """`data` (a partial nested dict, as read from YAML) merged over the *current* values of
    `base`, validated as a whole file is (`from_dict`): the keys it names change, every other
    value keeps what `base` has — a partial file never resets a tuned value to its default.

    The one merge of the page's import and the CLI's `--config` (over the defaults)."""
    if data is not None and not isinstance(data, dict):
        raise ConfigError(f"must be a mapping of keys to values, got {type(data).__name__}",
                          file=file, field="(top level)")
    new = from_dict(type(base), _deep_merge(to_dict(base), _migrated(data or {})), file=file)
    return Merged(new, changes(base, new))


def _migrated(data: dict[str, Any]) -> dict[str, Any]:
    """`data` with every `MOVED` key read at its new place (unless that is given too) and every
    gone one dropped; a copy where anything moved, `data` itself otherwise."""
    out = data
    for old, new in MOVED.items():
        *parents, leaf = old.split(".")
        holder: Any = out
        for part in parents:
            holder = holder.get(part) if isinstance(holder, dict) else None
        if not isinstance(holder, dict) or leaf not in holder:
            continue
        if out is data:
            out = copy.deepcopy(data)
            holder = out
            for part in parents:
                holder = holder[part]
        value = holder.pop(leaf)
        if new is None:
            continue
        *new_parents, new_leaf = new.split(".")
        target = out
        for part in new_parents:
            nxt = target.get(part)
            if not isinstance(nxt, dict):
                if nxt is not None:
                    break  # not a mapping there: from_dict says so
                nxt = target[part] = {}
            target = nxt
        else:
            target.setdefault(new_leaf, value)
    return out


def merge_yaml(base: T, text: str, *, file: str | Path | None = None) -> Merged[T]:
    """YAML text merged over `base` (see `merge`)."""
    return merge(base, parse_yaml(text, ConfigError, file), file=file)


def _deep_merge(into: dict[str, Any], data: dict[str, Any]) -> dict[str, Any]:
    """A copy of `into` with `data` laid over it, mapping by mapping. A value that is not a
    mapping replaces what was there, so a bad one still reaches `from_dict`'s checks."""
    out = dict(into)
    for key, value in data.items():
        here = out.get(key)
        out[key] = _deep_merge(here, value) if isinstance(here, dict) and isinstance(value, dict) else value
    return out


def changes(before: Any, after: Any) -> list[Change]:
    """The parameters whose value differs between two trees of the same kind, in declaration order."""
    old = {p.path: p.value for p in params(before)}
    return [Change(p.path, old[p.path], p.value) for p in params(after) if old.get(p.path) != p.value]
