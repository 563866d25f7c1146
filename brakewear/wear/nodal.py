"""The friction and wear laws at the pad's friction nodes, step by step.

A law may depend on the pressure, the sliding speed and the temperature of
each node (:mod:`brakewear.laws.base`, :mod:`brakewear.laws.maps`).  The wear loop is
staggered in them as it is in the temperatures: each step takes the
coefficients of its start state (pressure, the step's mean speed, the
temperatures) and keeps them through the step,

    dh/dt = k_i p^a v_i^b,   k_i = k(p_i, v_i, T_i) at the start of the step,

so the implicit (backward Euler) step stays linear in the end pressure, and
a law without pressure dependence (:class:`~brakewear.laws.base.WearLaw`) gives
the same numbers as when it is called directly: both are
:func:`~brakewear.laws.base.archard_rate` of the law's coefficient.  The friction coefficient
per node ``mu_i = mu(p_i, v_i, T_i)`` goes into the friction operator of the
contact solve (one traction ``mu_i p_i`` per node) and into the heat flux.
"""
from __future__ import annotations

import logging

import numpy as np

from ..laws.base import archard_rate, archard_slope

logger = logging.getLogger(__name__)

__all__ = ["NodalLaws"]


class NodalLaws:
    """Per-node coefficients of the pad and rotor wear laws and of friction.

    :meth:`take` evaluates ``k`` of both laws at a state; the rates and their
    slopes then use those coefficients until the next :meth:`take`.
    """

    def __init__(self, pad_law, rotor_law, mu_law, mu0: float):
        self.pad_law, self.rotor_law, self.mu_law, self.mu0 = pad_law, rotor_law, mu_law, mu0
        self.k_pad = self.k_rot = None

    def take(self, p, v, T_pad, T_rot) -> None:
        """The wear coefficients at pressure ``p`` (Pa), speed ``v`` (m/s) and the
        face temperatures (K or None) of each pad node."""
        self.k_pad = self.pad_law.coefficient_at(p, v, T_pad)
        self.k_rot = (None if self.rotor_law is None
                      else self.rotor_law.coefficient_at(p, v, T_rot))

    def pad_rate(self, p, v) -> np.ndarray:
        """Pad wear rate (m/s) at pressure ``p``."""
        return archard_rate(self.pad_law, self.k_pad, p, v)

    def rotor_rate(self, p, v) -> np.ndarray:
        """Rotor wear rate (m/s) under each pad node at pressure ``p`` (0 without a law)."""
        if self.rotor_law is None:
            return np.zeros_like(np.asarray(p, dtype=float))
        return archard_rate(self.rotor_law, self.k_rot, p, v)

    def pad_slope(self, p, v) -> np.ndarray:
        return archard_slope(self.pad_law, self.k_pad, p, v)

    def rotor_slope(self, p, v) -> np.ndarray:
        if self.rotor_law is None:
            return np.zeros_like(np.asarray(p, dtype=float))
        return archard_slope(self.rotor_law, self.k_rot, p, v)

    def mu(self, p, v, T_pad):
        """The friction coefficient of a solve: the number, or the law's value at each
        pad node (pressure ``p``, speed ``v``, face temperature ``T_pad``)."""
        if self.mu_law is None:
            return self.mu0
        return np.asarray(self.mu_law.mu_at(p, v, T_pad), dtype=float) * np.ones_like(v)

    @staticmethod
    def effective(mu, p, area) -> float:
        """The friction force over the normal force, ``sum mu p A / sum p A``: the one
        number a per-node ``mu`` gives the brake's torque."""
        if np.ndim(mu) == 0:
            return float(mu)
        w = np.clip(p, 0.0, None) * area
        s = float(w.sum())
        return float((mu * w).sum() / s) if s > 0 else float(np.mean(mu))
