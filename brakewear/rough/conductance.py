"""Contact conductance of two rough faces, ``h_c(p)`` (:class:`RoughConductance`).

Heat crosses a static rough interface through its contact spots.  For
elastic half-spaces the conductance per nominal area is tied to the
interface's incremental normal stiffness ``k_n = dp / d delta`` (Pa/m) by
Barber's analogy (Barber 2003; :func:`brakewear.analytic.barber_conductance`)::

    h_c = kappa_s k_n / E*,     kappa_s = 2 kappa_1 kappa_2 / (kappa_1 + kappa_2)

so a law for ``k_n(p)`` is a law for ``h_c(p)``.  Two such laws:

* ``"halfspace"`` (default): the stiffness grows in proportion to the
  pressure, ``k_n = p / (gamma sigma)`` (the form of Persson's theory,
  which Pastewka et al. 2013 confirmed numerically away from finite-size
  effects), with ``gamma`` fitted to this package's own half-space solves on
  periodic self-affine surfaces (:func:`halfspace_conductance`; the fit, its
  spread over surfaces and seeds and the command that makes it are in
  docs/rough.md)::

      h_c = kappa_s p / (gamma sigma E*)

* ``"mikic"``: Mikic's (1974) elastic correlation
  (:func:`brakewear.analytic.mikic_elastic_conductance`), with the mean
  absolute profile slope ``m = Sdq / sqrt(pi)`` of an isotropic Gaussian surface.

Two rough faces in contact are one rough face on a flat of the composite
roughness: ``sigma = sqrt(sigma_pad^2 + sigma_rotor^2)``, ``Sdq =
sqrt(Sdq_pad^2 + Sdq_rotor^2)`` (independent surfaces), and the contact modulus
``E*`` of the pair.

What this leaves out: plasticity of the asperity tips, the third body (wear
debris and transfer film) that bridges the gaps of a sliding brake
interface, and the heat generated at the spots themselves.  It is a static
conductance: a lower bound for a run-in sliding interface.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ..analytic import barber_conductance, mikic_elastic_conductance
from ..errors import RoughnessError
from .halfspace import HalfSpace
from .normal import solve_normal
from .stiffness import contact_stiffness
from .topography import Topography, _positive

logger = logging.getLogger(__name__)

__all__ = ["RoughConductance", "halfspace_conductance", "HALFSPACE_FIT", "LAWS"]

#: Conductance laws of :class:`RoughConductance`.
LAWS = ("halfspace", "mikic")

#: ``k_n = p / (gamma sigma)``: ``gamma`` fitted to the half-space solves of
#: studies/rough_conductance.py over ``range`` of ``p / (E* Sdq)`` (real contact
#: of about 1 to 10 % of the nominal area).
HALFSPACE_FIT = {"gamma": 0.445, "range": (3e-3, 3e-2)}


@dataclass(frozen=True)
class RoughConductance:
    """``h_c(p)`` of a rough interface.

    Parameters
    ----------
    rms_height
        Composite rms height ``sigma`` (m).
    rms_slope
        Composite areal rms slope ``Sdq`` (the ``"mikic"`` law; None for ``"halfspace"``).
    modulus
        Contact modulus ``E*`` of the pair (Pa).
    kappa
        ``kappa_s = 2 kappa_1 kappa_2 / (kappa_1 + kappa_2)`` (W/m K).
    law
        ``"halfspace"`` or ``"mikic"``.
    """

    rms_height: float
    rms_slope: float | None
    modulus: float
    kappa: float
    law: str = "halfspace"

    def __post_init__(self):
        _positive("rms_height", self.rms_height)
        if self.rms_slope is None:
            if self.law == "mikic":
                raise RoughnessError("the 'mikic' law needs rms_slope (Sdq)")
        elif _positive("rms_slope", self.rms_slope, "(dimensionless)") > 2.0:
            raise RoughnessError(f"rms_slope = {self.rms_slope!r} is not allowed; the "
                                 "half-space theory needs small slopes (Sdq <= 2)")
        _positive("modulus", self.modulus, "Pa")
        _positive("kappa", self.kappa, "W/m K")
        if self.law not in LAWS:
            raise RoughnessError(f"law = {self.law!r} is not allowed; allowed: "
                                 f"{', '.join(LAWS)}")

    @classmethod
    def of_faces(cls, pad: tuple, rotor: tuple, modulus: float, kappa_pad: float,
                 kappa_rotor: float, law: str = "halfspace") -> RoughConductance:
        """From each face's ``(rms height (m), rms slope or None)`` and conductivity (W/m K)."""
        for name, k in (("kappa_pad", kappa_pad), ("kappa_rotor", kappa_rotor)):
            _positive(name, k, "W/m K")
        for name, face in (("pad", pad), ("rotor", rotor)):
            _positive(f"{name} rms height", face[0])
        sigma = float(np.hypot(pad[0], rotor[0]))
        slope = (None if pad[1] is None or rotor[1] is None
                 else float(np.hypot(pad[1], rotor[1])))
        return cls(sigma, slope, modulus,
                   2.0 * kappa_pad * kappa_rotor / (kappa_pad + kappa_rotor), law)

    def normal_stiffness(self, p):
        """Incremental normal stiffness per nominal area ``k_n(p)`` (Pa/m)."""
        p = np.asarray(p, dtype=float)
        if np.any(p < 0) or not np.all(np.isfinite(p)):
            raise RoughnessError(f"pressure min {np.min(p)!r} Pa is not allowed; need "
                                 "finite p >= 0")
        Es, s, m = self.modulus, self.rms_height, self.rms_slope
        if self.law == "mikic":
            h = mikic_elastic_conductance(p, Es, s, m / np.sqrt(np.pi), self.kappa)
            return h * Es / self.kappa
        return p / (HALFSPACE_FIT["gamma"] * s)

    def conductance(self, p):
        """Contact conductance ``h_c(p)`` (W/m^2 K) at the nominal pressure ``p`` (Pa)."""
        return barber_conductance(self.normal_stiffness(p), self.modulus, self.kappa)


def halfspace_conductance(topography: Topography, pressures, modulus: float,
                          kappa: float = 1.0, poisson: float = 0.3, tol: float = 1e-8,
                          workers: int = 1) -> dict:
    """Conductance of a periodic rough face on a flat from half-space solves.

    For each nominal pressure (Pa, increasing) it solves the normal contact
    (:func:`~brakewear.rough.solve_normal`, warm-started from the last) and the
    incremental stiffness of its contact set
    (:func:`~brakewear.rough.contact_stiffness`), ``k_n = K / A``, and
    ``h_c = kappa k_n / E*``.

    Returns
    -------
    dict
        Arrays ``p``, ``k_n`` (Pa/m), ``h_c`` (W/m^2 K), ``contact_fraction``
        and ``approach`` (m), and the surface's ``rms_height`` and ``rms_slope``.
    """
    if not topography.periodic:
        raise RoughnessError("halfspace_conductance needs a periodic topography (one period "
                             "of a nominally flat interface)")
    ps = np.asarray(pressures, dtype=float)
    if ps.ndim != 1 or np.any(ps <= 0) or np.any(np.diff(ps) <= 0):
        raise RoughnessError("pressures must be positive and increasing (Pa)")
    hs = HalfSpace(topography.shape, topography.pixel, modulus, poisson, periodic=True,
                   workers=workers)
    A = topography.size[0] * topography.size[1]
    g0 = -topography.heights
    out = {k: [] for k in ("p", "k_n", "h_c", "contact_fraction", "approach")}
    p_last = None
    for p in ps:
        res = solve_normal(hs, g0, load=p * A, tol=tol, p0=p_last)
        p_last = res.pressure
        k_n = contact_stiffness(hs, res.contact, "normal").stiffness / A
        for k, v in (("p", p), ("k_n", k_n), ("h_c", kappa * k_n / modulus),
                     ("contact_fraction", res.contact_fraction), ("approach", res.approach)):
            out[k].append(float(v))
    return {**{k: np.array(v) for k, v in out.items()},
            "rms_height": topography.rms_height(), "rms_slope": topography.rms_slope()}
