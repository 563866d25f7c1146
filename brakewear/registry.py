"""Named parts a scene chooses from: their tables, and the keys each part reads.

The tables of brakewear's swappable parts share this: interface models
(:mod:`brakewear.interfaces.registry`), wear laws (:mod:`brakewear.laws.base`)
and applications of a schedule (:mod:`brakewear.duty.applications`).  A part
is one class that declares itself in class attributes, as a scikit-fem
element carries its properties:

* ``name`` -- what a scene file calls it (its own, not inherited);
* ``keys`` -- its own keys of the scene table it is named in
  (:class:`OptionKey`: how the scene reader reads each, its default and its
  allowed values), which the table checks (:func:`check_options`), raising a
  :class:`~brakewear.errors.SceneError` that names the key and the value in
  the user's units;
* its **capabilities** -- True or False class attributes, from the table's
  list (an interface model's ``accepts_load``, an application's ``braked``);
* the members the table's contract asks for (a builder, ``check``, ...).

:meth:`Registry.register` reads all of these from the class alone; nothing
about a part is declared twice.  A part outside the package reaches the
tables in one of three ways, each importing the module that registers it
(:mod:`brakewear.parts`): an entry point of the group ``brakewear.parts`` in
an installed distribution (loaded on the first lookup of any table), the
``[scene] import`` key of a scene file, or ``brakewear run --import MODULE``.
"""
from __future__ import annotations

import importlib
import logging
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, fields, is_dataclass
from typing import Any

from .checks import check_choice, check_number, fail
from .errors import InputError, SceneError
from .parts import load_entry_points

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
    scale
        The SI value of one ``unit`` where the key is read in a fixed unit of
        its own rather than the file's ``[units]`` (an application's ``v0`` in
        km/h: ``1 / 3.6``); 1 otherwise.
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
    scale: float = 1.0

    def check(self, value: Any, table: str) -> None:
        """Refuse ``value`` unless it is allowed.

        Parameters
        ----------
        value
            The key's value (SI).
        table
            The table it is a key of, for the message (``"interface"``).

        Raises
        ------
        SceneError
            Naming ``<table>.<name>`` and the value in the user's units.
        """
        key = f"{table}.{self.name}"
        if value is None and self.allow_none:
            return
        if self.choices:
            check_choice(key, value, self.choices)
        elif self.kind not in ("str", "path", "bool"):
            check_number(key, value, self.lo, self.hi, lo_open=self.lo_open, unit=self.unit,
                         allow_none=self.allow_none)


def check_options(keys: Iterable[OptionKey], given: Mapping[str, Any], table: str, owner: str,
                  others: Mapping[str, list[str]] | None = None) -> dict[str, Any]:
    """The keys a part was given, checked, with the defaults of those not given.

    Parameters
    ----------
    keys
        The part's :class:`OptionKey`.
    given
        Key -> value (SI) as the scene gave them.
    table
        The scene table, for messages (``"interface"``).
    owner
        How messages name the part (``"interface.model = 'winkler'"``).
    others
        Key -> the other parts that take it (named in the message).

    Returns
    -------
    dict
        Every key of the part -> its value.

    Raises
    ------
    SceneError
        For a key the part does not take, or a value it does not allow.
    """
    own = {k.name: k for k in keys}
    for name in given:
        if name not in own:
            takes = ", ".join(own) or "no keys of its own"
            by = (others or {}).get(name)
            why = (f"a key of {' or '.join(by)}" if by else f"unknown key {name!r}")
            raise fail(f"{table}.{name}", f"{why}; {owner} takes: {takes}")
    out = {}
    for k in own.values():
        value = given.get(k.name, k.default)
        k.check(value, table)
        out[k.name] = value
    return out


class Registry:
    """A table of parts by name, in the order of registration.

    Parameters
    ----------
    what
        What a part is (``"interface model"``), for messages.
    key
        The scene key that names one (``"interface.model"``).
    modules
        Modules of the package that register parts of this table when they
        are imported, loaded on the first lookup (parts that sit above the
        table's own package, such as the caliper's interface model).
    capabilities
        The capabilities a part of this table may declare: class attributes,
        True or False (missing: False).
    members
        What else a part's class must have (its contract's methods), named in
        the order a missing one is reported.
    error
        The :class:`~brakewear.errors.InputError` kind a refused registration
        raises.

    Notes
    -----
    The first lookup (:meth:`get`, :meth:`names`, iteration, ``in``) imports
    ``modules`` and then the entry points of :data:`~brakewear.parts.ENTRY_POINT_GROUP`
    (:func:`~brakewear.parts.load_entry_points`), so that installed parts are found without
    an import of their own.
    """

    def __init__(self, what: str, key: str, *, modules: tuple[str, ...] = (),
                 capabilities: tuple[str, ...] = (), members: tuple[str, ...] = (),
                 error: type[InputError] = SceneError):
        self.what, self.key = what, key
        self.capabilities, self.members, self.error = tuple(capabilities), tuple(members), error
        self._entries: dict[str, type[Any]] = {}
        self._modules, self._loaded = tuple(modules), False

    def _load(self) -> None:
        if not self._loaded:
            self._loaded = True
            for module in self._modules:
                importlib.import_module(module)
        load_entry_points()

    def register(self, part: type[Any], *, replace: bool = False) -> type[Any]:
        """Add the class ``part`` under its ``name``; usable as a class decorator.

        Parameters
        ----------
        part
            The part's class: its own ``name``, its ``keys`` (a tuple of
            :class:`OptionKey`, default none), its capabilities (True or
            False) and the table's ``members``.
        replace
            Replace a part of the same name (otherwise refused).

        Returns
        -------
        type
            ``part``.

        Raises
        ------
        InputError
            (The table's ``error`` kind) naming what the class lacks or
            declares wrongly.
        """
        if not isinstance(part, type):
            raise fail(self.key, f"{part!r} is not a class; a {self.what} is registered by its "
                                 "class, which carries its name, keys and capabilities",
                       self.error)
        who = part.__name__
        name = vars(part).get("name")
        if name is None:
            had = getattr(part, "name", None)
            raise fail(self.key, f"{who} declares no name of its own" + (
                f" (it inherits {had!r})" if had is not None else "") + f"; give the class "
                f"name = \"...\", what a scene calls this {self.what}", self.error)
        if not isinstance(name, str) or not name.isidentifier():
            raise fail(self.key, f"{name!r} is not allowed as the name of a {self.what}; need "
                                 "a name of letters, digits and _", self.error)
        self._check_declared(part, who)
        old = self._entries.get(name)
        if old is not None and old is not part and not replace:
            raise fail(self.key, f"{name!r} is registered already (by {old.__module__}."
                                 f"{old.__qualname__}); pass replace=True to replace it",
                       self.error)
        self._entries[name] = part
        logger.debug("%s %r registered (%s)", self.what, name, who)
        return part

    def _check_declared(self, part: type[Any], who: str) -> None:
        """``keys``, the capabilities and the members of ``part`` as the table needs them."""
        keys = getattr(part, "keys", ())
        if not isinstance(keys, tuple) or not all(isinstance(k, OptionKey) for k in keys):
            raise fail(self.key, f"{who}.keys = {keys!r}; need a tuple of "
                                 "brakewear.registry.OptionKey", self.error)
        names = [k.name for k in keys]
        if len(set(names)) != len(names):
            twice = next(n for n in names if names.count(n) > 1)
            raise fail(self.key, f"{who}.keys declares {twice!r} twice", self.error)
        given = {f.name for f in fields(part)} if is_dataclass(part) else set()
        for attr in ("name", "keys", *self.capabilities):
            if attr in given:
                raise fail(self.key, f"{who}.{attr} is a dataclass field; declare it as a class "
                                     f"attribute (ClassVar, or without an annotation)",
                           self.error)
        for cap in self.capabilities:
            if not isinstance(getattr(part, cap, False), bool):
                raise fail(self.key, f"{who}.{cap} = {getattr(part, cap)!r}; a capability is "
                                     "True or False on the class", self.error)
        missing = [m for m in self.members if not hasattr(part, m)]
        if missing:
            raise fail(self.key, f"{who} is not a {self.what}: it has no "
                                 f"{', '.join(missing)}", self.error)

    def unregister(self, name: str) -> None:
        """Remove the part ``name`` (a script or a test that registered it for a while).

        Parameters
        ----------
        name
            A registered name.
        """
        self.get(name)
        del self._entries[name]

    def get(self, name: str, key: str | None = None) -> type[Any]:
        """The class registered as ``name``.

        Parameters
        ----------
        name
            What a scene names.
        key
            The scene key for the message (default the table's).

        Returns
        -------
        type
            The part's class.

        Raises
        ------
        SceneError
            Naming the key and the registered names if there is none.
        """
        names = self.names()
        if not isinstance(name, str) or name not in names:
            known = f"allowed: {', '.join(map(repr, names))}" if names else \
                f"no {self.what} is registered"
            raise fail(key or self.key, f"{name!r} is not allowed; {known} (your own "
                                        f"{self.what}: name its module in [scene] import or "
                                        "brakewear run --import, or install it with an entry "
                                        "point of 'brakewear.parts'; docs/extending.md)")
        return self._entries[name]

    def capabilities_of(self, part: type[Any]) -> frozenset:
        """The capabilities ``part`` declares (those of the table's that are True on it).

        Parameters
        ----------
        part
            A class (registered or not).

        Returns
        -------
        frozenset
            Capability names.
        """
        return frozenset(c for c in self.capabilities if getattr(part, c, False) is True)

    def options(self, part: type[Any], given: Mapping[str, Any], table: str,
                owner: str | None = None) -> dict[str, Any]:
        """``given`` checked against the keys of ``part`` (:func:`check_options`); a key of
        another registered part is named as such.

        Parameters
        ----------
        part
            A registered class.
        given
            Key -> value (SI).
        table
            The scene table (``"interface"``, ``"wear.pad"``).
        owner
            How messages name the part (default ``"<key> = '<name>'"``).

        Returns
        -------
        dict
            Every key of the part -> its value.
        """
        others: dict[str, list[str]] = {}
        for other in self:
            if other is not part:
                for k in getattr(other, "keys", ()):
                    others.setdefault(k.name, []).append(f"{self.key} = {other.name!r}")
        return check_options(getattr(part, "keys", ()), given, table,
                             owner or f"{self.key} = {part.name!r}", others)

    def key_kinds(self) -> dict[str, str]:
        """Every registered part's keys: name -> how the scene reader reads it."""
        return {k.name: k.kind for part in self for k in getattr(part, "keys", ())}

    def registered(self) -> tuple[type[Any], ...]:
        """The parts registered so far, without loading the table's modules (for
        a registration's own checks against the others)."""
        return tuple(self._entries.values())

    def names(self) -> tuple[str, ...]:
        """The registered names, in the order of registration."""
        self._load()
        return tuple(self._entries)

    def __iter__(self) -> Iterator[type[Any]]:
        self._load()
        return iter(list(self._entries.values()))

    def __contains__(self, name: str) -> bool:
        self._load()
        return name in self._entries
