"""Elasticity in scikit-fem style: Lame parameters, Voigt strains and the bilinear and linear forms.

:func:`elasticity_form` is the readable reference form for an anisotropic
Voigt stiffness ``C`` (isotropic and transversely isotropic are special
cases); the fast assembly of :mod:`brakewear.fem.assembly` is tested
against it.  Extra data reaches the forms through ``w``.
"""
from __future__ import annotations

import logging
from collections.abc import Sequence

import numpy as np
import skfem as fem
from skfem.helpers import dot, sym_grad

from ..errors import MeshError

logger = logging.getLogger(__name__)

__all__ = [
    "lame_parameters",
    "scalar_element",
    "voigt_strain",
    "elasticity_form",
    "thermal_strain_form",
    "traction_form",
    "pressure_form",
]


def lame_parameters(E: float, nu: float) -> tuple[float, float]:
    """Lamé's lambda and mu from Young's modulus and Poisson's ratio."""
    return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))


def scalar_element(mesh: fem.Mesh) -> fem.Element:
    """The scalar Lagrange element matching a tetrahedral mesh's order."""
    if isinstance(mesh, fem.MeshTet2):
        return fem.ElementTetP2()
    if isinstance(mesh, fem.MeshTet1):
        return fem.ElementTetP1()
    raise MeshError(f"unsupported mesh type {type(mesh).__name__}; need MeshTet or MeshTet2")


def _intorder(elem: fem.Element) -> int:
    # P1: the integrand is constant, one point is exact.  P2 meshes here are
    # isoparametric (curved), where the integrand is rational: degree 4 makes
    # the quadrature error negligible against the discretisation error.
    return 1 if elem.maxdeg == 1 else 2 * elem.maxdeg


def voigt_strain(u) -> list:
    """Strain of a skfem vector field in Voigt order, engineering shear."""
    e = sym_grad(u)
    return [e[0, 0], e[1, 1], e[2, 2], 2 * e[1, 2], 2 * e[0, 2], 2 * e[0, 1]]


def elasticity_form(C: np.ndarray) -> fem.BilinearForm:
    """``BilinearForm`` of ``eps(u) : C : eps(v)`` for a 6x6 Voigt stiffness ``C``."""
    C = np.asarray(C, dtype=float)

    @fem.BilinearForm
    def form(u, v, w):
        eu, ev = voigt_strain(u), voigt_strain(v)
        return sum(C[i, j] * eu[j] * ev[i] for i in range(6) for j in range(6) if C[i, j] != 0.0)

    return form


def thermal_strain_form(C: np.ndarray, alpha: float) -> fem.LinearForm:
    """Load of a thermal strain ``alpha dT I``; ``dT`` arrives as ``w['dT']``.

    ``int eps(v) : C : (alpha dT I)``; with this load a free body under a
    uniform ``dT`` expands stress-free.
    """
    s = np.asarray(C, dtype=float) @ np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0]) * alpha

    @fem.LinearForm
    def form(v, w):
        ev = voigt_strain(v)
        return w["dT"] * sum(s[i] * ev[i] for i in range(6) if s[i] != 0.0)

    return form


def traction_form(t: Sequence[float]) -> fem.LinearForm:
    """Facet ``LinearForm`` of a constant traction vector ``t`` (Pa)."""
    tv = np.asarray(t, dtype=float)

    @fem.LinearForm
    def form(v, w):
        return tv[0] * v[0] + tv[1] * v[1] + tv[2] * v[2]

    return form


def pressure_form(p: float) -> fem.LinearForm:
    """Facet ``LinearForm`` of a pressure ``p`` (Pa) acting against the outward normal."""

    @fem.LinearForm
    def form(v, w):
        return -p * dot(w.n, v)

    return form


# Voigt index of the strain component (k, l): 0 xx, 1 yy, 2 zz, 3 yz, 4 xz, 5 xy
_VOIGT = np.array([[0, 5, 4], [5, 1, 3], [4, 3, 2]])
