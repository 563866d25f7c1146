"""How frictional heat ``q = mu p v`` is shared between pad and rotor."""
from __future__ import annotations

import logging

import numpy as np

from ..errors import ThermalError
from ..fem.heat import check_thermal
from ..laws.base import friction_flux

logger = logging.getLogger(__name__)

__all__ = ["partition_effusivity", "heat_flux"]




def partition_effusivity(mat_pad, mat_rotor, area_ratio: float | None = None) -> float:
    """Share of the frictional heat that enters the pad.

    ``e = sqrt(kappa rho c)`` (effusivity).  Two half-spaces heated through
    a common face from the same instant have surface temperatures
    ``2 q_i sqrt(t) / (sqrt(pi) e_i)``; equal temperatures on both sides
    give ``q_pad / e_pad = q_rotor / e_rotor``, so::

        fraction_pad = e_pad / (e_pad + e_rotor)            (area_ratio None)

    With ``area_ratio = A_pad / A_swept`` (pad face over the ring it sweeps)
    the rotor's flux is first averaged over a revolution (its mean density
    is ``q_rotor A_pad / A_swept``) and the *mean* surface temperatures are
    matched::

        fraction_pad = e_pad A_pad / (e_pad A_pad + e_rotor A_swept)

    Parameters
    ----------
    mat_pad, mat_rotor
        :class:`~brakewear.materials.Material` or :class:`~brakewear.materials.Thermal`.
    area_ratio
        ``A_pad / A_swept`` in (0, 1], or None.
    """
    e_p = check_thermal(mat_pad, "pad").effusivity
    e_r = check_thermal(mat_rotor, "rotor").effusivity
    if area_ratio is None:
        return e_p / (e_p + e_r)
    if not (np.isfinite(area_ratio) and 0.0 < area_ratio <= 1.0):
        raise ThermalError(f"area_ratio = {area_ratio!r} is not allowed; it must lie in (0, 1]")
    return e_p * area_ratio / (e_p * area_ratio + e_r)


def heat_flux(p: np.ndarray, v: np.ndarray, mu) -> np.ndarray:
    """Frictional heat flux ``q = mu p v`` (W/m^2) at the contact nodes
    (:func:`brakewear.laws.base.friction_flux`, with its inputs checked).

    ``p`` (Pa; tension counts as zero), ``v`` sliding speed (m/s, >= 0),
    ``mu`` a number or an array per node (e.g. :meth:`FrictionLaw.mu` of the
    face temperature).
    """
    p = np.asarray(p, dtype=float)
    v = np.asarray(v, dtype=float)
    mu = np.asarray(mu, dtype=float)
    if np.any(v < 0) or not np.all(np.isfinite(v)):
        raise ThermalError(f"sliding speed min {v.min()!r} m/s is not allowed; need finite v >= 0")
    if np.any(mu < 0) or not np.all(np.isfinite(mu)):
        raise ThermalError(f"friction coefficient min {mu.min()!r} is not allowed; need mu >= 0")
    return friction_flux(p, v, mu)

