"""Checks of scene values: each raises a :class:`~brakewear.errors.SceneError` naming the key."""
from __future__ import annotations

import logging
import math
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any, Iterator, Mapping

from .errors import SceneError

logger = logging.getLogger(__name__)

__all__ = []


#: key -> (unit, factor, offset, value as written) of the values a scene file gave
#: in its own units (SI = value * factor + offset); checks show those, not SI.
_USER_UNITS: ContextVar[Mapping[str, tuple]] = ContextVar("brakewear_user_units", default={})


@contextmanager
def user_units(mapping: Mapping[str, tuple]) -> Iterator[None]:
    """Within: messages about the keys of ``mapping`` speak the scene file's units."""
    token = _USER_UNITS.set(mapping)        # not a copy: the reader fills it as it goes
    try:
        yield
    finally:
        _USER_UNITS.reset(token)


def user_unit(key: str) -> str | None:
    """The unit the user gave ``key`` in (None: SI, or not from a scene file)."""
    m = _USER_UNITS.get().get(key)
    return None if m is None else m[0]


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
    v = raw if math.isclose(back, raw, rel_tol=1e-9, abs_tol=1e-12 * abs(offset)) else back
    return f"{v!r} {name}", [f"{(b - offset) / factor:.6g} {name}" for b in bounds]


def fail(key: str, msg: str) -> SceneError:
    return SceneError(f"{key}: {msg}")


def check_choice(key: str, value: Any, allowed: tuple) -> None:
    if value not in allowed:
        raise fail(key, f"{value!r} is not allowed; allowed: "
                         f"{', '.join(repr(a) for a in allowed)}")


def check_number(key: str, value: Any, lo: float | None = None, hi: float | None = None,
                  lo_open: bool = True, unit: str = "", allow_none: bool = False) -> None:
    if value is None and allow_none:
        return
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise fail(key, f"{value!r} is a {type(value).__name__}; expected a number")
    if not math.isfinite(value):
        raise fail(key, f"{value!r} is not allowed; it must be a finite number")
    if lo is not None and (value <= lo if lo_open else value < lo):
        v, (b,) = _shown(key, value, unit, (lo,))
        raise fail(key, f"{v} is not allowed; it must be {'>' if lo_open else '>='} {b}")
    if hi is not None and value > hi:
        v, (b,) = _shown(key, value, unit, (hi,))
        raise fail(key, f"{v} is not allowed; it must be <= {b}")


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


def check_plausible(key: str, value: Any, table: str | None = None) -> None:
    """Refuse a value outside the error bounds of :data:`PLAUSIBLE`, warn outside the
    warning bounds (``table``: the entry, default ``key``; None values pass)."""
    if value is None or isinstance(value, bool) or not isinstance(value, (int, float)):
        return
    unit, e_lo, w_lo, w_hi, e_hi, why = PLAUSIBLE[table or key]
    v, (el, wl, wh, eh) = _shown(key, value, unit, tuple(
        math.nan if b is None else b for b in (e_lo, w_lo, w_hi, e_hi)))
    if (e_lo is not None and value < e_lo) or (e_hi is not None and value > e_hi):
        allowed = (f"{el} to {eh}" if e_lo is not None and e_hi is not None
                   else f"at most {eh}" if e_hi is not None else f"at least {el}")
        raise fail(key, f"{v} is implausible; {why}; allowed: {allowed}")
    if (w_lo is not None and value < w_lo) or (w_hi is not None and value > w_hi):
        bound = f"below {wl}" if w_lo is not None and value < w_lo else f"above {wh}"
        logger.warning("%s = %s is unusual (%s; %s); check the value and its unit", key, v,
                       bound, why)


def check_int(key: str, value: Any, lo: int, allow_none: bool = False) -> None:
    if value is None and allow_none:
        return
    if isinstance(value, bool) or not isinstance(value, int):
        raise fail(key, f"{value!r} is a {type(value).__name__}; expected a whole number")
    if value < lo:
        raise fail(key, f"{value!r} is not allowed; it must be >= {lo}")


def check_bool(key: str, value: Any) -> None:
    if not isinstance(value, bool):
        raise fail(key, f"{value!r} is a {type(value).__name__}; expected true or false")
