"""Checks of input values: each raises an :class:`~brakewear.errors.InputError` kind
(a :class:`~brakewear.errors.SceneError` unless told) naming the key and the value.

A value read from a file is shown as the file wrote it: the reader registers each
such key with its unit (:func:`user_units`), and every check here shows the value
and its bounds in that unit; a value given from Python is shown in SI.
"""
from __future__ import annotations

import logging
import math
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar
from types import MappingProxyType
from typing import Any

import numpy as np

from .errors import InputError, SceneError

logger = logging.getLogger(__name__)

__all__ = []


#: key -> (unit, factor, offset, value as written) of the values a scene file gave
#: in its own units (SI = value * factor + offset); checks show those, not SI.
_USER_UNITS: ContextVar[Mapping[str, tuple]] = ContextVar(
    "brakewear_user_units", default=MappingProxyType({}))


@contextmanager
def user_units(mapping: Mapping[str, tuple]) -> Iterator[None]:
    """Within: messages about the keys of ``mapping`` speak the scene file's units."""
    token = _USER_UNITS.set(mapping)        # not a copy: the reader fills it as it goes
    try:
        yield
    finally:
        _USER_UNITS.reset(token)


@contextmanager
def file_messages(source: str, mapping: Mapping[str, tuple]) -> Iterator[None]:
    """Within: checks speak the file's units (``mapping``, as for :func:`user_units`) and
    every :class:`~brakewear.errors.InputError` raised names the file ``source`` (a
    ``"<...>"`` source, Python's, is not named)."""
    with user_units(mapping):
        try:
            yield
        except InputError as exc:
            if not source or source.startswith("<") or str(exc).startswith(source):
                raise
            raise type(exc)(f"{source}: {exc}") from None


def user_unit(key: str) -> str | None:
    """The unit the user gave ``key`` in (None: SI, or not from a scene file)."""
    m = _USER_UNITS.get().get(key)
    return None if m is None else m[0]


def user_scale(key: str) -> tuple[str, float, float] | None:
    """``(unit, factor, offset)`` of the unit the user gave ``key`` in (SI = value *
    factor + offset), or None (SI, or not from a scene file)."""
    m = _USER_UNITS.get().get(key)
    return None if m is None else (m[0], m[1], m[2])


#: the unit a computed value is shown in outside a scene file: (name, factor, offset)
_DEFAULT_SHOWN = {"length": ("mm", 1e-3, 0.0), "pressure": ("MPa", 1e6, 0.0),
                  "time": ("s", 1.0, 0.0), "angular_speed": ("rad/s", 1.0, 0.0),
                  "temperature": ("C", 1.0, 273.15)}


def shown_in(kind: str, value: float, digits: int = 4, decimals: int | None = None) -> str:
    """``value`` (SI) of a quantity ``kind`` (``"length"``, ``"pressure"``, ``"time"``,
    ``"angular_speed"``, ``"temperature"``) in the unit the scene file's ``[units]``
    gives it (outside a scene file: mm, MPa, s, rad/s, C), to ``digits`` significant
    digits (or ``decimals`` decimals)."""
    m = _USER_UNITS.get().get(f"units.{kind}")
    name, factor, offset = _DEFAULT_SHOWN[kind] if m is None else m[:3]
    x = (value - offset) / factor
    return f"{x:.{decimals}f} {name}" if decimals is not None else f"{x:.{digits}g} {name}"


def shown_value(key: str, value: Any, unit: str) -> str:
    """``value`` (SI, in ``unit``) as the user wrote it for ``key``: ``"30.0 mm"``."""
    return _shown(key, value, unit)[0]


def _shown(key: str, value: Any, unit: str, bounds: tuple = ()) -> tuple[str, list[str]]:
    """``value`` and ``bounds`` (SI) as text in the user's unit for ``key``."""
    m = _USER_UNITS.get().get(key)
    if m is None or isinstance(value, bool) or not isinstance(value, (int, float)):
        u = f" {unit}" if unit else ""
        return f"{value!r}{u}", [f"{b:g}{u}" for b in bounds]
    name, factor, offset, raw = m
    back = (value - offset) / factor
    v = raw if isinstance(raw, (int, float)) and math.isclose(
        back, raw, rel_tol=1e-9, abs_tol=1e-12 * abs(offset)) else float(f"{back:.12g}")
    return f"{v!r} {name}", [f"{(b - offset) / factor:.6g} {name}" for b in bounds]


def _compact(v: float) -> str:
    """A number as written (``60.0``), or to 6 digits where that is long."""
    r = repr(v)
    return r if len(r) <= 12 else f"{v:.6g}"


def fail(key: str, msg: str, kind: type[InputError] = SceneError) -> InputError:
    """The error (``kind``, a SceneError unless told) ``"key: msg"``."""
    return kind(f"{key}: {msg}")


def check_choice(key: str, value: Any, allowed: tuple,
                 kind: type[InputError] = SceneError) -> None:
    if value not in allowed:
        raise fail(key, f"{value!r} is not allowed; allowed: "
                        f"{', '.join(repr(a) for a in allowed)}", kind)


def check_number(key: str, value: Any, lo: float | None = None, hi: float | None = None,
                  lo_open: bool = True, unit: str = "", allow_none: bool = False,
                  kind: type[InputError] = SceneError) -> None:
    """Refuse ``value`` unless a finite number within ``lo`` (open or closed) .. ``hi``
    (closed), naming ``key`` and showing the value and the bound it passed in the
    user's unit."""
    if value is None and allow_none:
        return
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise fail(key, f"{value!r} is a {type(value).__name__}; expected a number", kind)
    if not math.isfinite(value):
        raise fail(key, f"{value!r} is not allowed; it must be a finite number", kind)
    if lo is not None and (value <= lo if lo_open else value < lo):
        v, (b,) = _shown(key, value, unit, (lo,))
        raise fail(key, f"{v} is not allowed; it must be {'>' if lo_open else '>='} {b}", kind)
    if hi is not None and value > hi:
        v, (b,) = _shown(key, value, unit, (hi,))
        raise fail(key, f"{v} is not allowed; it must be <= {b}", kind)


def check_order(low_key: str, low: float, high_key: str, high: float, unit: str = "", *,
                blame: str | None = None, strict: bool = True, why: str = "",
                kind: type[InputError] = SceneError) -> None:
    """Refuse unless ``low < high`` (``<=`` when not ``strict``): a bound checked against
    another key or the start state.  The message is about ``blame`` (default
    ``high_key``) and names the other key, both values in the user's units."""
    if (low < high) if strict else (low <= high):
        return
    blame = high_key if blame is None else blame
    # a key the user did not write (a default, a geometry value) speaks the other's unit
    scale = user_scale(low_key) or user_scale(high_key)
    lo_txt, hi_txt = (shown_value(k, v, unit) if user_scale(k) else
                      f"{_compact(v)}{' ' + unit if unit else ''}" if scale is None else
                      f"{(v - scale[2]) / scale[1]:.6g} {scale[0]}"
                      for k, v in ((low_key, low), (high_key, high)))
    if blame == high_key:
        what = f"{hi_txt} is not allowed; it must be {'above' if strict else 'at least'} " \
               f"{low_key} = {lo_txt}"
    else:
        what = f"{lo_txt} is not allowed; it must be {'below' if strict else 'at most'} " \
               f"{high_key} = {hi_txt}"
    raise fail(blame, what + (f" ({why})" if why else ""), kind)


#: Plausible ranges (SI): key -> (unit, error below, warn below, warn above, error above,
#: what the range means).  Outside the error bounds a value is refused; outside the
#: warning bounds it is logged as a warning.
PLAUSIBLE: dict[str, tuple] = {
    "environment.line_pressure": ("Pa", None, None, 25e6, 100e6,
                                  "brake line pressures stay below 25 MPa (250 bar)"),
    "interface.mu": ("", None, None, 1.0, 2.0,
                     "friction coefficients of brake pairs lie between 0.2 and 0.7"),
    "environment.omega": ("rad/s", None, None, 500.0, 5000.0,
                          "a wheel at 400 km/h turns at about 400 rad/s"),
    "environment.ambient": ("K", 173.15, 233.15, 323.15, 673.15,
                            "ambient temperatures lie between -40 C and 50 C"),
    "thermal.T_initial": ("K", 173.15, 233.15, 1073.15, 1473.15,
                          "brake temperatures stay below 800 C"),
    "thermal.T_ref": ("K", 173.15, 233.15, 1073.15, 1473.15,
                      "brake temperatures stay below 800 C"),
    "T_threshold": ("K", 173.15, 233.15, 1073.15, 1473.15,
                    "brake temperatures stay below 800 C"),
}


def check_plausible(key: str, value: Any, table: str | None = None,
                    kind: type[InputError] = SceneError) -> None:
    """Refuse a value outside the error bounds of :data:`PLAUSIBLE`, warn outside the
    warning bounds (``table``: the entry, default ``key``; None values pass)."""
    if value is None or isinstance(value, bool) or not isinstance(value, (int, float)):
        return
    unit, e_lo, w_lo, w_hi, e_hi, why = PLAUSIBLE[table or key]
    # a value checked under its own name, or under the scene key it stands for
    shown_key = key if key in _USER_UNITS.get() or table is None else table
    v, (el, wl, wh, eh) = _shown(shown_key, value, unit, tuple(
        math.nan if b is None else b for b in (e_lo, w_lo, w_hi, e_hi)))
    if (e_lo is not None and value < e_lo) or (e_hi is not None and value > e_hi):
        allowed = (f"{el} to {eh}" if e_lo is not None and e_hi is not None
                   else f"at most {eh}" if e_hi is not None else f"at least {el}")
        raise fail(key, f"{v} is implausible; {why}; allowed: {allowed}", kind)
    if (w_lo is not None and value < w_lo) or (w_hi is not None and value > w_hi):
        # once per quantity and value: a scene's line pressure is checked where it is
        # read, and again by the model and the interface it builds
        if (table or key, value) in _WARNED:
            return
        _WARNED.add((table or key, value))
        bound = f"below {wl}" if w_lo is not None and value < w_lo else f"above {wh}"
        logger.warning("%s = %s is unusual (%s; %s); check the value and its unit",
                       shown_key, v, bound, why)


#: (quantity, value) pairs :func:`check_plausible` has warned about (each once)
_WARNED: set = set()


def check_line_pressure(line_pressure: Any) -> None:
    """Refuse a line pressure (Pa) that is not > 0 or is implausible."""
    if not np.isfinite(line_pressure) or line_pressure <= 0:
        raise SceneError(f"line_pressure = {line_pressure!r} Pa is not allowed; need > 0")
    check_plausible("line_pressure", float(line_pressure), "environment.line_pressure")


def check_int(key: str, value: Any, lo: int, allow_none: bool = False,
              kind: type[InputError] = SceneError, hi: int | None = None) -> None:
    if value is None and allow_none:
        return
    if isinstance(value, bool) or not isinstance(value, int):
        raise fail(key, f"{value!r} is a {type(value).__name__}; expected a whole number",
                   kind)
    if value < lo or (hi is not None and value > hi):
        allowed = f">= {lo}" if hi is None else f"a whole number {lo} to {hi}"
        raise fail(key, f"{value!r} is not allowed; it must be {allowed}", kind)


def check_bool(key: str, value: Any, kind: type[InputError] = SceneError) -> None:
    if not isinstance(value, bool):
        raise fail(key, f"{value!r} is a {type(value).__name__}; expected true or false",
                   kind)


def read_csv_rows(path, what: str, kind: type[InputError] = SceneError
                  ) -> tuple[list[dict], list[str]]:
    """The rows (dicts) and the header of a CSV file whose lines starting with ``#``
    are comments; a file that cannot be read is a ``kind`` error naming ``what`` it
    was to be (``"the drive cycle"``)."""
    import csv
    from pathlib import Path

    path = Path(path)
    try:
        numbered = [(n, ln) for n, ln in enumerate(path.read_text(encoding="utf-8-sig")
                                                   .splitlines(), start=1)
                    if ln.strip() and not ln.lstrip().startswith("#")]
    except OSError as e:
        raise kind(f"{path}: cannot read {what} ({e.strerror})") from None
    except UnicodeDecodeError as e:
        raise kind(f"{path}: cannot read {what}: not a text file ({e.reason} at byte "
                   f"{e.start})") from None
    try:
        table = list(csv.reader([ln for _, ln in numbered]))
    except csv.Error as e:
        raise kind(f"{path}: cannot read {what}: not a CSV table ({e})") from None
    if not table:
        return [], []
    header = table[0]
    twice = next((c for i, c in enumerate(header) if c in header[:i]), None)
    if twice is not None:
        raise kind(f"{path}, line {numbered[0][0]}: the column {twice!r} is named twice in "
                   f"the header; name each column once")
    for (n, _), cells in zip(numbered[1:], table[1:]):
        if len(cells) != len(header):
            raise kind(f"{path}, line {n}: {len(cells)} cells, the header has {len(header)} "
                       "(a row cut short, or a stray comma); give every row a cell per "
                       "column, empty where nothing was measured")
    rows = [dict(zip(header, cells)) for cells in table[1:]]
    return rows, list(header)
