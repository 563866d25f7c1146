"""Closed forms of elastic contact: the contact modulus, Lamé's thick cylinder, Hertz's
sphere and cylinder, the flat punch, the elastic foundation (Winkler) against Hertz,
Mindlin's tangential stiffness.

All functions take and return SI units and accept NumPy arrays where a
coordinate is an argument.
"""
from __future__ import annotations

import numpy as np

from ..errors import FoundationError

__all__ = [
    "effective_modulus",
    "thick_cylinder_coefficients",
    "thick_cylinder_stress",
    "thick_cylinder_displacement",
    "hertz_sphere",
    "hertz_sphere_pressure",
    "hertz_cylinder",
    "flat_punch_pressure",
    "flat_punch_settlement",
    "johnson_modulus",
    "winkler_sphere",
    "winkler_sphere_approach",
    "winkler_sphere_pressure",
    "hertz_sphere_stiffness",
    "winkler_hertz_match",
    "mindlin_tangential_stiffness",
    "brush_hertz_modulus",
]


def effective_modulus(E1: float, nu1: float, E2: float = np.inf, nu2: float = 0.0) -> float:
    """Contact modulus ``E*``: 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (E2 = inf: rigid).

    Examples
    --------
    Two equal bodies give half the plane-strain modulus ``E / (1 - nu^2)``:

    >>> round(effective_modulus(210e9, 0.3, 210e9, 0.3) / (210e9 / (2 * (1 - 0.09))), 12)
    1.0
    """
    inv = (1.0 - nu1 ** 2) / E1 + (0.0 if np.isinf(E2) else (1.0 - nu2 ** 2) / E2)
    return 1.0 / inv


def thick_cylinder_coefficients(a: float, b: float, p_i: float) -> tuple[float, float]:
    """Lamé coefficients ``A, B`` of a thick cylinder a < r < b under internal pressure.

    Examples
    --------
    The radial stress is the pressure at the bore and zero at the rim:

    >>> s_r, s_t = thick_cylinder_stress(np.array([0.05, 0.1]), 0.05, 0.1, 1e6)
    >>> (s_r / 1e6).round(12).tolist()
    [-1.0, 0.0]
    """
    A = p_i * a ** 2 / (b ** 2 - a ** 2)
    B = p_i * a ** 2 * b ** 2 / (b ** 2 - a ** 2)
    return A, B


def thick_cylinder_stress(r, a: float, b: float, p_i: float):
    """(sigma_r, sigma_theta) at radius ``r``."""
    A, B = thick_cylinder_coefficients(a, b, p_i)
    r = np.asarray(r, dtype=float)
    return A - B / r ** 2, A + B / r ** 2


def thick_cylinder_displacement(r, a: float, b: float, p_i: float, E: float, nu: float):
    """Radial displacement ``u_r(r)`` in plane strain."""
    A, B = thick_cylinder_coefficients(a, b, p_i)
    r = np.asarray(r, dtype=float)
    return (1.0 + nu) / E * ((1.0 - 2.0 * nu) * A * r + B / r)


def hertz_sphere(F: float, R: float, Es: float) -> dict:
    """Sphere of radius ``R`` on a flat under force ``F``.

    Returns the contact radius ``a``, the peak pressure ``p0`` and the approach
    ``delta``.

    Examples
    --------
    The approach gives the force back, ``F = (4/3) E* sqrt(R) delta^(3/2)``:

    >>> h = hertz_sphere(100.0, 0.01, 100e9)
    >>> round(float(4 / 3 * 100e9 * np.sqrt(0.01) * h["delta"] ** 1.5), 9)
    100.0
    """
    a = (3.0 * F * R / (4.0 * Es)) ** (1.0 / 3.0)
    return {"a": a, "p0": 3.0 * F / (2.0 * np.pi * a ** 2), "delta": a ** 2 / R}


def hertz_sphere_pressure(r, F: float, R: float, Es: float):
    """Hertz pressure p(r) = p0 sqrt(1 - r^2/a^2), zero outside the contact."""
    h = hertz_sphere(F, R, Es)
    r = np.asarray(r, dtype=float)
    return h["p0"] * np.sqrt(np.clip(1.0 - (r / h["a"]) ** 2, 0.0, None))


def hertz_cylinder(P: float, R: float, Es: float) -> dict:
    """Cylinder on a flat, force per unit length ``P`` (plane strain): half-width, peak.

    Examples
    --------
    The elliptical pressure carries the load, ``pi a p0 / 2 = P``:

    >>> h = hertz_cylinder(1e4, 0.01, 100e9)
    >>> round(float(np.pi * h["a"] * h["p0"] / 2), 6)
    10000.0
    """
    a = np.sqrt(4.0 * P * R / (np.pi * Es))
    return {"a": a, "p0": 2.0 * P / (np.pi * a)}


def flat_punch_pressure(r, F: float, a: float):
    """Rigid flat circular punch: p(r) = F / (2 pi a sqrt(a^2 - r^2)), r < a."""
    r = np.asarray(r, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(r < a, F / (2.0 * np.pi * a * np.sqrt(a ** 2 - r ** 2)), 0.0)


def flat_punch_settlement(F: float, a: float, Es: float) -> float:
    """Settlement of a rigid flat punch: delta = F / (2 a E*).

    Examples
    --------
    >>> flat_punch_settlement(1000.0, 0.005, 100e9)      # m
    1e-06
    """
    return F / (2.0 * a * Es)


def johnson_modulus(E: float, nu: float, thickness: float, constrained: bool = True) -> float:
    """Foundation modulus ``k`` (Pa/m) of a thin elastic layer on a rigid base.

    Johnson, Contact Mechanics, ch. 9: ``k = E (1 - nu) / ((1 + nu)(1 - 2 nu) h)``
    for a layer whose lateral expansion is prevented (thin, bonded layer), and
    ``k = E / h`` for one that is free to expand.

    Parameters
    ----------
    E, nu
        The layer's Young's modulus (Pa) and Poisson's ratio.
    thickness
        The layer's thickness (m).
    constrained
        Whether its lateral expansion is prevented.

    Returns
    -------
    float
        ``k`` (Pa/m).

    Raises
    ------
    FoundationError
        If ``E`` or ``thickness`` is not a finite positive number, or ``nu``
        is outside (-1, 0.5).

    Examples
    --------
    With ``nu = 0`` the constraint changes nothing; at ``nu = 0.25`` it stiffens by 1.2:

    >>> johnson_modulus(1e9, 0.0, 0.01) == johnson_modulus(1e9, 0.0, 0.01, False) == 1e11
    True
    >>> round(johnson_modulus(1e9, 0.25, 0.01) / johnson_modulus(1e9, 0.25, 0.01, False), 12)
    1.2
    """
    for name, val in (("E", E), ("thickness", thickness)):
        if not (np.isfinite(val) and val > 0):
            raise FoundationError(
                f"johnson_modulus: {name} = {val!r} is not allowed; need a finite value > 0"
            )
    if not (-1.0 < nu < 0.5):
        raise FoundationError(f"johnson_modulus: nu = {nu!r} is not allowed; need -1 < nu < 0.5")
    if constrained:
        return E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu) * thickness)
    return E / thickness


def winkler_sphere(R: float, k: float, delta: float | None = None, F: float | None = None) -> dict:
    """Rigid sphere on a Winkler foundation, given the approach ``delta`` or the load ``F``.

    Returns ``a = sqrt(2 R delta)``, ``p0 = k delta``, ``delta`` and
    ``F = pi k R delta^2``.  Hertz at the same approach has ``a = sqrt(R delta)``:
    the foundation's contact is sqrt(2) times wider, because it has no
    lateral coupling to pull the surface down around the contact.
    """
    if (delta is None) == (F is None):
        raise FoundationError("winkler_sphere: give exactly one of delta and F")
    if delta is None:
        assert F is not None                # one of the two, checked above
        delta = winkler_sphere_approach(F, R, k)
    return {"a": np.sqrt(2.0 * R * delta), "p0": k * delta, "delta": delta,
            "F": np.pi * k * R * delta ** 2}


def winkler_sphere_approach(F: float, R: float, k: float) -> float:
    """Approach of a rigid sphere on a Winkler foundation: delta = sqrt(F / (pi k R))."""
    return float(np.sqrt(F / (np.pi * k * R)))


def winkler_sphere_pressure(r, R: float, k: float, delta: float):
    """p(r) = k (delta - r^2 / (2 R)) inside the contact, zero outside."""
    r = np.asarray(r, dtype=float)
    return k * np.clip(delta - r ** 2 / (2.0 * R), 0.0, None)


def hertz_sphere_stiffness(F: float, R: float, Es: float) -> float:
    """Tangent normal stiffness of the Hertz sphere, ``dF/d delta = 2 E* a`` (N/m).

    It is also the stiffness of a rigid flat punch of the contact radius (the
    incremental contact is that punch: Barber's theorem).
    """
    return 2.0 * Es * hertz_sphere(F, R, Es)["a"]


def winkler_hertz_match(F: float, R: float, Es: float, match: str = "radius") -> dict:
    """A Winkler bed calibrated on the Hertz sphere, and what it predicts.

    A bed ``p = K (delta - r^2 / (2 R))`` has ``a^2 = 2 R delta``,
    ``F = pi K R delta^2`` (:func:`winkler_sphere`) and the tangent stiffness
    ``dF/d delta = 2 pi K R delta``.  Against Hertz (:func:`hertz_sphere`,
    :func:`hertz_sphere_stiffness`) at the load ``F``:

    * ``match = "radius"`` (the thesis's calibration): Hertz's contact radius
      at Hertz's load, ``K = 16 E* / (3 pi a)``; then the bed's approach is
      ``delta_H / 2``, its stiffness ``8/3`` of Hertz's ``2 E* a`` and its peak
      pressure ``4/3`` of ``p0``;
    * ``match = "stiffness"``: Hertz's tangent stiffness at Hertz's load,
      ``K = 3 E* / (4 pi a)``; then the approach is ``4/3`` of Hertz's, the
      contact area ``8/3`` and the peak pressure ``1/2``.

    One modulus cannot match area, approach and stiffness at once.

    Returns
    -------
    dict
        ``K`` (Pa/m), ``a``, ``delta``, ``p0``, ``stiffness`` of the bed, the
        Hertz values under ``hertz`` and the ratios bed/Hertz under ``ratio``
        (``approach``, ``stiffness``, ``peak``, ``area``).
    """
    h = hertz_sphere(F, R, Es)
    if match == "radius":
        K = 16.0 * Es / (3.0 * np.pi * h["a"])
    elif match == "stiffness":
        K = 3.0 * Es / (4.0 * np.pi * h["a"])
    else:
        raise FoundationError(f"winkler_hertz_match: match = {match!r} is not allowed; allowed: "
                         "'radius', 'stiffness'")
    w = winkler_sphere(R, K, F=F)
    k_w = 2.0 * np.pi * K * R * w["delta"]
    k_h = hertz_sphere_stiffness(F, R, Es)
    return {"K": K, "a": w["a"], "delta": w["delta"], "p0": w["p0"], "stiffness": k_w,
            "hertz": {**h, "stiffness": k_h},
            "ratio": {"approach": w["delta"] / h["delta"], "stiffness": k_w / k_h,
                      "peak": w["p0"] / h["p0"], "area": (w["a"] / h["a"]) ** 2}}


def mindlin_tangential_stiffness(a: float, Es: float, nu: float) -> float:
    """Tangential stiffness of a stuck circular contact of radius ``a`` (N/m).

    Mindlin (1949); Johnson (1985), section 7.2: a rigid disc bonded to a
    half-space moves by ``Q (2 - nu) / (8 G a)`` under a force ``Q``, the
    normal-tangential coupling neglected (exact for ``nu = 0`` and for two
    bodies of one material).  With ``G = E* (1 - nu) / 2`` (one elastic body of
    ``E* = E / (1 - nu^2)``; also two equal bodies) that is::

        K_t = 8 G a / (2 - nu) = 4 a E* (1 - nu) / (2 - nu)

    against ``K_n = 2 E* a``: ``K_t / K_n = 2 (1 - nu) / (2 - nu)``.
    """
    if not (-1.0 < nu < 0.5):
        raise FoundationError(f"mindlin_tangential_stiffness: nu = {nu!r} is not allowed; need "
                         "-1 < nu < 0.5")
    return 4.0 * a * Es * (1.0 - nu) / (2.0 - nu)


def brush_hertz_modulus(F: float, R: float, Es: float, nu: float,
                        match: str = "radius") -> float:
    """Tangential (brush) modulus ``k_t`` (Pa/m) of a bed calibrated on the Hertz sphere.

    A brush ``q = k_t u`` over the bed's contact area ``A_w`` has the
    tangential stiffness ``k_t A_w``; set equal to Mindlin's stuck circle of
    Hertz's radius (:func:`mindlin_tangential_stiffness`)::

        k_t = 4 a E* (1 - nu) / ((2 - nu) A_w)

    ``A_w`` is the contact area of :func:`winkler_hertz_match` with the same
    ``match``: ``pi a^2`` for ``"radius"`` (then
    ``k_t = 4 E* (1 - nu) / ((2 - nu) pi a)``), ``8/3 pi a^2`` for ``"stiffness"``.
    Either brush reproduces the tangential stiffness of the smooth contact.
    """
    w = winkler_hertz_match(F, R, Es, match)
    return mindlin_tangential_stiffness(w["hertz"]["a"], Es, nu) / (np.pi * w["a"] ** 2)
