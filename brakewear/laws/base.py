"""Friction and wear laws: what a surface does under pressure, speed and temperature.

:class:`WearLaw` -- the generalised Archard law ``dh/dt = k(T) p^a v^b``
(``a = b = 1``: Archard, ``k`` in 1/Pa = m^2/N), with an Arrhenius rise of
``k`` above a threshold temperature (Liu and Rhee).  :class:`FrictionLaw` --
``mu(T)``, a linear fade above a reference temperature.

Both also answer the per-node calls of the wear loop that every friction
and wear law of brakewear answers (:mod:`brakewear.laws.maps` has the tables and
the other closed forms): ``mu_at(p, v, T)``, ``coefficient_at(p, v, T)`` and
``rate(p, v, T)``, each an array over the nodes (:func:`node_inputs` checks
and broadcasts the nodes' pressure, sliding speed and temperature), and
``needs_temperature``.  :class:`NodeFrictionLaw` and :class:`NodeWearLaw`
state these calls; a run checks its laws against them once, at its start
(:func:`check_wear_law`, :func:`friction_law`).  Every wear rate, the laws'
own and the wear loop's, is :func:`archard_rate` of the law's coefficient.

A scene's ``[wear.pad]`` / ``[wear.rotor]`` table gives the built-in law
(``k``, ``a``, ``b``, ... or a measured ``k_map``), or names a registered one
by ``model``, with that law's own keys (a class registered by
:func:`register_wear_law`).
"""
from __future__ import annotations

import logging
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..errors import LawError, ThermalError, WearError
from ..materials import T_AMBIENT_DEFAULT
from ..registry import Registry

logger = logging.getLogger(__name__)

__all__ = ["WearLaw", "FrictionLaw", "node_inputs", "friction_flux", "friction_power",
           "NodeFrictionLaw", "NodeWearLaw", "archard_rate", "archard_slope", "check_wear_law",
           "friction_law", "register_wear_law", "unregister_wear_law", "wear_law_model",
           "wear_law_options", "wear_law_names", "wear_law_keys"]


#: Universal gas constant (J/mol K) for the Arrhenius temperature law.
R_GAS = 8.314462618


def node_inputs(p, v, T=None, error: type[Exception] = WearError
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, tuple[int, ...]]:
    """The nodes' pressure, sliding speed and temperature as float arrays, checked.

    Parameters
    ----------
    p
        Contact pressure (Pa); tension (p < 0) counts as 0.
    v
        Sliding speed (m/s), >= 0 (a speed, not a velocity component).
    T
        Temperature (K), > 0, or None.
    error
        The error raised for a value that is not allowed.

    Returns
    -------
    p, v, T, shape
        ``p`` clipped at 0, ``v`` and ``T`` (None stays None) as arrays, and the
        nodes' shape: the three broadcast together.
    """
    p = np.clip(np.asarray(p, dtype=float), 0.0, None)
    v = np.asarray(v, dtype=float)
    if not np.isfinite(p).all():
        raise error(f"contact pressure {float(p[~np.isfinite(p)].flat[0])!r} Pa is not allowed; "
                    "need a finite pressure")
    if not (np.isfinite(v).all() and (v >= 0).all()):
        bad = float(v[~(np.isfinite(v) & (v >= 0))].flat[0])
        raise error(f"sliding speed {bad!r} m/s is not allowed; need a finite v >= 0 "
                    "(a speed, not a velocity component)")
    shapes = [p.shape, v.shape]
    if T is not None:
        T = np.asarray(T, dtype=float)
        if not (np.isfinite(T).all() and (T > 0).all()):
            bad = float(T[~(np.isfinite(T) & (T > 0))].flat[0])
            raise error(f"temperature {bad!r} K is not allowed; need a finite T > 0 K")
        shapes.append(T.shape)
    return p, v, T, np.broadcast_shapes(*shapes)


@runtime_checkable
class NodeFrictionLaw(Protocol):
    """What the wear loop asks of a friction law: ``mu`` per node."""

    needs_temperature: bool

    def mu_at(self, p, v, T=None) -> np.ndarray:
        """Friction coefficient at pressure ``p`` (Pa), speed ``v`` (m/s), ``T`` (K or None)."""


@runtime_checkable
class NodeWearLaw(Protocol):
    """What the wear loop asks of a wear law: ``k`` and ``dh/dt`` per node.

    ``dh/dt = k p^a v^b``: the loop takes ``k`` (:meth:`coefficient_at`) at the
    start of each step and the rate is :func:`archard_rate` of it, the same
    function the law's :meth:`rate` uses.
    """

    a: float
    b: float
    needs_temperature: bool

    def coefficient_at(self, p, v, T=None) -> np.ndarray:
        """Wear coefficient ``k`` per node (m^2/N for ``a = b = 1``)."""

    def rate(self, p, v, T=None) -> np.ndarray:
        """Wear rate ``dh/dt`` per node (m/s)."""


def archard_rate(law, k, p, v) -> np.ndarray:
    """The wear rate ``dh/dt = k p^a v^b`` (m/s) of ``law`` (its exponents ``a``,
    ``b``) with the coefficients ``k``, at pressure ``p`` (Pa; tension counts as
    0) and sliding speed ``v`` (m/s): the one rate of every wear law and of the
    wear loop.

    Examples
    --------
    Archard (``a = b = 1``): 1 MPa at 10 m/s with k = 5e-15 1/Pa wears 50 nm/s;
    tension wears nothing.

    >>> law = WearLaw(5e-15)
    >>> archard_rate(law, 5e-15, np.array([1e6, -1e6]), 10.0).tolist()
    [5e-08, 0.0]
    """
    return k * np.clip(p, 0.0, None) ** law.a * v ** law.b


def archard_slope(law, k, p, v) -> np.ndarray:
    """``d(rate)/dp`` of :func:`archard_rate` at ``p`` (for ``a = 1`` simply ``k v^b``)."""
    if law.a == 1.0:
        return k * 1.0 ** law.a * v ** law.b
    pp = np.maximum(p, 1e-300)
    return law.a * (k * pp ** law.a * v ** law.b) / pp


#: the members of a wear law the loop uses, in the order a missing one is named
_WEAR_MEMBERS = ("coefficient_at", "a", "b", "rate", "needs_temperature")


def check_wear_law(name: str, law, thermal) -> None:
    """A wear law the loop can evaluate per node (:class:`NodeWearLaw`), and its
    temperature: a law that needs one needs ``thermal``."""
    if not isinstance(law, NodeWearLaw):
        attr = next(m for m in _WEAR_MEMBERS if not hasattr(law, m))
        raise WearError(f"{name} = {law!r} is not a wear law (no {attr!r}); use "
                        "brakewear.WearLaw or a law of brakewear.laws.maps")
    if law.needs_temperature and thermal is None:
        # a WearLaw takes its base coefficient without a temperature; a map with a
        # temperature axis cannot: try it once, before anything is computed
        try:
            law.coefficient_at(np.full(1, 1e6), np.ones(1), None)
        except Exception as e:
            raise WearError(f"{name} ({type(law).__name__}) depends on temperature and has no "
                            "value without one; it needs thermal coupling (thermal="
                            f"ThermalModel, or thermal.enabled = true): {e}") from None


def friction_law(mu, thermal) -> tuple[object | None, float]:
    """``(law, mu0)`` of a run's ``mu``: a number (no law) or a friction law
    (:class:`NodeFrictionLaw`); a law that needs a temperature needs ``thermal``.
    ``mu0`` is a number for the first contact system (the law's values are set
    once the nodes' state is known)."""
    if hasattr(mu, "mu_at") and callable(mu.mu_at):
        if not isinstance(mu, NodeFrictionLaw):
            raise WearError(f"mu = {mu!r} is not a friction law (no 'needs_temperature'); "
                            "use brakewear.FrictionLaw or a law of brakewear.laws.maps")
        if mu.needs_temperature and thermal is None:
            raise WearError(f"the friction law {type(mu).__name__} depends on temperature; "
                            "it needs thermal coupling (thermal=ThermalModel, or "
                            "thermal.enabled = true in a scene)")
        return mu, 0.0
    try:
        ok = np.isfinite(mu) and mu >= 0
    except TypeError:
        ok = False
    if not ok:
        raise WearError(f"mu = {mu!r} is not allowed; need a friction coefficient >= 0 or a "
                        "friction law (brakewear.laws.base, brakewear.laws.maps)")
    return None, float(mu)


def _per_node(value, shape: tuple[int, ...]) -> np.ndarray:
    """``value`` (a number or an array) as a new float array of the nodes' shape."""
    return np.array(np.broadcast_to(np.asarray(value, dtype=float), shape))


@dataclass(frozen=True)
class WearLaw:
    """``dh/dt = k(T) p^a v^b``.

    Parameters
    ----------
    k
        Wear coefficient at or below ``T_threshold`` (1/Pa for a = b = 1).
    a, b
        Pressure and speed exponents (Rhee's law; 1, 1 is Archard).
    T_threshold, activation_energy
        Above ``T_threshold`` (K) the coefficient rises as
        ``k exp(E/R (1/T_threshold - 1/T))`` (Arrhenius, Liu and Rhee);
        ``activation_energy = 0`` (default) means no temperature dependence.

    Examples
    --------
    The rate is linear in ``p`` and ``v`` (Archard); above ``T_threshold`` the
    coefficient rises by the Arrhenius factor:

    >>> law = WearLaw(k=5e-15)
    >>> float(law.rate(2e6, 10.0)) == 2 * float(law.rate(1e6, 10.0)) == 1e-07
    True
    >>> hot = WearLaw(k=5e-15, activation_energy=50e3)
    >>> T1, T0 = 600.0, hot.T_threshold
    >>> ratio = float(hot.coefficient(T1)) / hot.k
    >>> bool(np.isclose(ratio, np.exp(50e3 / R_GAS * (1 / T0 - 1 / T1)), rtol=1e-14))
    True
    >>> float(hot.coefficient(300.0)) == hot.k                   # below the threshold
    True
    """

    k: float
    a: float = 1.0
    b: float = 1.0
    T_threshold: float = 503.15  # 230 C: resin-bonded pads wear faster above it
    activation_energy: float = 0.0  # J/mol

    def __post_init__(self):
        if not (np.isfinite(self.k) and self.k > 0):
            raise WearError(f"wear coefficient k = {self.k!r} is not allowed; need k > 0 (1/Pa)")
        for name in ("a", "b"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0):
                raise WearError(f"wear exponent {name} = {v!r} is not allowed; need {name} > 0")
        if not (np.isfinite(self.T_threshold) and self.T_threshold > 0):
            raise WearError(f"T_threshold = {self.T_threshold!r} K is not allowed; need > 0 K")
        if not (np.isfinite(self.activation_energy) and self.activation_energy >= 0):
            raise WearError(f"activation_energy = {self.activation_energy!r} J/mol; need >= 0")

    def coefficient(self, T=None) -> np.ndarray | float:
        """``k(T)``; ``T`` in kelvin (None: the base coefficient)."""
        if T is None or self.activation_energy == 0.0:
            return self.k
        T = np.asarray(T, dtype=float)
        if np.any(T <= 0):
            raise WearError(f"temperature {T.min()!r} K is not allowed; need T > 0 K")
        boost = np.exp(self.activation_energy / R_GAS
                       * (1.0 / self.T_threshold - 1.0 / np.maximum(T, self.T_threshold)))
        return self.k * boost

    def rate(self, p, v, T=None) -> np.ndarray:
        """Wear rate ``dh/dt`` (m/s) at pressure ``p`` (Pa, tension counts as 0) and
        sliding speed ``v`` (m/s, must be >= 0)."""
        p = np.asarray(p, dtype=float)
        v = np.asarray(v, dtype=float)
        if np.any(v < 0):
            raise WearError(f"sliding speed {v.min()!r} m/s is not allowed; need v >= 0 "
                            "(a speed, not a velocity component)")
        # through coefficient_at, which the wear loop reads: a law that changes k per
        # node changes both
        return archard_rate(self, self.coefficient_at(p, v, T), p, v)

    @property
    def needs_temperature(self) -> bool:
        """Whether ``k`` depends on the temperature (``activation_energy > 0``)."""
        return self.activation_energy > 0.0

    def coefficient_at(self, p, v, T=None) -> np.ndarray:
        """:meth:`coefficient` ``k(T)`` per node: an array of the shape of ``p, v, T``
        broadcast together (:func:`node_inputs`; ``p`` and ``v`` set only the shape)."""
        _, _, T, shape = node_inputs(p, v, T, WearError)
        return _per_node(self.coefficient(T), shape)


@dataclass(frozen=True)
class FrictionLaw:
    """Temperature-dependent friction (fade): ``mu(T) = max(mu_min, mu0 + slope (T - T_ref))``.

    ``slope = 0`` (default) is a constant ``mu0``.  A resin-bonded pad fades
    above a few hundred degrees C: a negative slope above ``T_ref`` models
    it to first order.

    Parameters
    ----------
    mu0
        The friction coefficient at ``T_ref``, >= 0.
    slope
        d mu / dT (1/K); negative: fade.
    T_ref
        The reference temperature (K).
    mu_min
        The least ``mu`` the fade reaches, >= 0.

    Examples
    --------
    >>> fade = FrictionLaw(0.4, slope=-1e-3, T_ref=300.0, mu_min=0.25)
    >>> [round(float(fade.mu(T)), 12) for T in (300.0, 400.0, 600.0)]
    [0.4, 0.3, 0.25]
    """

    mu0: float
    slope: float = 0.0       # 1/K
    T_ref: float = T_AMBIENT_DEFAULT
    mu_min: float = 0.0

    def __post_init__(self):
        for key in ("mu0", "mu_min"):
            v = getattr(self, key)
            if not (np.isfinite(v) and v >= 0):
                raise ThermalError(f"FrictionLaw: {key} = {v!r} is not allowed; need >= 0")
        if not np.isfinite(self.slope):
            raise ThermalError(f"FrictionLaw: slope = {self.slope!r} is not allowed; need finite")

    def mu(self, T=None):
        """``mu`` at temperature ``T`` (K; None: ``mu0``)."""
        if T is None or self.slope == 0.0:
            return self.mu0
        return np.maximum(self.mu_min, self.mu0 + self.slope * (np.asarray(T, float) - self.T_ref))

    @property
    def needs_temperature(self) -> bool:
        """Whether ``mu`` depends on the temperature (``slope != 0``)."""
        return self.slope != 0.0

    def mu_at(self, p, v, T=None) -> np.ndarray:
        """:meth:`mu` ``mu(T)`` per node, like :meth:`WearLaw.coefficient_at`."""
        _, _, T, shape = node_inputs(p, v, T, ThermalError)
        return _per_node(self.mu(T), shape)


def friction_flux(p: np.ndarray, v: np.ndarray, mu) -> np.ndarray:
    """Frictional power per area ``q = mu p v`` (W/m^2) at the contact nodes (``p`` in
    Pa, tension counting as zero; ``v`` the sliding speed, m/s; ``mu`` a number or one
    per node)."""
    return np.asarray(mu, dtype=float) * np.clip(np.asarray(p, dtype=float), 0.0, None) \
        * np.asarray(v, dtype=float)


def friction_power(p: np.ndarray, v: np.ndarray, mu, area: np.ndarray) -> float:
    """Frictional power of a face (W): :func:`friction_flux` times the nodes' areas.

    The one definition of friction work in brakewear: a wear step's is this
    power at its start pressure and its mean speed times its length (the
    ``friction_work`` of a :class:`~brakewear.wear.WearStep`, and the heat the
    thermal model takes in over the step, whose flux is :func:`friction_flux`);
    an application's is the sum of its steps'.

    Examples
    --------
    Two nodes of 1 cm^2 at 1 MPa, sliding at 10 m/s with mu = 0.4: 800 W.

    >>> round(friction_power(np.array([1e6, 1e6]), np.array([10.0, 10.0]), 0.4,
    ...                      np.array([1e-4, 1e-4])), 9)
    800.0
    """
    return float(friction_flux(p, v, mu) @ np.asarray(area, dtype=float))


_WEAR_LAWS = Registry("wear law", "wear.pad.model", members=("build",), error=LawError)


def register_wear_law(part: type[Any], *, replace: bool = False) -> type[Any]:
    """Add the wear law ``part`` to those a scene names by ``model`` (a class decorator).

    The class declares itself: ``name`` (what ``[wear.pad] model`` says),
    ``keys`` (its own keys of the table, :class:`~brakewear.registry.OptionKey`)
    and the class method ``build(options, material)``, which returns the law (a
    :class:`NodeWearLaw`) of its checked keys (SI) and the worn surface's
    :class:`~brakewear.materials.Material` (its ``wear_k``).

    Parameters
    ----------
    part
        The law's class.
    replace
        Replace a law of the same name (otherwise refused).

    Returns
    -------
    type
        ``part``.

    Raises
    ------
    LawError
        Naming what the class lacks or declares wrongly.
    """
    return _WEAR_LAWS.register(part, replace=replace)


def unregister_wear_law(name: str) -> None:
    """Take the law ``name`` out of the table (registered for a while, by a test).

    Parameters
    ----------
    name
        A registered law's name.
    """
    _WEAR_LAWS.unregister(name)


def wear_law_model(name: str, key: str = "wear.pad.model") -> type[Any]:
    """The class registered as ``name``.

    Parameters
    ----------
    name
        What ``model`` says.
    key
        The scene key for the message (``"wear.rotor.model"``).

    Returns
    -------
    type
        The law's class.

    Raises
    ------
    SceneError
        Naming ``key`` and the registered names if there is none.
    """
    return _WEAR_LAWS.get(name, key)


def wear_law_options(cls: type[Any], given: Mapping[str, Any], table: str) -> dict[str, Any]:
    """``given`` (the law's keys of ``table``, e.g. ``"wear.pad"``) checked, with the
    defaults of the others.

    Parameters
    ----------
    cls
        A registered law's class.
    given
        Key -> value (SI).
    table
        The scene table.

    Returns
    -------
    dict
        Every key of the law -> its value.
    """
    return _WEAR_LAWS.options(cls, given, table, f"{table}.model = {cls.name!r}")


def wear_law_names() -> tuple[str, ...]:
    """The registered wear laws' names.

    Returns
    -------
    tuple of str
        In the order of registration.
    """
    return _WEAR_LAWS.names()


def wear_law_keys() -> dict[str, str]:
    """Every registered law's keys and how the scene reader reads each.

    Returns
    -------
    dict
        Key -> kind (:class:`~brakewear.registry.OptionKey`).
    """
    return _WEAR_LAWS.key_kinds()
