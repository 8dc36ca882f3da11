"""Reading the user's text files (JSON maps, sim configs, YAML) so that every failure is one
`UserError` naming the file and, for a parse error, the line and column."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import yaml

from pico_studio.errors import UserError


def read_text(path: str | Path, error: type[UserError], what: str) -> str:
    """The file's text; `error` saying why not ("cannot read", "not a text file (expected ...)")."""
    p = Path(path)
    try:
        return p.read_text(encoding="utf-8")
    except OSError as e:
        raise error(f"cannot read: {e.strerror or e}", file=p) from None
    except UnicodeDecodeError:
        raise error(f"not a text file (expected {what})", file=p) from None


def read_json(path: str | Path, error: type[UserError], what: str) -> Any:
    text = read_text(path, error, what)
    try:
        return json.loads(text)
    except json.JSONDecodeError as e:
        raise error(f"not valid JSON at line {e.lineno}, column {e.colno}: {e.msg}", file=Path(path)) from None


def parse_yaml(text: str, error: type[UserError], file: str | Path | None) -> Any:
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(e, "problem", None) or str(e)
        raise error(f"not valid YAML{where}: {problem}", file=file) from None
