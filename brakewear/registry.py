"""Named parts a scene chooses from, and the keys each part reads (:class:`Registry`).

The tables of brakewear's swappable parts share this: interface models
(:mod:`brakewear.interfaces.registry`), wear laws (:mod:`brakewear.laws.base`)
and applications of a schedule (:mod:`brakewear.duty.applications`).  Each
entry is registered once under its name; a scene file names it and gives
its own keys (:class:`OptionKey`: how the scene reader reads each, its
default and allowed values), which the entry checks itself
(:func:`check_options`), raising a :class:`~brakewear.errors.SceneError`
that names the key and the value in the user's units.
"""
from __future__ import annotations

import importlib
import logging
from dataclasses import dataclass
from typing import Any, Iterator, Mapping

from .checks import check_choice, check_number, fail

logger = logging.getLogger(__name__)

__all__ = ["OptionKey", "Registry", "check_options"]


@dataclass(frozen=True)
class OptionKey:
    """A key of a scene table that belongs to one registered part.

    Parameters
    ----------
    name
        The key as written in the file.
    kind
        How the scene reader reads it: ``"num"``, ``"str"``, ``"bool"``,
        ``"int"``, ``"path"`` or a unit quantity (``"length"``,
        ``"pressure"``, ``"time"``, ...: converted from the file's units).
    default
        The value when the key is not given.
    choices
        The allowed values of a string key.
    lo, hi, lo_open, unit
        The allowed range of a number (SI) and its unit for messages.
    allow_none
        Whether None (the key's own default rule) is allowed.
    doc
        One line for the documentation.
    """

    name: str
    kind: str = "num"
    default: Any = None
    choices: tuple = ()
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = True
    unit: str = ""
    allow_none: bool = False
    doc: str = ""

    def check(self, value: Any, table: str) -> None:
        """Raise a :class:`~brakewear.errors.SceneError` naming ``<table>.<name>`` and
        the value in the user's units unless ``value`` is allowed."""
        key = f"{table}.{self.name}"
        if value is None and self.allow_none:
            return
        if self.choices:
            check_choice(key, value, self.choices)
        elif self.kind not in ("str", "path", "bool"):
            check_number(key, value, self.lo, self.hi, lo_open=self.lo_open, unit=self.unit,
                         allow_none=self.allow_none)


def check_options(keys, given: Mapping[str, Any], table: str, owner: str,
                  others: Mapping[str, list[str]] | None = None) -> dict[str, Any]:
    """``given`` checked against ``keys`` (the :class:`OptionKey` of ``owner``, e.g.
    ``"interface.model = 'winkler'"``), with the defaults of the keys not given.
    ``others``: key -> the other owners that take it (named in the message)."""
    own = {k.name: k for k in keys}
    for name in given:
        if name not in own:
            takes = ", ".join(own) or "no keys of its own"
            by = (others or {}).get(name)
            why = (f"a key of {' or '.join(by)}" if by else f"unknown key {name!r}")
            raise fail(f"{table}.{name}", f"{why}; {owner} takes: {takes}")
    out = {}
    for k in keys:
        value = given.get(k.name, k.default)
        k.check(value, table)
        out[k.name] = value
    return out


class Registry:
    """Entries by name, in the order of registration.

    Parameters
    ----------
    what
        What an entry is (``"interface model"``), for messages.
    key
        The scene key that names one (``"interface.model"``).
    modules
        Modules of the package that register entries of this table when they
        are imported, loaded on the first lookup (parts that sit above the
        table's own package, such as the caliper's interface model).
    """

    def __init__(self, what: str, key: str, modules: tuple[str, ...] = ()):
        self.what, self.key = what, key
        self._entries: dict[str, Any] = {}
        self._modules, self._loaded = tuple(modules), not modules

    def _load(self) -> None:
        if not self._loaded:
            self._loaded = True
            for module in self._modules:
                importlib.import_module(module)

    def register(self, name: str, entry: Any, replace: bool = False) -> Any:
        """Add ``entry`` under ``name`` (``replace=True``: over one of the same name)."""
        if not isinstance(name, str) or not name.isidentifier():
            raise fail(self.key, f"{name!r} is not allowed as the name of a {self.what}; need "
                                 "a name of letters, digits and _")
        if name in self._entries and not replace:
            raise fail(self.key, f"{name!r} is registered already; pass replace=True to "
                                 "replace it")
        self._entries[name] = entry
        logger.debug("%s %r registered", self.what, name)
        return entry

    def unregister(self, name: str) -> None:
        """Remove ``name`` (a script or a test that registered it for a while)."""
        self.get(name)
        del self._entries[name]

    def get(self, name: str, key: str | None = None) -> Any:
        """The entry of ``name`` (a :class:`~brakewear.errors.SceneError` naming the
        key -- ``key``, default the registry's -- and the registered names if there
        is none)."""
        check_choice(key or self.key, name, self.names())
        return self._entries[name]

    def registered(self) -> tuple[Any, ...]:
        """The entries registered so far, without loading the table's modules (for
        a registration's own checks against the others)."""
        return tuple(self._entries.values())

    def names(self) -> tuple[str, ...]:
        self._load()
        return tuple(self._entries)

    def __iter__(self) -> Iterator[Any]:
        self._load()
        return iter(list(self._entries.values()))

    def __contains__(self, name: str) -> bool:
        self._load()
        return name in self._entries
