"""Checks of scene values: each raises a :class:`~brakewear.errors.SceneError` naming the key."""
from __future__ import annotations

import logging
import math
from typing import Any

from .errors import SceneError

logger = logging.getLogger(__name__)

__all__ = []


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
    u = f" {unit}" if unit else ""
    if lo is not None and (value <= lo if lo_open else value < lo):
        raise fail(key, f"{value!r}{u} is not allowed; it must be {'>' if lo_open else '>='} "
                         f"{lo:g}{u}")
    if hi is not None and value > hi:
        raise fail(key, f"{value!r}{u} is not allowed; it must be <= {hi:g}{u}")


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
