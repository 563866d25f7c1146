"""The elastic foundation (Winkler bed and brush) on the half-space's grid.

Each pixel is an independent spring: under a rigid indenter of initial
separation ``g0`` and approach ``delta``::

    p = K max(delta - g0, 0)          (normal, K in Pa/m)
    q = k_t u                         (tangential brush on the contact, k_t in Pa/m)

so the load is ``F(delta) = K A_pixel sum max(delta - g0, 0)``, the normal
tangent stiffness ``dF/d delta = K A_c`` and the tangential stiffness
``k_t A_c`` (``A_c`` the contact area).  No pixel feels another: this is
what makes the model fast, and what it gets wrong.

Calibrated as the thesis calibrates it (Soderberg and Bjorklund 2008), on
the smooth case: ``K`` gives Hertz's contact radius at Hertz's load,
``K = 16 E* / (3 pi a)`` (:func:`brakewear.analytic.winkler_hertz_match`),
and ``k_t`` gives Mindlin's tangential stiffness of that circle,
``k_t = 4 E* (1 - nu) / ((2 - nu) pi a)``
(:func:`brakewear.analytic.brush_hertz_modulus`).
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np

from ..analytic import brush_hertz_modulus, winkler_hertz_match
from ..errors import FoundationSolveError, RoughnessError
from .topography import _positive

logger = logging.getLogger(__name__)

__all__ = ["FoundationBed", "FoundationContact", "hertz_calibrated_bed"]


@dataclass(frozen=True)
class FoundationContact:
    """A solved bed: ``pressure`` (Pa per pixel), ``approach`` (m), ``load`` (N),
    ``contact`` (bool per pixel), ``normal_stiffness`` and ``tangential_stiffness``
    (N/m), ``iterations`` and ``seconds``."""

    pressure: np.ndarray
    approach: float
    load: float
    contact: np.ndarray
    pixel_area: float
    normal_stiffness: float
    tangential_stiffness: float
    iterations: int
    seconds: float

    @property
    def area(self) -> float:
        return float(self.contact.sum()) * self.pixel_area


@dataclass(frozen=True)
class FoundationBed:
    """A Winkler bed of modulus ``modulus`` (Pa/m) with a brush of ``brush`` (Pa/m).

    Parameters
    ----------
    modulus
        Normal foundation modulus ``K`` (Pa/m).
    brush
        Tangential modulus ``k_t`` (Pa/m).
    """

    modulus: float
    brush: float

    def __post_init__(self):
        object.__setattr__(self, "modulus", _positive("modulus", self.modulus, "Pa/m"))
        object.__setattr__(self, "brush", _positive("brush", self.brush, "Pa/m"))

    def solve(self, gap, pixel_area: float, load: float) -> FoundationContact:
        """The bed under ``load`` (N) on the initial separation ``gap`` (m per pixel).

        The load is piecewise linear and convex in ``delta``; Newton's method
        from above (the approach that carries the load on the lowest pixel
        alone) decreases monotonically onto the exact root in a few steps,
        each one pass over the grid.
        """
        t0 = time.perf_counter()
        g = np.asarray(gap, dtype=float)
        A = _positive("pixel_area", pixel_area, "m^2")
        if g.ndim != 2 or not np.all(np.isfinite(g)):
            raise RoughnessError(f"gap must be a finite 2D grid; got shape {g.shape}")
        if not (np.isfinite(load) and load > 0):
            raise RoughnessError(f"load = {load!r} N is not allowed; need a force > 0")
        c = load / (self.modulus * A)          # sum of the interferences it needs (m)
        gf = g.ravel()
        delta = float(gf.min()) + c
        on = gf < delta
        n_on = int(np.count_nonzero(on))
        it = 0
        for it in range(1, 200):  # noqa: B007  (the count is reported)
            delta = (c + float(np.sum(gf, where=on))) / n_on
            on = gf < delta            # the set only shrinks: Newton from above
            n_new = int(np.count_nonzero(on))
            if n_new == n_on:          # the same set: delta is its exact root
                break
            n_on = n_new
        else:
            raise FoundationSolveError(f"foundation bed: Newton on the approach did not settle "
                                       f"in 200 steps (approach {delta:.6g} m, {n_on} pixels "
                                       "in contact)")
        over = np.clip(delta - g, 0.0, None)
        p = self.modulus * over
        contact = over > 0
        Ac = float(contact.sum()) * A
        res = FoundationContact(p, delta, float(p.sum() * A), contact, A, self.modulus * Ac,
                                self.brush * Ac, it, time.perf_counter() - t0)
        return res


def hertz_calibrated_bed(load: float, radius: float, modulus: float, poisson: float,
                         match: str = "radius") -> FoundationBed:
    """The bed calibrated on the smooth sphere (radius ``radius``, contact modulus
    ``modulus`` E*, Poisson's ratio ``poisson``) at ``load``.

    ``match = "radius"`` (the thesis's calibration): Hertz's contact radius at
    Hertz's load; ``"stiffness"``: Hertz's normal tangent stiffness
    (:func:`brakewear.analytic.winkler_hertz_match`).  The brush matches
    Mindlin's tangential stiffness on the bed's smooth contact area
    (:func:`brakewear.analytic.brush_hertz_modulus`).
    """
    if match not in ("radius", "stiffness"):
        raise RoughnessError(f"match = {match!r} is not allowed; allowed: 'radius', "
                             "'stiffness'")
    K = winkler_hertz_match(load, radius, modulus, match)["K"]
    return FoundationBed(K, brush_hertz_modulus(load, radius, modulus, poisson, match))
