"""Closed-form reference solutions (docs/references.md), tested on their own.

All functions take and return SI units and accept NumPy arrays where a
coordinate is an argument.
"""
from __future__ import annotations

import numpy as np

from .errors import FoundationError, ThermalError

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
    "uniform_wear_pressure",
    "uniform_wear_torque",
    "uniform_pressure_effective_radius",
    "slab_temperature",
    "semi_infinite_surface_temperature",
    "semi_infinite_temperature",
    "inerfc",
    "stop_flux",
    "stop_heat",
    "stop_surface_temperature",
    "stop_temperature",
    "stop_peak_time",
    "stop_peak_temperature",
    "bulk_temperature_rise",
    "johnson_modulus",
    "winkler_sphere",
    "winkler_sphere_pressure",
    "winkler_sphere_approach",
    "hertz_sphere_stiffness",
    "winkler_hertz_match",
    "mindlin_tangential_stiffness",
    "brush_hertz_modulus",
    "mikic_elastic_conductance",
    "barber_conductance",
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


def uniform_wear_pressure(r, F: float, theta: float, ri: float, ro: float):
    """Steady uniform-wear pressure of an annular-sector pad: p = F / (theta (ro - ri) r).

    Examples
    --------
    ``p r`` is the same everywhere (every point wears at ``k p omega r``), and the
    pressure carries the force over the sector:

    >>> r = np.linspace(0.1, 0.15, 6)
    >>> p = uniform_wear_pressure(r, 2000.0, 1.0, 0.1, 0.15)
    >>> bool(np.allclose(p * r, p[0] * r[0], rtol=1e-14))
    True
    >>> from scipy.integrate import quad
    >>> round(quad(lambda s: uniform_wear_pressure(s, 2000.0, 1.0, 0.1, 0.15) * s, 0.1, 0.15)[0], 9)
    2000.0
    """
    return F / (theta * (ro - ri) * np.asarray(r, dtype=float))


def uniform_wear_torque(F: float, mu: float, ri: float, ro: float) -> float:
    """Braking torque per face under uniform wear: mu F (ro + ri) / 2.

    Examples
    --------
    >>> round(uniform_wear_torque(5000.0, 0.4, 0.1, 0.15), 12)      # N m
    250.0
    """
    return mu * F * (ro + ri) / 2.0


def uniform_pressure_effective_radius(ri: float, ro: float) -> float:
    """Effective friction radius under uniform pressure: (2/3)(ro^3 - ri^3)/(ro^2 - ri^2).

    Examples
    --------
    Above the mean radius of uniform wear, by ``(ro - ri)^2 / (6 (ro + ri))``:

    >>> r = uniform_pressure_effective_radius(0.1, 0.15)
    >>> bool(np.isclose(r, 0.125 + 0.05 ** 2 / (6 * 0.25), rtol=1e-14, atol=0))
    True
    """
    return 2.0 / 3.0 * (ro ** 3 - ri ** 3) / (ro ** 2 - ri ** 2)


def slab_temperature(x, q: float, L: float, kappa: float, T0: float = 0.0):
    """Steady slab, flux ``q`` into x = 0, T = T0 at x = L: T0 + q (L - x) / kappa."""
    return T0 + q * (L - np.asarray(x, dtype=float)) / kappa


def semi_infinite_surface_temperature(t, q: float, kappa: float, rho: float, c: float,
                                      T0: float = 0.0):
    """Surface temperature of a half-space under constant flux: T0 + 2 q sqrt(t / (pi kappa rho c)).

    Examples
    --------
    Four times the time, twice the rise:

    >>> T = semi_infinite_surface_temperature(np.array([1.0, 4.0]), 1e6, 50.0, 7200.0, 500.0)
    >>> round(float(T[1] / T[0]), 12)
    2.0
    """
    return T0 + 2.0 * q * np.sqrt(np.asarray(t, dtype=float) / (np.pi * kappa * rho * c))


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
            raise FoundationError(f"johnson_modulus: {name} = {val!r} is not allowed; need a finite "
                             "value > 0")
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


def mikic_elastic_conductance(p, Es: float, sigma: float, slope: float, kappa_s: float):
    """Contact conductance of rough surfaces in elastic contact (W/m^2 K), Mikic (1974)::

        h_c = 1.54 kappa_s (m / sigma) (sqrt(2) p / (E* m))^0.94

    ``p`` the nominal pressure (Pa), ``E*`` the contact modulus, ``sigma`` the
    combined rms height ``sqrt(sigma_1^2 + sigma_2^2)`` (m), ``m`` the
    combined mean absolute profile slope ``sqrt(m_1^2 + m_2^2)`` and
    ``kappa_s = 2 kappa_1 kappa_2 / (kappa_1 + kappa_2)`` (W/m K).  For an
    isotropic Gaussian surface of areal rms slope ``Sdq``, ``m = Sdq / sqrt(pi)``.
    A correlation of the Greenwood-Williamson kind, stated for
    ``1e-5 < p / E* m < 1e-2`` or so (a small real contact area).
    """
    p = np.asarray(p, dtype=float)
    return 1.54 * kappa_s * slope / sigma * (np.sqrt(2.0) * np.clip(p, 0.0, None)
                                             / (Es * slope)) ** 0.94


def barber_conductance(stiffness, Es: float, kappa_s: float):
    """Conductance of an elastic contact from its incremental normal stiffness, Barber (2003)::

        C = kappa_s (dF / d delta) / E*

    exact for half-spaces (the thermal and the incremental elastic problems are
    the same Dirichlet problem on the contact spots); ``kappa_s`` as in
    :func:`mikic_elastic_conductance`.  A stiffness per nominal area (Pa/m)
    gives a conductance per area (W/m^2 K).  One circle: ``C = 2 kappa_s a``.
    """
    return kappa_s * np.asarray(stiffness, dtype=float) / Es


def semi_infinite_temperature(x, t: float, q: float, kappa: float, rho: float, c: float,
                              T0: float = 0.0):
    """Temperature at depth ``x`` of a half-space under constant surface flux ``q`` since t = 0.

    ``T0 + (2 q / kappa) sqrt(a t) ierfc(x / (2 sqrt(a t)))``, ``a = kappa / (rho c)``,
    ``ierfc(z) = exp(-z^2) / sqrt(pi) - z erfc(z)`` (Carslaw and Jaeger, section 2.9).
    At ``x = 0`` it is :func:`semi_infinite_surface_temperature`.
    """
    from scipy.special import erfc

    x = np.asarray(x, dtype=float)
    s = np.sqrt(kappa / (rho * c) * t)
    z = x / (2.0 * s)
    ierfc = np.exp(-z ** 2) / np.sqrt(np.pi) - z * erfc(z)
    return T0 + 2.0 * q * s / kappa * ierfc


# --------------------------------------------------------------- one stop ---
# A stop at constant deceleration: the sliding speed, and with it the flux
# q = mu p v, falls linearly to zero, q(t) = q0 (1 - t / t_s) for 0 <= t <= t_s
# (Newcomb and Spurr; Limpert, Brake Design and Safety, ch. 3).


def inerfc(n: int, z):
    """Repeated integral of the complementary error function, ``i^n erfc(z)``.

    ``i^0 erfc = erfc``, ``i^n erfc(z) = int_z^inf i^(n-1) erfc(s) ds``, by the
    recurrence ``2 n i^n erfc = i^(n-2) erfc - 2 z i^(n-1) erfc`` with
    ``i^(-1) erfc(z) = 2 exp(-z^2) / sqrt(pi)`` (Carslaw and Jaeger, appendix II).
    ``i^n erfc(0) = 1 / (2^n Gamma(n/2 + 1))``.  Forward recurrence loses
    relative accuracy where ``i^n erfc`` is small (``z`` beyond about 3 for
    n = 3); the absolute error stays at round-off of ``i^(n-2) erfc``.

    Examples
    --------
    At ``z = 0``, ``1 / (2^n Gamma(n/2 + 1))``: 1, ``1/sqrt(pi)``, 1/4:

    >>> values = [float(inerfc(n, 0.0)) for n in (0, 1, 2)]
    >>> bool(np.allclose(values, [1.0, 1.0 / np.sqrt(np.pi), 0.25], rtol=1e-14))
    True
    """
    from scipy.special import erfc

    if not (isinstance(n, (int, np.integer)) and n >= 0):
        raise ThermalError(f"inerfc: n = {n!r} is not allowed; need a whole number >= 0")
    z = np.asarray(z, dtype=float)
    prev, cur = 2.0 * np.exp(-z ** 2) / np.sqrt(np.pi), erfc(z)
    for k in range(1, n + 1):
        prev, cur = cur, (prev - 2.0 * z * cur) / (2.0 * k)
    return cur


def _check_stop(t_stop: float) -> None:
    if not (np.isfinite(t_stop) and t_stop > 0):
        raise ThermalError(f"t_stop = {t_stop!r} s is not allowed; need a stop time > 0")


def stop_flux(t, q0: float, t_stop: float):
    """Flux of a stop, ``q0 (1 - t / t_s)`` for ``0 <= t <= t_s`` and zero after it (W/m^2)."""
    _check_stop(t_stop)
    t = np.asarray(t, dtype=float)
    return np.where((t >= 0) & (t <= t_stop), q0 * (1.0 - t / t_stop), 0.0)


def stop_heat(t0, t1, q0: float, t_stop: float):
    """Heat per unit area that enters between ``t0`` and ``t1`` (J/m^2): the exact
    integral of :func:`stop_flux`; ``q0 t_s / 2`` over the whole stop.  Divided by
    ``t1 - t0`` it is the step's mean flux.

    Examples
    --------
    >>> float(stop_heat(0.0, 4.0, 1e6, 4.0)), float(stop_heat(0.0, 2.0, 1e6, 4.0))
    (2000000.0, 1500000.0)
    """
    _check_stop(t_stop)

    def cumulative(t):
        s = np.clip(np.asarray(t, dtype=float), 0.0, t_stop)
        return q0 * (s - s ** 2 / (2.0 * t_stop))

    return cumulative(t1) - cumulative(t0)


def stop_temperature(x, t, q0: float, t_stop: float, kappa: float, rho: float, c: float,
                     T0: float = 0.0):
    """Temperature at depth ``x`` of a half-space heated by a stop's falling flux.

    Superposition of a constant flux ``q0`` and a flux ``-(q0 / t_s) t`` (and,
    after the stop, of ``+(q0 / t_s)(t - t_s)`` from ``t_s``: the flux is then
    zero).  With ``a = kappa / (rho c)`` and ``z = x / (2 sqrt(a t))``, a flux
    ``F t^(n/2)`` gives ``F Gamma(n/2 + 1) 2^(n+1) sqrt(a t) t^(n/2) i^(n+1)erfc(z)
    / kappa`` (Carslaw and Jaeger, section 2.9), so::

        T - T0 = (2 q0 sqrt(a t) / kappa) ierfc(z)
                 - (8 q0 t sqrt(a t) / (t_s kappa)) i^3erfc(z)      (0 <= t <= t_s)

    At ``x = 0`` it is :func:`stop_surface_temperature`.  ``t`` a number
    (``x`` may be an array) or an array (``x`` a number).
    """
    _check_stop(t_stop)
    a = kappa / (rho * c)
    t = np.asarray(t, dtype=float)
    rise = (q0 * _power_flux_response(x, t, 0, a, kappa)
            - q0 / t_stop * (_power_flux_response(x, t, 2, a, kappa)
                             - _power_flux_response(x, t - t_stop, 2, a, kappa)))
    return T0 + rise


def _power_flux_response(x, s, n: int, a: float, kappa: float):
    """Half-space response to the flux ``s^(n/2)`` switched on at ``s = 0`` (zero before)."""
    from scipy.special import gamma

    x, s = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(s, dtype=float))
    out = np.zeros(x.shape)
    on = s > 0
    d = np.sqrt(a * s[on])
    out[on] = (gamma(n / 2 + 1) * 2.0 ** (n + 1) * d * s[on] ** (n / 2)
               * inerfc(n + 1, x[on] / (2.0 * d)) / kappa)
    return out


def stop_surface_temperature(t, q0: float, t_stop: float, kappa: float, rho: float, c: float,
                             T0: float = 0.0):
    """Surface temperature of a half-space over a stop (Newcomb, Limpert)::

        T - T0 = (2 q0 sqrt(t) / (e sqrt(pi))) (1 - 2 t / (3 t_s)),   0 <= t <= t_s

    with the effusivity ``e = sqrt(kappa rho c)``; after the stop (zero flux)
    ``(2 q0 / (e sqrt(pi))) (sqrt(t) - 2 (t^1.5 - (t - t_s)^1.5) / (3 t_s))``.
    Its maximum is at ``t_s / 2`` (:func:`stop_peak_temperature`).

    Examples
    --------
    Its maximum is :func:`stop_peak_temperature`, at :func:`stop_peak_time`:

    >>> args = (2e6, 4.0, 50.0, 7200.0, 500.0)
    >>> t = np.linspace(0.0, 4.0, 401)
    >>> float(t[np.argmax(stop_surface_temperature(t, *args))]) == stop_peak_time(4.0)
    True
    >>> peak = float(stop_surface_temperature(stop_peak_time(4.0), *args))
    >>> round(peak / stop_peak_temperature(*args), 12)
    1.0
    """
    _check_stop(t_stop)
    t = np.asarray(t, dtype=float)
    e = np.sqrt(kappa * rho * c)
    tc = np.clip(t, 0.0, None)
    after = np.clip(t - t_stop, 0.0, None)
    return T0 + 2.0 * q0 / (e * np.sqrt(np.pi)) * (
        np.sqrt(tc) - 2.0 * (tc ** 1.5 - after ** 1.5) / (3.0 * t_stop))


def stop_peak_time(t_stop: float) -> float:
    """Time of the surface maximum over a stop: ``t_s / 2``."""
    _check_stop(t_stop)
    return 0.5 * t_stop


def stop_peak_temperature(q0: float, t_stop: float, kappa: float, rho: float, c: float,
                          T0: float = 0.0) -> float:
    """Largest surface temperature of a stop: ``T0 + (2 sqrt(2) / 3) q0 sqrt(t_s) / (e sqrt(pi))``."""
    e = np.sqrt(kappa * rho * c)
    return float(T0 + 2.0 * np.sqrt(2.0) / 3.0 * q0 * np.sqrt(t_stop) / (e * np.sqrt(np.pi)))


def bulk_temperature_rise(energy: float, mass, c) -> float:
    """Temperature rise of lumped bodies that store ``energy`` (J): ``E / sum(m c)``.

    ``mass`` (kg) and ``c`` (J/kg K) are numbers or one per body.

    Examples
    --------
    A 300 kJ stop into a 7 kg iron rotor and a 0.5 kg pad:

    >>> bulk_temperature_rise(300e3, [7.0, 0.5], [500.0, 1000.0])     # K: 300 kJ / 4 kJ/K
    75.0
    """
    mc = float(np.sum(np.asarray(mass, dtype=float) * np.asarray(c, dtype=float)))
    if not (np.isfinite(mc) and mc > 0):
        raise ThermalError(f"bulk_temperature_rise: sum(m c) = {mc!r} J/K is not allowed; "
                           "need > 0")
    return float(energy) / mc
