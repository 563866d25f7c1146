"""Wear laws and the distribution of wear on pad and rotor.

Generalised Archard law: ``dh/dt = k(T) p^a v^b`` (``a = b = 1``: Archard,
``k`` in 1/Pa = m^2/N).  The pad wears pointwise at its friction-face nodes.
A rotor point at radius ``r`` passes under the pad once per revolution, so the
rotor wears by the circumferential mean: the worn volume that the pad
removes per unit time at radius ``r`` is spread over the whole ring of rotor
nodes at that radius.  Both distributions conserve volume exactly: the volume
rate of a surface equals ``sum_s k p_s v_s A_s`` over the pad's contact nodes.

This module is the ground floor of the wear loop (``simulate.py``, next): it
holds the laws and the per-step distribution, not the time stepping.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

logger = logging.getLogger(__name__)

__all__ = ["WearError", "WearLaw", "pad_wear_rate", "rotor_rings", "rotor_wear_rate"]

#: Universal gas constant (J/mol K) for the Arrhenius temperature law.
R_GAS = 8.314462618


class WearError(ValueError):
    """Invalid wear input (names the parameter, the value and what is allowed)."""


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
        return self.coefficient(T) * np.clip(p, 0.0, None) ** self.a * v ** self.b


def pad_wear_rate(law: WearLaw, p: np.ndarray, v: np.ndarray, T=None) -> np.ndarray:
    """Pad wear rate at each friction-face node (m/s): the law, pointwise."""
    return law.rate(p, v, T)


def rotor_rings(r_nodes: np.ndarray, tol: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Group rotor friction-face nodes into rings of equal radius.

    Returns ``ring`` (index per node) and the ring radii.  Nodes whose radii
    differ by less than ``tol`` (default 1e-9 of the largest radius) share a
    ring; the rotor meshes of brakewear are structured in r, so every ring is
    a full circle of nodes.
    """
    r = np.asarray(r_nodes, dtype=float)
    tol = 1e-9 * r.max() if tol is None else tol
    order = np.argsort(r)
    new = np.concatenate([[True], np.diff(r[order]) > tol])
    ring_sorted = np.cumsum(new) - 1
    ring = np.empty(r.size, dtype=np.int64)
    ring[order] = ring_sorted
    radii = np.bincount(ring, weights=r) / np.bincount(ring)
    return ring, radii


def rotor_wear_rate(volume_rate: np.ndarray, coupling: sp.spmatrix, ring: np.ndarray,
                    area: np.ndarray) -> np.ndarray:
    """Revolution-averaged rotor wear rate at each rotor friction-face node (m/s).

    Parameters
    ----------
    volume_rate
        (n_slave,) volume the pad removes from the rotor per unit time at each
        pad contact node (``k_rotor p v A``, m^3/s).
    coupling
        (n_slave, n_rotor) which rotor nodes lie under each pad node (rows sum
        to one: a contact pair's coupling restricted to the rotor's face nodes).
    ring, area
        Ring index and tributary area of each rotor face node (:func:`rotor_rings`,
        :func:`brakewear.contact.tributary_areas`).

    The volume each pad node takes from the rotor nodes under it is summed
    per ring and spread uniformly (by area) over the whole ring: the rotor
    passes under the pad once per revolution.  The rotor's volume rate equals
    ``volume_rate.sum()`` exactly.
    """
    per_node = sp.csr_matrix(coupling).T @ np.asarray(volume_rate, dtype=float)
    n_ring = int(ring.max()) + 1
    ring_volume = np.bincount(ring, weights=per_node, minlength=n_ring)
    ring_area = np.bincount(ring, weights=area, minlength=n_ring)
    if np.any((ring_volume > 0) & (ring_area <= 0)):
        raise WearError("a rotor ring receives wear but has no area")
    return (ring_volume / np.where(ring_area > 0, ring_area, 1.0))[ring]
