"""The kinds of application a schedule knows: their table, and one read from a scene file.

An application class (:class:`~brakewear.duty.applications.Application`) is
registered by :func:`register_application` under its ``name`` (a class
attribute, with its ``keys`` and ``braked``); a scene file's ``[schedule]
applications`` then lists it by ``kind``, each field in the unit of its key
(:func:`application_from_table`).  The built-in kinds -- ``"stop"``,
``"drag"``, ``"dwell"`` -- register themselves in
:mod:`brakewear.duty.applications`.
"""
from __future__ import annotations

import logging
from dataclasses import fields, is_dataclass
from typing import Any

from ..errors import DutyError
from ..registry import Registry
from .vehicle import _finite

logger = logging.getLogger(__name__)

__all__ = ["register_application", "unregister_application", "application_kinds",
           "application_from_table", "is_application"]

_KINDS = Registry("application", "schedule.applications.kind", capabilities=("braked",),
                  members=("braked", "needs_vehicle", "check", "check_scene", "run"),
                  error=DutyError)


def register_application(part: type[Any], *, replace: bool = False) -> type[Any]:
    """Add an application class to the kinds a schedule knows (a class decorator).

    Parameters
    ----------
    part
        The application's class (:class:`Application`): its ``name``, its
        ``keys`` (one per field a scene file may give), ``braked`` and its
        methods.
    replace
        Replace a kind of the same name (otherwise refused).

    Returns
    -------
    type
        ``part``.

    Raises
    ------
    DutyError
        Naming what the class lacks, or a key that is not one of its fields.
    """
    given = {f.name for f in fields(part)} if is_dataclass(part) else None
    for k in getattr(part, "keys", ()):
        if given is not None and getattr(k, "name", None) not in given:
            raise DutyError(f"{part.__name__}.keys: {getattr(k, 'name', k)!r} is not a field "
                            f"of {part.__name__}; its keys are the fields a scene file gives")
    return _KINDS.register(part, replace=replace)


def unregister_application(kind: str) -> None:
    """Take the kind ``kind`` out of the table (registered for a while, by a test).

    Parameters
    ----------
    kind
        A registered application's ``name``.
    """
    _KINDS.unregister(kind)


def application_kinds() -> tuple[str, ...]:
    """The registered kinds, in the order of registration.

    Returns
    -------
    tuple of str
        Their names.
    """
    return _KINDS.names()


def is_application(app) -> bool:
    """Whether ``app`` is of a registered kind.

    Parameters
    ----------
    app
        Any object.

    Returns
    -------
    bool
        True for an instance of a registered class.
    """
    return any(isinstance(app, cls) for cls in _KINDS)


def application_from_table(table: dict, where: str = "schedule", source: str = "") -> Any:
    """An application from a scene file's table: ``kind`` and the kind's fields in
    the units of its :attr:`~Application.keys` (a :class:`DutyError` naming ``where``);
    ``source``
    (where it comes from, for messages) goes to a kind with a ``source`` field."""
    if not isinstance(table, dict) or "kind" not in table:
        raise DutyError(f"{where}: {table!r} is not an application; need a table with "
                        f"kind = one of {', '.join(map(repr, application_kinds()))}")
    kind = table["kind"]
    if kind not in _KINDS:
        raise DutyError(f"{where}: kind = {kind!r} is not allowed; registered kinds: "
                        f"{', '.join(map(repr, application_kinds()))}")
    cls = _KINDS.get(kind)
    keys = {k.name: k for k in cls.keys}
    unknown = sorted(set(table) - set(keys) - {"kind"})
    if unknown:
        raise DutyError(f"{where}: unknown key(s) {', '.join(unknown)} of a {kind}; allowed: "
                        + ", ".join(f"{n} ({k.unit or '-'})" for n, k in keys.items()))
    kw = {}
    for name, v in table.items():
        if name == "kind":
            continue
        k = keys[name]
        if k.scale != 1.0 and not _finite(v):
            raise DutyError(f"{where}: {kind}.{name} = {v!r} is not a number ({k.unit})")
        kw[name] = v * k.scale if k.scale != 1.0 else v
    if source and "source" in {f.name for f in fields(cls)}:
        kw["source"] = source
    try:
        return cls(**kw)
    except TypeError as exc:
        raise DutyError(f"{where}: {kind}: {exc}") from None
    except DutyError as exc:
        raise DutyError(f"{where}: {exc} (in SI units; the file's: "
                        + ", ".join(f"{k.name} {k.unit}" for k in cls.keys) + ")") from None
