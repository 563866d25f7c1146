"""Closed forms of the tribometer tests: partial slip (Cattaneo-Mindlin) and worn shapes.

Partial slip of two elastic bodies of one material (no coupling of normal and
tangential tractions) under a normal load ``P`` and a tangential load
``Q < mu P`` applied monotonically from zero (Johnson, Contact Mechanics,
section 7.1-7.2; docs/references.md):

* cylinder (plane strain, loads per unit length): the contact half-width ``a``
  is Hertz's, the stick zone ``|x| < c`` has ``c / a = sqrt(1 - Q / (mu P))``
  and the shear traction is ``q = mu p0 sqrt(1 - x^2/a^2) - mu p0 (c/a)
  sqrt(1 - x^2/c^2)`` (the second term in the stick zone only);
* sphere: ``c / a = (1 - Q / (mu P))^(1/3)`` and the tangential approach
  ``delta = 3 mu P K / (16 a) [1 - (1 - Q / (mu P))^(2/3)]`` with
  ``K = (2 - nu1)/G1 + (2 - nu2)/G2``.

In plane strain the displacement of a body relative to its remote points
grows without bound (the logarithm of the half-plane), so the 2D tangential
compliance is given here as what the slip adds to the full-stick one
(:func:`cattaneo_mindlin_cylinder_slip_compliance`), together with the slip
of the surfaces in the slip zone (:func:`cattaneo_mindlin_cylinder_slip`).

Worn shapes: a sphere pin on a flat that does not wear wears a flat cap whose
volume is Archard's ``k F s`` (:func:`spherical_cap_height`); a block worn
by a ring conforms to it, its scar a circular segment of area ``k F' s`` per
unit width (:func:`conforming_block_on_ring`).  All functions take and
return SI units.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import ContactError

__all__ = [
    "cattaneo_mindlin_cylinder",
    "cattaneo_mindlin_cylinder_traction",
    "cattaneo_mindlin_cylinder_slip",
    "cattaneo_mindlin_cylinder_slip_compliance",
    "cattaneo_mindlin_sphere",
    "cattaneo_mindlin_sphere_traction",
    "cattaneo_mindlin_sphere_displacement",
    "spherical_cap_volume",
    "spherical_cap_height",
    "circular_segment_area",
    "conforming_block_on_ring",
]


def _positive(where: str, **values) -> None:
    for name, v in values.items():
        if not (isinstance(v, (int, float, np.floating)) and math.isfinite(v) and v > 0):
            raise ContactError(f"{where}: {name} = {v!r} is not allowed; need a finite value > 0")


def _load_ratio(where: str, P: float, Q: float, mu: float) -> float:
    _positive(where, P=P, mu=mu)
    if not (math.isfinite(Q) and 0.0 <= Q < mu * P):
        raise ContactError(f"{where}: Q = {Q!r} is not allowed; partial slip needs "
                           f"0 <= Q < mu P = {mu * P:g} (at Q = mu P the whole contact slides)")
    return Q / (mu * P)


def cattaneo_mindlin_cylinder(P: float, Q: float, mu: float, R: float, Es: float) -> dict:
    """Cylinder on a flat (plane strain) under ``P`` and ``Q < mu P`` per unit length.

    Returns
    -------
    dict
        ``a`` (m), ``c`` (m, the stick zone's half-width), ``p0`` (Pa), ``q0 = mu p0``.

    Examples
    --------
    >>> r = cattaneo_mindlin_cylinder(P=1e5, Q=0.75 * 0.5 * 1e5, mu=0.5, R=0.01, Es=1e11)
    >>> round(r["c"] / r["a"], 12)
    0.5
    """
    ratio = _load_ratio("cattaneo_mindlin_cylinder", P, Q, mu)
    _positive("cattaneo_mindlin_cylinder", R=R, Es=Es)
    a = math.sqrt(4.0 * P * R / (math.pi * Es))
    p0 = 2.0 * P / (math.pi * a)
    return {"a": a, "c": a * math.sqrt(1.0 - ratio), "p0": p0, "q0": mu * p0}


def cattaneo_mindlin_cylinder_traction(x, P: float, Q: float, mu: float, R: float, Es: float):
    """Shear traction ``q(x)`` (Pa, along ``Q``) of the cylinder's partial slip.

    Its integral over the contact is ``Q``:

    >>> import numpy as np
    >>> x = np.linspace(-1.0, 1.0, 200001) * cattaneo_mindlin_cylinder(1e5, 0, .5, .01, 1e11)["a"]
    >>> q = cattaneo_mindlin_cylinder_traction(x, 1e5, 3e4, 0.5, 0.01, 1e11)
    >>> bool(abs(np.trapezoid(q, x) / 3e4 - 1.0) < 1e-4)
    True
    """
    r = cattaneo_mindlin_cylinder(P, Q, mu, R, Es)
    x = np.asarray(x, dtype=float)
    a, c, q0 = r["a"], r["c"], r["q0"]
    q = q0 * np.sqrt(np.clip(1.0 - (x / a) ** 2, 0.0, None))
    if c > 0:
        q = q - q0 * (c / a) * np.sqrt(np.clip(1.0 - (x / c) ** 2, 0.0, None))
    return q


def cattaneo_mindlin_cylinder_slip(x, P: float, Q: float, mu: float, R: float, Es: float):
    """Relative slip ``s(x)`` (m) of the surfaces of the cylinder's partial slip.

    Zero in the stick zone; in the slip zone ``c < |x| < a``::

        s = mu p0 / (a E*) [|x| sqrt(x^2 - c^2) - c^2 ln((|x| + sqrt(x^2 - c^2)) / c)]

    (the slope of the relative tangential displacement of two half-planes of
    one material under the shear traction is ``2 / (pi E*)`` times its Hilbert
    transform).  Outside the contact the value at ``|x| = a`` is returned: the
    slip the rim reached.
    """
    r = cattaneo_mindlin_cylinder(P, Q, mu, R, Es)
    a, c, p0 = r["a"], r["c"], r["p0"]
    ax = np.minimum(np.abs(np.asarray(x, dtype=float)), a)
    root = np.sqrt(np.clip(ax ** 2 - c ** 2, 0.0, None))
    with np.errstate(divide="ignore", invalid="ignore"):
        log = np.where(ax > c, np.log((ax + root) / c), 0.0) if c > 0 else 0.0
    s = mu * p0 / (a * Es) * (ax * root - c ** 2 * log)
    return np.where(ax > c, s, 0.0)


def cattaneo_mindlin_cylinder_slip_compliance(P: float, Q: float, mu: float, R: float,
                                              Es: float) -> float:
    """What partial slip adds to the tangential approach of the cylinder (m).

    The approach of the two bodies under ``Q`` minus their approach under the
    same ``Q`` when the whole contact sticks (shear traction ``Q / (pi sqrt(a^2 -
    x^2))``): finite in plane strain, where each approach by itself is not::

        d = 2 mu P / (pi E* a^2) [(a^2 - c^2) / 2 - c^2 ln(a / c)]

    It rises from 0 at ``Q = 0`` to ``mu P / (pi E*)`` at gross slip:

    >>> import math
    >>> d = cattaneo_mindlin_cylinder_slip_compliance(1e5, 0.5 * 1e5 * (1 - 1e-12), 0.5,
    ...                                                0.01, 1e11)
    >>> round(d / (0.5 * 1e5 / (math.pi * 1e11)), 6)
    1.0
    """
    r = cattaneo_mindlin_cylinder(P, Q, mu, R, Es)
    a, c = r["a"], r["c"]
    log = c ** 2 * math.log(a / c) if c > 0 else 0.0
    return 2.0 * mu * P / (math.pi * Es * a ** 2) * ((a ** 2 - c ** 2) / 2.0 - log)


def cattaneo_mindlin_sphere(F: float, Q: float, mu: float, R: float, Es: float) -> dict:
    """Sphere on a flat under ``F`` and ``Q < mu F``: ``a``, ``c``, ``p0``, ``q0 = mu p0``.

    >>> r = cattaneo_mindlin_sphere(10.0, 0.875 * 5.0, 0.5, 0.005, 1e11)
    >>> round(r["c"] / r["a"], 12)
    0.5
    """
    ratio = _load_ratio("cattaneo_mindlin_sphere", F, Q, mu)
    _positive("cattaneo_mindlin_sphere", R=R, Es=Es)
    a = (3.0 * F * R / (4.0 * Es)) ** (1.0 / 3.0)
    p0 = 3.0 * F / (2.0 * math.pi * a ** 2)
    return {"a": a, "c": a * (1.0 - ratio) ** (1.0 / 3.0), "p0": p0, "q0": mu * p0}


def cattaneo_mindlin_sphere_traction(r, F: float, Q: float, mu: float, R: float, Es: float):
    """Shear traction ``q(r)`` (Pa, along ``Q``) of the sphere's partial slip; it
    integrates to ``Q`` over the contact."""
    s = cattaneo_mindlin_sphere(F, Q, mu, R, Es)
    r = np.asarray(r, dtype=float)
    a, c, q0 = s["a"], s["c"], s["q0"]
    q = q0 * np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None))
    if c > 0:
        q = q - q0 * (c / a) * np.sqrt(np.clip(1.0 - (r / c) ** 2, 0.0, None))
    return q


def cattaneo_mindlin_sphere_displacement(F: float, Q: float, mu: float, R: float,
                                         E1: float, nu1: float, E2: float, nu2: float) -> dict:
    """Tangential approach of a sphere and a flat under ``F`` and ``Q < mu F``.

    Mindlin's, with the normal-tangential coupling neglected (exact for two
    bodies of one material)::

        delta = 3 mu F K / (16 a) [1 - (1 - Q / (mu F))^(2/3)]
        K = (2 - nu1) / G1 + (2 - nu2) / G2

    Returns
    -------
    dict
        ``delta`` (m), ``stick`` (m, the approach ``Q K / (8 a)`` when the whole
        contact sticks), ``slip`` (``delta - stick``, what the slip adds), ``a``.

    Examples
    --------
    >>> d = cattaneo_mindlin_sphere_displacement(10.0, 1e-9, 0.5, 0.005, 2e11, .3, 2e11, .3)
    >>> round(d["delta"] / d["stick"], 6)
    1.0
    """
    Es = 1.0 / ((1.0 - nu1 ** 2) / E1 + (1.0 - nu2 ** 2) / E2)
    s = cattaneo_mindlin_sphere(F, Q, mu, R, Es)
    K = 2.0 * (1.0 + nu1) * (2.0 - nu1) / E1 + 2.0 * (1.0 + nu2) * (2.0 - nu2) / E2
    a = s["a"]
    delta = 3.0 * mu * F * K / (16.0 * a) * (1.0 - (1.0 - Q / (mu * F)) ** (2.0 / 3.0))
    stick = Q * K / (8.0 * a)
    return {"delta": delta, "stick": stick, "slip": delta - stick, "a": a}


def spherical_cap_volume(h, R: float):
    """Volume of a spherical cap of height ``h`` on a sphere of radius ``R``:
    ``pi h^2 (3 R - h) / 3``."""
    h = np.asarray(h, dtype=float)
    return np.pi * h ** 2 * (3.0 * R - h) / 3.0


def spherical_cap_height(V: float, R: float) -> dict:
    """The flat a sphere pin wears on a flat that does not wear: cap height and radius.

    ``V`` is the worn volume (Archard: ``k F s``).  The height solves
    ``pi h^2 (3 R - h) / 3 = V`` (the root in ``[0, R]``, by the cubic's
    trigonometric form); the flat's radius is ``sqrt(2 R h - h^2)``.

    Examples
    --------
    >>> c = spherical_cap_height(float(spherical_cap_volume(1e-4, 5e-3)), 5e-3)
    >>> round(c["h"] / 1e-4, 12), round(c["radius"] / (2 * 5e-3 * 1e-4 - 1e-8) ** 0.5, 12)
    (1.0, 1.0)
    """
    _positive("spherical_cap_height", R=R)
    if not (math.isfinite(V) and 0.0 <= V <= 2.0 * math.pi * R ** 3 / 3.0):
        raise ContactError(f"spherical_cap_height: V = {V!r} m^3 is not allowed; need 0 <= V "
                           f"<= the half sphere's {2 * math.pi * R ** 3 / 3:g} m^3")
    # u = 1 - h/R solves u^3 - 3u + 2 = 3V / (pi R^3); with u = 2 cos(phi) that is
    # cos(3 phi) = -t, and the root u in [0, 1] is the branch 3 phi in [pi, 3 pi / 2]
    t = 1.0 - 3.0 * V / (2.0 * math.pi * R ** 3)
    u = 2.0 * math.cos((2.0 * math.pi - math.acos(max(-1.0, min(1.0, -t)))) / 3.0)
    h = R * (1.0 - u) if V > 0 else 0.0
    for _ in range(2):                       # Newton polish to round-off
        if h <= 0:
            break
        h -= (float(spherical_cap_volume(h, R)) - V) / (math.pi * h * (2.0 * R - h))
    return {"h": h, "radius": math.sqrt(max(2.0 * R * h - h * h, 0.0)), "V": V}


def circular_segment_area(w, R: float):
    """Area of the circular segment of chord ``w`` on a circle of radius ``R``:
    ``R^2 asin(w / 2R) - (w / 2) sqrt(R^2 - w^2 / 4)`` (the block scar of ASTM G77)."""
    w = np.asarray(w, dtype=float)
    return R ** 2 * np.arcsin(w / (2.0 * R)) - 0.5 * w * np.sqrt(R ** 2 - w ** 2 / 4.0)


def conforming_block_on_ring(P: float, R: float, s: float, k_block: float,
                             k_ring: float = 0.0) -> dict:
    """A block worn into the ring that slides on it, both rigid (plane strain).

    The block's scar is the ring's circle: a segment of area ``k_block P s``
    per unit width (``P`` force per unit width, ``s`` the sliding distance).
    The ring wears uniformly around its circumference, ``k_ring P s / (2 pi R)``.
    A scar that keeps the ring's shape while the ring sinks into it at speed
    ``V`` wears at ``V cos(theta)`` along its normal, so Archard's law sets
    the pressure ``p(theta) = p0 cos(theta) - p1`` (``p1`` the ring's uniform
    wear, ``p0`` from the load).

    Returns
    -------
    dict
        ``width`` (m, the chord), ``depth`` (m), ``area`` (m^2), ``theta0``
        (rad, the scar's half-angle), ``p0``, ``p1`` (Pa), ``ring_depth`` (m).

    Examples
    --------
    >>> r = conforming_block_on_ring(P=1e4, R=0.0175, s=100.0, k_block=1e-14)
    >>> bool(abs(r["area"] / (1e-14 * 1e4 * 100.0) - 1.0) < 1e-9)
    True
    """
    _positive("conforming_block_on_ring", P=P, R=R, s=s, k_block=k_block)
    area = k_block * P * s
    if area >= math.pi * R ** 2 / 2.0:
        raise ContactError(f"conforming_block_on_ring: the scar area {area:g} m^2 passes the "
                           "ring's half section; the block would be worn past the ring's axis")
    lo, hi = 0.0, 2.0 * R
    for _ in range(200):                     # the segment's area grows with its chord
        mid = 0.5 * (lo + hi)
        if float(circular_segment_area(mid, R)) < area:
            lo = mid
        else:
            hi = mid
    w = 0.5 * (lo + hi)
    th0 = math.asin(w / (2.0 * R))
    p1 = k_ring * P / (2.0 * math.pi * R * k_block) if k_ring > 0 else 0.0
    # P = int (p0 cos - p1) cos R dtheta over +-th0
    p0 = (P / R + 2.0 * p1 * math.sin(th0)) / (th0 + math.sin(th0) * math.cos(th0))
    return {"width": w, "depth": R - math.sqrt(R * R - w * w / 4.0), "area": area,
            "theta0": th0, "p0": p0, "p1": p1, "ring_depth": k_ring * P * s / (2 * math.pi * R)}
