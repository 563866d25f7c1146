"""Friction and wear laws: what a surface does under pressure, speed and temperature.

:class:`WearLaw` -- the generalised Archard law ``dh/dt = k(T) p^a v^b``
(``a = b = 1``: Archard, ``k`` in 1/Pa = m^2/N), with an Arrhenius rise of
``k`` above a threshold temperature (Liu and Rhee).  :class:`FrictionLaw` --
``mu(T)``, a linear fade above a reference temperature.

Both also answer the per-node calls of the wear loop that every friction
and wear law of brakewear answers (:mod:`brakewear.maps` has the tables and
the other closed forms): ``mu_at(p, v, T)``, ``coefficient_at(p, v, T)`` and
``rate(p, v, T)``, each an array over the nodes (:func:`node_inputs` checks
and broadcasts the nodes' pressure, sliding speed and temperature), and
``needs_temperature``.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from .errors import ThermalError, WearError
from .materials import T_AMBIENT_DEFAULT

logger = logging.getLogger(__name__)

__all__ = ["WearLaw", "FrictionLaw", "node_inputs", "friction_flux", "friction_power"]


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
        return self.coefficient_at(p, v, T) * np.clip(p, 0.0, None) ** self.a * v ** self.b

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
    """
    return float(friction_flux(p, v, mu) @ np.asarray(area, dtype=float))
