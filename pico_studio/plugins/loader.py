"""Loading plugins: a `.py` file, a module name, or installed packages' entry points.

    load_plugin("my_stage.py")          # or "my_team.perception" (an importable module)
    load_entry_points()                 # every installed `pico_studio.plugins` entry point
    reload("my_stage.py")               # the file changed: run it again, its stages replaced

A plugin that fails to import raises `PluginError` naming the file and line (the CLI prints
it and exits 2; the page shows it): nothing of it stays registered. A reload that fails
keeps the previous version running and records the error on the `Plugin`.
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.metadata
import importlib.util
import os
import sys
import traceback
from collections.abc import Callable
from pathlib import Path
from types import ModuleType

from pico_studio.errors import PluginError
from pico_studio.plugins import declare, registry
from pico_studio.plugins.registry import LOADED, Plugin, Stage

ENTRY_POINT_GROUP = "pico_studio.plugins"


def is_path(spec: str) -> bool:
    return spec.endswith(".py") or os.sep in spec or "/" in spec


def load_plugin(spec: str) -> Plugin:
    """Load a plugin by path (`x.py`) or module name; loading one already loaded is a no-op."""
    if is_path(spec):
        path = Path(spec).expanduser().resolve()
        if str(path) in LOADED:
            return LOADED[str(path)]
        return _load(str(path), "file", lambda: _exec_file(path), path)
    if spec in LOADED:
        return LOADED[spec]
    found = _find_module(spec)
    return _load(spec, "module", lambda: importlib.import_module(spec), found)


def load_plugins(specs: list[str] | None) -> list[Plugin]:
    return [load_plugin(s) for s in specs or []]


def load_entry_points() -> list[Plugin]:
    """Every installed package's `pico_studio.plugins` entry point (its value: a module)."""
    out = []
    for ep in importlib.metadata.entry_points(group=ENTRY_POINT_GROUP):
        module = ep.value.partition(":")[0].strip()
        if module in LOADED:
            out.append(LOADED[module])
            continue
        out.append(_load(module, "entry point", _entry_point_loader(ep, module), _find_module(module)))
    return out


def _entry_point_loader(ep: importlib.metadata.EntryPoint, module: str) -> Callable[[], ModuleType]:
    def run() -> ModuleType:
        ep.load()  # imports the module (and whatever `module:attr` names)
        return importlib.import_module(module)

    return run


def reload(key: str) -> Plugin:
    """Run a loaded plugin again (its file changed); on failure the old version stays."""
    plugin = _find_loaded(key)
    old = list(plugin.stages)
    for s in old:
        registry.unregister(s)
    try:
        if plugin.origin == "file" and plugin.file is not None:
            path = plugin.file
            stages, _ = _collect(plugin.key, lambda: _exec_file(path), path)
        else:
            module = sys.modules.get(plugin.module_name)
            stages, _ = _collect(plugin.key, lambda: _reimport(plugin.module_name, module), plugin.file)
    except PluginError as e:
        for s in old:
            registry.register(s, plugin.key)
        plugin.error = str(e)
        raise
    plugin.stages = stages
    plugin.error = None
    plugin.mtime = _mtime(plugin.file)
    return plugin


def unload(key: str) -> None:
    plugin = _find_loaded(key)
    for s in plugin.stages:
        registry.unregister(s)
    del LOADED[plugin.key]


def specs() -> list[str]:
    """What loads the same plugins in another process (a spawned worker): `load_plugins(specs)`."""
    return list(LOADED)


def changed() -> list[Plugin]:
    """The loaded plugins whose file is newer than when loaded."""
    return [p for p in LOADED.values() if p.changed()]


def _find_loaded(key: str) -> Plugin:
    if key in LOADED:
        return LOADED[key]
    resolved = str(Path(key).expanduser().resolve())
    if resolved in LOADED:
        return LOADED[resolved]
    raise PluginError(f"no plugin {key!r} is loaded; loaded: {', '.join(LOADED) or 'none'}")


def _load(key: str, origin: str, run: Callable[[], ModuleType], file: Path | None) -> Plugin:
    stages, module = _collect(key, run, file)
    plugin = Plugin(key, origin, module.__name__, file, stages, _mtime(file))
    LOADED[key] = plugin
    return plugin


def _collect(key: str, run: Callable[[], ModuleType], file: Path | None) -> tuple[list[Stage], ModuleType]:
    """Run the import, collecting the stages it registers; undo them all if it fails."""
    token, stages = declare.loading(key)
    try:
        module = run()
    except Exception as e:
        for s in stages:
            registry.unregister(s)
        raise PluginError(_one_line(e), file=_where(e, file)) from None
    finally:
        declare.done(token)
    return stages, module


def _exec_file(path: Path) -> ModuleType:
    if not path.is_file():
        raise FileNotFoundError(f"no such plugin file {path}")
    # a stable name per path, so pickled params classes find their module again in a fork
    name = f"pico_studio_plugin_{path.stem}_{hashlib.sha1(str(path).encode()).hexdigest()[:8]}"
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot load {path} as Python")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        sys.modules.pop(name, None)
        raise
    return module


def _reimport(name: str, module: ModuleType | None) -> ModuleType:
    importlib.invalidate_caches()
    return importlib.reload(module) if module is not None else importlib.import_module(name)


def _find_module(name: str) -> Path | None:
    try:
        spec = importlib.util.find_spec(name)
    except (ImportError, ValueError):
        return None
    return Path(spec.origin) if spec is not None and spec.origin and spec.origin != "built-in" else None


def _mtime(file: Path | None) -> float | None:
    try:
        return os.stat(file).st_mtime_ns if file is not None else None
    except OSError:
        return None


def _one_line(e: BaseException) -> str:
    text = str(e).strip().splitlines()
    msg = text[0] if text else ""
    if isinstance(e, SyntaxError) and e.msg:
        msg = e.msg
    return f"{type(e).__name__}: {msg}" if msg else type(e).__name__


def _where(e: BaseException, file: Path | None) -> str:
    """`file:line` of the error: the plugin file's deepest line in the traceback (where the
    user's code went wrong), else the deepest line of all, else just the file."""
    if isinstance(e, SyntaxError) and e.filename:
        return f"{e.filename}:{e.lineno}" if e.lineno else e.filename
    frames = traceback.extract_tb(e.__traceback__)
    if file is not None:
        mine = [f for f in frames if Path(f.filename).resolve() == file.resolve()]
        if mine:
            return f"{mine[-1].filename}:{mine[-1].lineno}"
    outside = [f for f in frames if not f.filename.startswith(str(Path(__file__).parent))
               and "importlib" not in f.filename and "<frozen" not in f.filename]
    if outside:
        return f"{outside[-1].filename}:{outside[-1].lineno}"
    return str(file) if file is not None else "(plugin)"
