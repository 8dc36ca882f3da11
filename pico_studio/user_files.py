"""The one bounded reader of the user's files (JSON maps, sim configs, YAML, images,
recordings): every failure is one `UserError` naming the file and, for a parse error, the
line and column, and no file can make it hang or exhaust memory.

* Only regular files are read. A directory, device (`/dev/zero`), FIFO or socket is refused
  by name after an `os.stat`, before anything is opened (opening a FIFO for reading blocks
  until a writer comes); files are then opened non-blocking and checked again with
  `fstat`, in case the path was swapped in between.
* Each kind of file has a size cap (`FileLimits`, generous: a real map is < 1 MB, a config
  < 10 kB), checked before reading. Override one with the environment, e.g.
  `PICO_STUDIO_MAX_MAP_MB=200`; the names are in `FileLimits.env_names()`.
* JSON and YAML are parsed with a nesting-depth limit (`FileLimits.depth`) that is checked
  *before* the recursive parts of the parsers run, so a `[[[[...` file is a clear error,
  not a `RecursionError`. YAML integers longer than `int_digits` and duplicate mapping
  keys (the last would silently win) are errors naming the line(s).
"""

from __future__ import annotations

import json
import os
import re
import stat
from dataclasses import dataclass, fields
from pathlib import Path
from typing import IO, Any

import numpy as np
import yaml

from pico_studio.errors import MapError, UserError

MB = 1 << 20


@dataclass(frozen=True)
class FileLimits:
    """Caps on what a user's file may hold. Sizes in bytes."""

    map_bytes: int = 50 * MB  # JSON maps, map_server YAMLs, heightmap images
    config_bytes: int = 5 * MB  # config YAMLs, simulator config JSONs
    recording_bytes: int = 8 * 1024 * MB  # bags and CARMEN logs (a long bag is a few GB)
    upload_bytes: int = 50 * MB  # files uploaded through the page
    image_pixels: int = 25_000_000  # 5000 x 5000 px, a 125 m square at 2.5 cm/px (real maps: < 1 Mpx)
    decompressed_ratio: int = 100  # a gzip log may grow to ratio x its size (text: ~5-10x) ...
    decompressed_floor_bytes: int = 64 * MB  # ... or to this, whichever is larger
    line_bytes: int = 4 * MB  # one line of a text recording (a 10000-beam scan is ~100 kB)
    depth: int = 64  # nesting of JSON/YAML containers (a map needs 3, a config 4)
    int_digits: int = 100  # an integer literal in YAML

    @staticmethod
    def env_names() -> dict[str, str]:
        """field -> environment variable that overrides it (sizes in MB, others as is)."""
        out = {}
        for f in fields(FileLimits):
            name = f.name.removesuffix("_bytes")
            unit = "_MB" if f.name.endswith("_bytes") else ""
            out[f.name] = f"PICO_STUDIO_MAX_{name.upper()}{unit}"
        return out


def limits() -> FileLimits:
    """The limits in force: the defaults, with any `PICO_STUDIO_MAX_*` override."""
    values: dict[str, int] = {}
    for name, var in FileLimits.env_names().items():
        text = os.environ.get(var)
        if text is None:
            continue
        try:
            v = float(text)
        except ValueError:
            raise UserError(f"must be a number, got {text!r}", field=var) from None
        if not (v > 0 and v < 1e12):
            raise UserError(f"must be a positive number, got {text!r}", field=var)
        values[name] = int(v * MB) if name.endswith("_bytes") else int(v)
    return FileLimits(**values)


KINDS = {"map": "map_bytes", "config": "config_bytes", "recording": "recording_bytes", "upload": "upload_bytes"}


def _kind_for(error: type[UserError]) -> str:
    return "map" if issubclass(error, MapError) else "config"


def _cap(kind: str) -> int:
    return int(getattr(limits(), KINDS[kind]))


def _human(n: float) -> str:
    for unit in ("bytes", "kB", "MB", "GB"):
        if n < 1024 or unit == "GB":
            return f"{n:.0f} {unit}" if unit == "bytes" else f"{n:.1f} {unit}"
        n /= 1024
    return f"{n:.1f} GB"


def _not_regular(mode: int) -> str | None:
    """What a non-regular file is, or None for a regular one."""
    if stat.S_ISREG(mode):
        return None
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def check_file(path: str | Path, error: type[UserError], kind: str | None = None) -> int:
    """The size of the regular file at `path`, or `error` saying why it cannot be read:
    missing, a directory / device / FIFO / socket (named, never opened), or over the cap
    of its `kind` ("map", "config", "recording", "upload"; default from `error`)."""
    p = Path(path)
    kind = kind or _kind_for(error)
    try:
        st = os.stat(p)
    except FileNotFoundError:
        raise error("cannot read: no such file", file=p) from None
    except OSError as e:
        raise error(f"cannot read: {e.strerror or e}", file=p) from None
    what = _not_regular(st.st_mode)
    if what is not None:
        raise error(f"is {what}, not a regular file", file=p)
    cap = _cap(kind)
    if st.st_size > cap:
        var = FileLimits.env_names()[KINDS[kind]]
        raise error(
            f"is {_human(st.st_size)}, over the {_human(cap)} limit for a {kind} file (set {var} to raise it)",
            file=p,
        )
    return int(st.st_size)


def check_output(path: str | Path, error: type[UserError]) -> None:
    """`error` when `path` exists and is not a regular file: writing to a FIFO blocks until
    a reader comes, to a device is never what was meant. Checked by `os.stat`, unopened."""
    try:
        st = os.stat(path)
    except FileNotFoundError:
        return
    except OSError as e:
        raise error(f"cannot write: {e.strerror or e}", file=Path(path)) from None
    what = _not_regular(st.st_mode)
    if what is not None:
        raise error(f"cannot write: is {what}, not a regular file", file=Path(path))


def check_upload(name: str, content: bytes, error: type[UserError], suffixes: tuple[str, ...]) -> str:
    """The file name an upload may be saved under (its last path part), or `error` for an
    upload over the upload cap, with a name that is no file name, or of the wrong kind."""
    cap = _cap("upload")
    if len(content) > cap:
        raise error(f"is {_human(len(content))}, over the {_human(cap)} upload limit", file=str(name)[:200])
    base = Path(str(name).replace("\\", "/")).name
    if base in ("", ".", "..") or "\0" in base or len(base) > 255:
        raise error("is not a usable file name", file=str(name)[:200])
    if not base.lower().endswith(suffixes):
        raise error(f"upload one of {', '.join(suffixes)}", file=base)
    return base


def open_file(path: str | Path, error: type[UserError], kind: str | None = None) -> IO[bytes]:
    """The regular file at `path` opened for binary reading, checked as `check_file` does;
    opened non-blocking and re-checked, so a path swapped for a FIFO cannot block."""
    check_file(path, error, kind)
    p = Path(path)
    try:
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as e:
        raise error(f"cannot read: {e.strerror or e}", file=p) from None
    what = _not_regular(os.fstat(fd).st_mode)
    if what is not None:
        os.close(fd)
        raise error(f"is {what}, not a regular file", file=p)
    return os.fdopen(fd, "rb")


def read_bytes(path: str | Path, error: type[UserError], kind: str | None = None) -> bytes:
    """The whole (capped) file."""
    cap = _cap(kind or _kind_for(error))
    with open_file(path, error, kind) as f:
        data = f.read(cap + 1)  # the file may have grown since the stat
    if len(data) > cap:
        raise error(f"is over the {_human(cap)} limit", file=Path(path))
    return data


def read_text(path: str | Path, error: type[UserError], what: str, kind: str | None = None) -> str:
    """The file's text; `error` saying why not ("cannot read", "not a text file (expected ...)")."""
    data = read_bytes(path, error, kind)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise error(f"not a text file (expected {what})", file=Path(path)) from None


def read_json(path: str | Path, error: type[UserError], what: str, kind: str | None = None) -> Any:
    return parse_json(read_text(path, error, what, kind), error, Path(path))


# ----- JSON ---------------------------------------------------------------------------------
_JSON_STRING = re.compile(r'"(?:[^"\\\n]|\\.)*"')


def _too_deep(text: str, opens: bytes, closes: bytes, limit: int) -> int | None:
    """The 1-based line where bracket nesting first exceeds `limit`, or None. `text` has its
    strings removed already; newlines are kept, so line numbers are the original's."""
    b = np.frombuffer(text.encode("utf-8", errors="replace"), dtype=np.uint8)
    table = np.zeros(256, dtype=np.int32)
    table[list(opens)], table[list(closes)] = 1, -1
    depth = np.cumsum(table[b])
    over = np.flatnonzero(depth > limit)
    if len(over) == 0:
        return None
    return int(np.count_nonzero(b[: over[0]] == ord("\n"))) + 1


def parse_json(text: str, error: type[UserError], file: str | Path | None) -> Any:
    """JSON text parsed, at most `FileLimits.depth` containers deep."""
    depth = limits().depth
    line = _too_deep(_JSON_STRING.sub('""', text), b"[{", b"]}", depth)
    if line is not None:
        raise error(f"nested deeper than {depth} levels at line {line}", file=file)
    try:
        return json.loads(text)
    except json.JSONDecodeError as e:
        raise error(f"not valid JSON at line {e.lineno}, column {e.colno}: {e.msg}", file=file) from None
    except (ValueError, RecursionError) as e:  # e.g. an integer of more than 4300 digits
        raise error(f"not usable JSON: {e}", file=file) from None


# ----- YAML ---------------------------------------------------------------------------------
class _BoundedLoader(yaml.SafeLoader):
    """SafeLoader with a nesting-depth limit, duplicate keys refused and integers capped."""

    max_depth = 64
    max_int_digits = 100

    def __init__(self, stream: str):
        super().__init__(stream)
        self._depth = 0

    def compose_node(self, parent: Any, index: Any) -> Any:
        # composing is PyYAML's recursive part (scanner and parser are state machines)
        self._depth += 1
        try:
            if self._depth > self.max_depth:
                mark = self.peek_event().start_mark
                raise yaml.composer.ComposerError(
                    None, None, f"nested deeper than {self.max_depth} levels", mark
                )
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def construct_mapping(self, node: Any, deep: bool = False) -> Any:
        if isinstance(node, yaml.MappingNode):
            first_line: dict[Any, int] = {}
            for key_node, _ in node.value:
                if key_node.tag == "tag:yaml.org,2002:merge":
                    continue  # `<<: *base` keys may be overridden: that is what merging is for
                key = self.construct_object(key_node, deep=False)
                try:
                    hash(key)
                except TypeError:
                    continue  # the base constructor says "found unhashable key"
                line = key_node.start_mark.line + 1
                if key in first_line:
                    raise yaml.constructor.ConstructorError(
                        None, None,
                        f"duplicate key {key!r} (first at line {first_line[key]}); "
                        "the last would silently win",
                        key_node.start_mark,
                    )
                first_line[key] = line
        return super().construct_mapping(node, deep=deep)

    def construct_yaml_int(self, node: Any) -> int:
        digits = len(str(node.value).lstrip("+-").replace("_", ""))
        if digits > self.max_int_digits:
            raise yaml.constructor.ConstructorError(
                None, None, f"an integer of {digits} digits is too long (at most {self.max_int_digits})",
                node.start_mark,
            )
        return super().construct_yaml_int(node)


_BoundedLoader.add_constructor("tag:yaml.org,2002:int", _BoundedLoader.construct_yaml_int)


def parse_yaml(text: str, error: type[UserError], file: str | Path | None) -> Any:
    """YAML text parsed safely: bounded depth, no duplicate keys, no endless integers."""
    lim = limits()
    loader = _BoundedLoader(text)
    loader.max_depth, loader.max_int_digits = lim.depth, lim.int_digits
    try:
        return loader.get_single_data()
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(e, "problem", None) or str(e)
        raise error(f"not valid YAML{where}: {problem}", file=file) from None
    except (ValueError, RecursionError) as e:
        raise error(f"not usable YAML: {e}", file=file) from None
    finally:
        loader.dispose()
