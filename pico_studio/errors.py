"""The user-facing error type: every bad input becomes one clear line naming file and field.

The CLI prints `str(error)` to stderr and exits 2; the web UI shows it as a notification.
Anything that is *not* a `UserError` is a bug and keeps its traceback.
"""

from __future__ import annotations

import reprlib
from pathlib import Path
from typing import Any

_SHORT = reprlib.Repr()
_SHORT.maxlevel, _SHORT.maxtuple, _SHORT.maxlist, _SHORT.maxdict, _SHORT.maxset = 2, 4, 4, 4, 4
_SHORT.maxstring, _SHORT.maxlong, _SHORT.maxother = 60, 40, 60


def short(value: Any) -> str:
    """A bounded repr of a user's value for an error message: a 5 MB string, a 4000-digit
    number or a YAML alias bomb (exponential when printed in full) stay one short line."""
    return _SHORT.repr(value)


class UserError(Exception):
    """Bad input from the user: a file, a field in it, and what is wrong."""

    def __init__(self, message: str, *, file: str | Path | None = None, field: str | None = None):
        self.message = message
        self.file = str(file) if file is not None else None
        self.field = field
        super().__init__(self.__str__())

    def __str__(self) -> str:
        where = ""
        if self.file and self.field:
            where = f"{self.file}: {self.field}: "
        elif self.file:
            where = f"{self.file}: "
        elif self.field:
            where = f"{self.field}: "
        return f"{where}{self.message}"


class MapError(UserError):
    """A map file (JSON or heightmap image) that cannot be used."""


class ConfigError(UserError):
    """A configuration file or value that is invalid."""


class SourceError(UserError):
    """A data source (simulator config, recording, robot connection) that cannot be used."""


class PluginError(UserError):
    """User code (a plugin) that cannot be loaded or registered: its file and line, and why."""
