"""Where a user's parts come from: installed entry points and imports by name.

A part outside the package (an interface model, a wear law, an application:
:mod:`brakewear.registry`) is registered when the module that defines it is
imported.  brakewear imports such modules three ways, as Python would:

* an **entry point** of the group :data:`ENTRY_POINT_GROUP` in an installed
  distribution (``[options.entry_points] brakewear.parts = my_parts =
  my_package.parts`` in its setup.cfg), loaded on the first lookup of any
  table (:func:`load_entry_points`);
* the **scene key** ``[scene] import = ["my_parts"]`` (module names, or
  ``.py`` files relative to the scene file), imported before the scene's
  tables are read (:func:`import_parts`);
* **the command line**, ``brakewear run --import my_parts SCENE``
  (repeatable; names relative to the working directory).
"""
from __future__ import annotations

import importlib
import importlib.util
import logging
import sys
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from importlib.metadata import entry_points
from pathlib import Path
from types import ModuleType

from .checks import fail
from .errors import InputError, SceneError

logger = logging.getLogger(__name__)

__all__ = ["ENTRY_POINT_GROUP", "load_entry_points", "import_parts"]

#: The entry-point group of brakewear's parts: each entry point names a module
#: that registers its parts when imported (``my_parts = my_package.parts``).
ENTRY_POINT_GROUP = "brakewear.parts"

#: group -> the entry points loaded (their values); a group is loaded once
_LOADED: dict[str, tuple[str, ...]] = {}


def load_entry_points(group: str = ENTRY_POINT_GROUP) -> tuple[str, ...]:
    """Import the modules that installed distributions name in the entry-point ``group``.

    Each entry point names a module that registers its parts when imported;
    a group is loaded once per process (on the first lookup of any table).

    Parameters
    ----------
    group
        The entry-point group.

    Returns
    -------
    tuple of str
        The entry points' values (``"my_package.parts"``), in the order loaded.

    Raises
    ------
    SceneError
        Naming the entry point and its distribution if one cannot be loaded.
    """
    if group in _LOADED:
        return _LOADED[group]
    _LOADED[group] = ()          # a part's module may look the tables up while it loads
    loaded = []
    for ep in entry_points(group=group):
        dist = getattr(getattr(ep, "dist", None), "name", None) or "an installed distribution"
        try:
            ep.load()
        except Exception as exc:
            del _LOADED[group]
            raise SceneError(f"entry point {ep.name} = {ep.value!r} of the group {group!r} "
                             f"(distribution {dist}) cannot be loaded: "
                             f"{type(exc).__name__}: {exc}; fix it or uninstall {dist}"
                             ) from exc
        logger.info("parts of %s loaded (entry point %s = %r)", dist, ep.name, ep.value)
        loaded.append(ep.value)
    _LOADED[group] = tuple(loaded)
    return _LOADED[group]


def import_parts(names: Iterable[str], key: str = "--import",
                 base: str | Path | None = None) -> list[ModuleType]:
    """Import the modules that register a user's parts, as Python would import them.

    Parameters
    ----------
    names
        Module names (``"my_parts"``, ``"my_package.parts"``), found on the
        Python path and in ``base``, or paths of ``.py`` files (relative to
        ``base``), whose folder is on the path while they run.  A module
        imported already is not run again.
    key
        What gave the names, for messages (``"scene.import"``, ``"--import"``).
    base
        The folder names are relative to (the scene file's; default the
        working directory).

    Returns
    -------
    list of module
        The modules, in the order given.

    Raises
    ------
    SceneError
        Naming ``key`` and the module if it cannot be found or raises while
        it runs (a registration it refuses included).
    """
    base = Path.cwd() if base is None else Path(base)
    out = []
    for name in names:
        if not isinstance(name, str) or not name.strip():
            raise fail(key, f"{name!r} is not allowed; need a module name (my_parts, "
                            "my_package.parts) or the path of a .py file")
        is_file = name.endswith(".py") or "/" in name or "\\" in name
        try:
            module = _import_file(name, key, base) if is_file else _import_module(name, base)
        except ModuleNotFoundError as exc:
            if exc.name is None or not name.startswith(exc.name):
                raise fail(key, f"{name!r}: importing it raised ModuleNotFoundError: {exc}"
                           ) from exc
            raise fail(key, f"{name!r}: no module named {exc.name!r} on the Python path or in "
                            f"{base}; give an importable module or the path of a .py file"
                       ) from None
        except InputError as exc:
            if str(exc).startswith(f"{key}: "):
                raise
            raise fail(key, f"{name!r}: {exc}") from exc
        except Exception as exc:
            raise fail(key, f"{name!r}: importing it raised {type(exc).__name__}: {exc}"
                       ) from exc
        logger.info("%s: %r imported (%s)", key, name, getattr(module, "__file__", "?"))
        out.append(module)
    return out


@contextmanager
def _on_path(folder: Path) -> Iterator[None]:
    """Within: ``folder`` first on ``sys.path``."""
    sys.path.insert(0, str(folder))
    importlib.invalidate_caches()
    try:
        yield
    finally:
        if str(folder) in sys.path:
            sys.path.remove(str(folder))


def _import_module(name: str, base: Path) -> ModuleType:
    if name in sys.modules:
        return sys.modules[name]
    with _on_path(base):
        return importlib.import_module(name)


def _import_file(name: str, key: str, base: Path) -> ModuleType:
    path = Path(name)
    path = (path if path.is_absolute() else base / path).resolve()
    if not path.is_file():
        raise fail(key, f"{name!r}: no such file ({path})")
    modname = path.stem
    if not modname.isidentifier():
        raise fail(key, f"{name!r}: {modname!r} is not allowed as a module name; need a file "
                        "name of letters, digits and _")
    known = sys.modules.get(modname)
    if known is not None:
        where = getattr(known, "__file__", None)
        if where is not None and Path(where).resolve() == path:
            return known
        raise fail(key, f"{name!r}: a module named {modname!r} is imported already (from "
                        f"{where or 'built-in'}); rename the file")
    spec = importlib.util.spec_from_file_location(modname, path)
    if spec is None or spec.loader is None:
        raise fail(key, f"{name!r}: not a Python module ({path})")
    module = importlib.util.module_from_spec(spec)
    sys.modules[modname] = module
    try:
        with _on_path(path.parent):
            spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[modname]
        raise
    return module
