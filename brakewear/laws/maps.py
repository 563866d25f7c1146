"""Friction and wear laws over pressure, speed and temperature, evaluated per node.

A pad material is characterised on a tribometer: the friction coefficient
``mu`` and the specific wear rate ``k`` (m^2/N, the Archard coefficient of
``dh/dt = k p v``) measured over a grid of contact pressures ``p``, sliding
speeds ``v`` and temperatures ``T``.  Such a measured map is a
:class:`TableMap` (read from a CSV by :func:`read_map`), used as a friction
law by :class:`FrictionMap` and as a wear law by :class:`WearMap`.  Two
closed forms complete them: :class:`StribeckFriction` (``mu`` falling from a
static to a kinetic value with speed) and :class:`MildSevereWear` (a switch
from a mild to a severe wear coefficient above a ``p v`` or temperature
threshold).

Every law answers the same per-node calls, the wear loop's protocol
(:class:`~brakewear.laws.base.NodeFrictionLaw`, :class:`~brakewear.laws.base.NodeWearLaw`;
:class:`~brakewear.laws.base.FrictionLaw` and :class:`~brakewear.laws.base.WearLaw` answer
them too): arrays ``p`` (Pa,
tension counts as 0), ``v`` (m/s, >= 0) and ``T`` (K, or None when the law
does not need it) in, one value per node out.  All are frozen dataclasses
of numbers, strings, tuples and arrays, so that a run's fingerprint
(:func:`brakewear.wear.fingerprint`) holds them exactly.
"""
from __future__ import annotations

import logging
import os
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np
from scipy.special import expit

from ..errors import LawError, MapError
from .base import NodeFrictionLaw, NodeWearLaw, archard_rate, node_inputs
from .map_files import AXES, AXIS_UNITS, BOUNDS, check_range, parse_table, read_table

logger = logging.getLogger(__name__)

__all__ = ["NodeFrictionLaw", "NodeWearLaw", "TableMap", "read_map", "FrictionMap", "WearMap",
           "StribeckFriction", "MildSevereWear", "example_map", "EXAMPLE_MAP", "AXIS_UNITS"]

#: the illustrative resin-pad map shipped with the package (:func:`example_map`)
EXAMPLE_MAP = "data/maps/resin_pad_illustrative.csv"

#: unit shown -> (factor to SI, offset) for the messages of a map's look-up
_SHOWN = {name: (f, o) for units in AXIS_UNITS.values() for name, f, o in units.values()}
_SI_UNIT = {"p": "Pa", "v": "m/s", "T": "K"}


@dataclass(frozen=True, eq=False)
class TableMap:
    """A quantity tabulated on a tensor grid of pressure, speed and temperature.

    Between the grid points the map is multilinear: linear in each axis in
    turn (on a 2 x 2 x 2 cell, trilinear), so data linear in each axis is
    reproduced to round-off and a constant exactly.  An axis with a single
    value makes the map constant along it.

    Parameters
    ----------
    axes
        The axes' names, a subset of ``("p", "v", "T")`` in any order.
    grid
        One strictly increasing tuple of values per axis, in SI (Pa, m/s, K).
    values
        The quantity at the grid points, shape ``(len(g) for g in grid)``.
    quantity
        ``"mu"`` (friction coefficient, 0..2) or ``"k"`` (specific wear rate,
        m^2/N, 0..1e-10).
    outside
        At a node beyond the grid: ``"clamp"`` takes the value at the nearest
        edge; ``"error"`` raises :class:`~brakewear.errors.MapError` naming the
        quantity, the value and the grid's range.  Only loaded nodes (p > 0)
        are checked: a node out of contact neither rubs nor wears.
    units
        The units the map's messages show per axis (the CSV's; default SI).
    source
        Where the map came from (the CSV's path), for messages.

    Notes
    -----
    ``units`` and ``source`` do not enter a run's fingerprint: the same
    numbers from another file or in other units are the same map.
    """

    axes: tuple[str, ...]
    grid: tuple[tuple[float, ...], ...]
    values: np.ndarray
    quantity: str
    outside: str = "clamp"
    units: tuple[str, ...] = field(default=(), compare=False)
    source: str = field(default="", compare=False)

    def __post_init__(self):
        name = f"TableMap ({self.source})" if self.source else "TableMap"
        axes = tuple(self.axes)
        if not axes or len(set(axes)) != len(axes) or not set(axes) <= set(AXES):
            raise MapError(f"{name}: axes = {self.axes!r} is not allowed; need distinct "
                           f"names from {AXES}")
        if self.quantity not in BOUNDS or self.quantity in AXES:
            raise MapError(f"{name}: quantity = {self.quantity!r} is not allowed; allowed: "
                           "'mu', 'k'")
        if self.outside not in ("clamp", "error"):
            raise MapError(f"{name}: outside = {self.outside!r} is not allowed; allowed: "
                           "'clamp', 'error'")
        if len(self.grid) != len(axes):
            raise MapError(f"{name}: {len(self.grid)} grid axes for the {len(axes)} axes {axes}")
        grid = tuple(tuple(float(x) for x in np.ravel(g)) for g in self.grid)
        for a, g in zip(axes, grid):
            if not g or np.any(np.diff(g) <= 0):
                raise MapError(f"{name}: the {a} axis {g} is not allowed; need one or more "
                               "strictly increasing values")
            for x in g:
                check_range(f"{name}: {a} axis value", a, x, _SI_UNIT[a])
        values = np.array(self.values, dtype=float)
        if values.shape != tuple(len(g) for g in grid):
            raise MapError(f"{name}: values have shape {values.shape}; the grid needs "
                           f"{tuple(len(g) for g in grid)}")
        for x in values.flat:
            check_range(f"{name}: {self.quantity} value", self.quantity, x, "")
        values.setflags(write=False)
        units = tuple(self.units) or tuple(_SI_UNIT[a] for a in axes)
        if len(units) != len(axes) or not set(units) <= set(_SHOWN):
            raise MapError(f"{name}: units = {self.units!r} is not allowed; need one of "
                           f"{sorted(_SHOWN)} per axis")
        for key, value in (("axes", axes), ("grid", grid), ("values", values),
                           ("units", units)):
            object.__setattr__(self, key, value)

    @property
    def needs_temperature(self) -> bool:
        """Whether the map varies with temperature (a ``T`` axis)."""
        return "T" in self.axes

    def evaluate(self, p, v, T=None) -> np.ndarray:
        """The quantity per node (multilinear on the grid, see the class docstring).

        Parameters
        ----------
        p, v, T
            Pressure (Pa, tension counts as 0), sliding speed (m/s, >= 0) and
            temperature (K; None only when the map has no ``T`` axis), arrays
            that broadcast together (:func:`brakewear.laws.base.node_inputs`).

        Returns
        -------
        numpy.ndarray
            One value per node, of the broadcast shape.
        """
        p, v, T, shape = node_inputs(p, v, T, MapError)
        if T is None and self.needs_temperature:
            raise MapError(f"the {self.quantity} map {self.source or ''} varies with "
                           "temperature: give T (K), e.g. a thermal model's face temperature")
        at = {"p": p, "v": v, "T": T}
        xs = [np.broadcast_to(at[a], shape).ravel() for a in self.axes]
        if self.outside == "error":
            self._check_inside(xs, np.broadcast_to(p, shape).ravel() > 0)
        return _multilinear(self.grid, self.values, xs).reshape(shape)

    def beyond(self, axis: str, values) -> str | None:
        """Text naming the value of ``values`` (SI) farthest beyond the grid along
        ``axis``, in the map's units, or None if all lie on the grid (or the map does
        not vary along ``axis``)."""
        if axis not in self.axes:
            return None
        k = self.axes.index(axis)
        g, unit = self.grid[k], self.units[k]
        x = np.asarray(values, dtype=float).ravel()
        beyond = np.maximum(g[0] - x, x - g[-1])
        if not beyond.size or beyond.max() <= 1e-9 * max(abs(g[0]), abs(g[-1])):
            return None
        f, o = _SHOWN[unit]
        shown = [f"{(b - o) / f:.6g}" for b in (x[np.argmax(beyond)], g[0], g[-1])]
        return (f"{axis} = {shown[0]} {unit} is outside the map's range {shown[1]} to "
                f"{shown[2]} {unit}")

    def _check_inside(self, xs: list[np.ndarray], loaded: np.ndarray) -> None:
        """Raise naming the farthest loaded node beyond the grid, if any."""
        for a, unit, g, x in zip(self.axes, self.units, self.grid, xs):
            lo, hi = g[0], g[-1]
            tol = 1e-9 * max(abs(lo), abs(hi))      # unit conversions' round-off
            beyond = np.where(loaded, np.maximum(lo - x, x - hi), -np.inf)
            if beyond.size and beyond.max() > tol:
                i = int(np.argmax(beyond))
                f, o = _SHOWN[unit]
                shown = [f"{(b - o) / f:.6g}" for b in (x[i], lo, hi)]
                n = int((beyond > tol).sum())
                raise MapError(
                    f"the {self.quantity} map {self.source or ''}: {a} = {shown[0]} {unit} "
                    f"(node {i}, the farthest of {n} loaded node(s) outside) is outside the "
                    f"map's range {shown[1]} to {shown[2]} {unit}; extend the map or use "
                    "outside='clamp' (a scene's map_outside = 'clamp') to take the edge "
                    "value")


def read_map(path: str | os.PathLike, quantity: str, outside: str = "clamp") -> TableMap:
    """A map from a CSV file (the format: :mod:`brakewear.laws.map_files`).

    Parameters
    ----------
    path
        The CSV: one row per grid point, axis columns ``p_Pa``, ``p_kPa``,
        ``p_MPa`` or ``p_bar``; ``v_m_s`` or ``v_km_h``; ``T_K`` or ``T_C``
        (one or more axes) and the value column.
    quantity
        ``"mu"`` (column ``mu``) or ``"k"`` (``k_m2_N``, or ``k_mm3_Nm`` =
        1e-9 m^2/N); a file may hold both, each read on its own.
    outside
        ``"clamp"`` or ``"error"`` (see :class:`TableMap`).

    Returns
    -------
    TableMap
        In SI; a bad file raises :class:`~brakewear.errors.MapError` naming the
        file, the row (line number) and the column.
    """
    return TableMap(**read_table(path, quantity), outside=outside)


def _multilinear(grid, values: np.ndarray, xs: list[np.ndarray]) -> np.ndarray:
    """Interpolate ``values`` on ``grid`` at the points ``xs`` (one array per axis),
    clamped to the grid: linear in each axis in turn, ``lo + t (hi - lo)``, so that
    equal neighbours give their value exactly."""
    idx, ts = [], []
    for g, x in zip(grid, xs):
        g = np.asarray(g)
        if g.size == 1:
            idx.append((np.zeros(x.shape, dtype=int),) * 2)
            ts.append(None)
            continue
        x = np.clip(x, g[0], g[-1])
        i = np.clip(np.searchsorted(g, x, side="right") - 1, 0, g.size - 2)
        idx.append((i, i + 1))
        ts.append((x - g[i]) / (g[i + 1] - g[i]))

    def along(k: int, picks: tuple) -> np.ndarray:
        if k == len(idx):
            return values[picks]
        lo = along(k + 1, picks + (idx[k][0],))
        if ts[k] is None:
            return lo
        return lo + ts[k] * (along(k + 1, picks + (idx[k][1],)) - lo)

    return np.asarray(along(0, ()), dtype=float)


def example_map(quantity: str, outside: str = "clamp") -> TableMap:
    """The illustrative resin-pad map shipped with the package (:data:`EXAMPLE_MAP`).

    Parameters
    ----------
    quantity
        ``"mu"`` or ``"k"``.
    outside
        ``"clamp"`` or ``"error"`` (see :class:`TableMap`).

    Returns
    -------
    TableMap
        ILLUSTRATIVE numbers of the shape typical of resin-bonded pads, not a
        measurement: calibrate with your own material's map.
    """
    import importlib.resources

    text = importlib.resources.files("brakewear").joinpath(EXAMPLE_MAP).read_text("utf-8")
    return TableMap(**parse_table(text, f"brakewear/{EXAMPLE_MAP}", quantity), outside=outside)


@dataclass(frozen=True, eq=False)
class _TableLaw:
    """A law read off a :class:`TableMap` of ``_quantity``."""

    table: TableMap
    _quantity: ClassVar[str] = ""

    def __post_init__(self):
        if not isinstance(self.table, TableMap) or self.table.quantity != self._quantity:
            raise MapError(f"{type(self).__name__} needs a TableMap of {self._quantity}; "
                           f"got {self.table!r}")

    @property
    def needs_temperature(self) -> bool:
        """Whether the map varies with temperature (a ``T`` axis)."""
        return self.table.needs_temperature


@dataclass(frozen=True, eq=False)
class FrictionMap(_TableLaw):
    """A friction law from a measured map: ``mu(p, v, T)``.

    Parameters
    ----------
    table
        A :class:`TableMap` of ``mu``.
    """

    _quantity: ClassVar[str] = "mu"

    def mu_at(self, p, v, T=None) -> np.ndarray:
        """``mu`` per node (see :meth:`TableMap.evaluate`)."""
        return self.table.evaluate(p, v, T)


@dataclass(frozen=True, eq=False)
class WearMap(_TableLaw):
    """An Archard wear law from a measured map: ``dh/dt = k(p, v, T) p v``.

    The map's ``k`` is the specific wear rate measured at each ``p, v, T``, so
    the exponents are ``a = b = 1``.

    Parameters
    ----------
    table
        A :class:`TableMap` of ``k`` (m^2/N).
    """

    _quantity: ClassVar[str] = "k"
    a: ClassVar[float] = 1.0
    b: ClassVar[float] = 1.0

    def coefficient_at(self, p, v, T=None) -> np.ndarray:
        """``k`` per node (m^2/N, see :meth:`TableMap.evaluate`)."""
        return self.table.evaluate(p, v, T)

    def rate(self, p, v, T=None) -> np.ndarray:
        """Wear rate ``k p v`` per node (m/s)."""
        p, v, T, _ = node_inputs(p, v, T, MapError)
        return archard_rate(self, self.table.evaluate(p, v, T), p, v)


def _check_law(owner: str, name: str, value, lo: float, hi: float, unit: str = "",
               lo_open: bool = False, why: str = "") -> None:
    """Raise a :class:`LawError` naming ``owner.name`` unless ``lo <(=) value <= hi``."""
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and np.isfinite(value)
    if ok and (value > lo if lo_open else value >= lo) and value <= hi:
        return
    u = f" {unit}" if unit else ""
    rel = "<" if lo_open else "<="
    raise LawError(f"{owner}: {name} = {value!r}{u} is not allowed; need {lo:g}{u} {rel} "
                   f"{name} <= {hi:g}{u}" + (f" ({why})" if why else ""))


@dataclass(frozen=True)
class StribeckFriction:
    """Friction falling with sliding speed (Stribeck-type).

    ``mu(v) = mu_kinetic + (mu_static - mu_kinetic) exp(-(v / v_stribeck)^delta)``.

    ``mu(0) = mu_static``; far above ``v_stribeck``, ``mu_kinetic``.  ``delta``
    shapes the transition (2: Gaussian, 1: exponential).  A ``mu_static`` below
    ``mu_kinetic`` is allowed: friction rising with speed.

    Parameters
    ----------
    mu_kinetic, mu_static
        Friction coefficients at high and zero speed, 0..2.
    v_stribeck
        The speed of the transition (m/s), > 0.
    delta
        Exponent of the transition, 0 < delta <= 10.
    """

    mu_kinetic: float
    mu_static: float
    v_stribeck: float
    delta: float = 2.0
    needs_temperature: ClassVar[bool] = False

    def __post_init__(self):
        for name in ("mu_kinetic", "mu_static"):
            _check_law("StribeckFriction", name, getattr(self, name), *BOUNDS["mu"][:2],
                       why=BOUNDS["mu"][2])
        _check_law("StribeckFriction", "v_stribeck", self.v_stribeck, 0.0, BOUNDS["v"][1],
                   "m/s", lo_open=True)
        _check_law("StribeckFriction", "delta", self.delta, 0.0, 10.0, lo_open=True)

    def mu_at(self, p, v, T=None) -> np.ndarray:
        """``mu(v)`` per node (``p`` and ``T`` only set the shape)."""
        p, v, T, shape = node_inputs(p, v, T, LawError)
        w = np.exp(-(v / self.v_stribeck) ** self.delta)
        # weights, not mu_k + (mu_s - mu_k) w: both limits come out exactly
        return np.array(np.broadcast_to(self.mu_static * w + self.mu_kinetic * (1.0 - w), shape))


@dataclass(frozen=True)
class MildSevereWear:
    """Archard wear switching from a mild to a severe coefficient above a threshold.

    ``k = (1 - s) k_mild + s k_severe``, ``dh/dt = k p v``, with the switch
    ``s`` of ``x = p v`` (``on="pv"``, W/m^2: the frictional power per area
    for mu = 1) or ``x = T`` (``on="T"``, K):

    * ``width > 0``: logistic, ``s = 1 / (1 + exp(-(x - threshold) / width))``;
      ``k`` then rises smoothly over a few ``width`` about the threshold, and
      the implicit wear scheme, whose step sees ``d(rate)/dp``, does not meet a
      jump;
    * ``width = 0``: a sharp step, mild below and severe above.

    At ``x = threshold`` both give the mean ``(k_mild + k_severe) / 2``.

    Parameters
    ----------
    k_mild, k_severe
        The wear coefficients (m^2/N), ``0 < k_mild <= k_severe <= 1e-10``.
    threshold
        Where the switch is centred: W/m^2 (``on="pv"``) or K (``on="T"``,
        173.15 to 1473.15 K).
    on
        ``"pv"`` or ``"T"``.
    width
        The logistic's width in the threshold's unit, ``0 <= width <=
        threshold / 5`` (so that the mild side is mild: s(0) < 0.7 %);
        None (default): 5 % of the threshold.
    """

    k_mild: float
    k_severe: float
    threshold: float
    on: str = "pv"
    width: float | None = None
    a: ClassVar[float] = 1.0
    b: ClassVar[float] = 1.0

    def __post_init__(self):
        owner, why = "MildSevereWear", BOUNDS["k"][2]
        _check_law(owner, "k_mild", self.k_mild, 0.0, BOUNDS["k"][1], "m^2/N", True, why)
        _check_law(owner, "k_severe", self.k_severe, self.k_mild, BOUNDS["k"][1], "m^2/N",
                   why="a severe wear coefficient is at least the mild one")
        if self.on not in ("pv", "T"):
            raise LawError(f"{owner}: on = {self.on!r} is not allowed; allowed: 'pv', 'T'")
        if self.on == "T":
            _check_law(owner, "threshold", self.threshold, *BOUNDS["T"][:2], "K",
                       why=BOUNDS["T"][2])
        else:
            _check_law(owner, "threshold", self.threshold, 0.0, np.inf, "W/m^2", lo_open=True)
        if self.width is None:
            object.__setattr__(self, "width", 0.05 * float(self.threshold))
        _check_law(owner, "width", self.width, 0.0, self.threshold / 5,
                   "K" if self.on == "T" else "W/m^2",
                   why="a wider switch is not mild on the mild side")

    @property
    def needs_temperature(self) -> bool:
        """Whether the switch is on temperature (``on == "T"``)."""
        return self.on == "T"

    def severity(self, p, v, T=None) -> np.ndarray:
        """The switch ``s`` per node: 0 mild, 1 severe."""
        p, v, T, shape = node_inputs(p, v, T, LawError)
        if self.on == "T":
            if T is None:
                raise LawError("MildSevereWear(on='T') switches on temperature: give T (K)")
            x = T
        else:
            x = p * v
        d = np.broadcast_to(x, shape) - self.threshold
        s = np.heaviside(d, 0.5) if self.width == 0 else expit(d / self.width)
        return np.asarray(s, dtype=float)

    def coefficient_at(self, p, v, T=None) -> np.ndarray:
        """``k`` per node (m^2/N)."""
        s = self.severity(p, v, T)
        return self.k_mild * (1.0 - s) + self.k_severe * s      # exact at s = 0 and 1

    def rate(self, p, v, T=None) -> np.ndarray:
        """Wear rate ``k p v`` per node (m/s)."""
        p, v, T, _ = node_inputs(p, v, T, LawError)
        return archard_rate(self, self.coefficient_at(p, v, T), p, v)
