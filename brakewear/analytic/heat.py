"""Closed forms of frictional heating: a slab, a half-space under constant flux and
under a stop's falling flux, repeated integrals of erfc, the lumped temperature rise,
and the contact conductance of rough faces (Mikic, Barber).

All functions take and return SI units and accept NumPy arrays where a
coordinate is an argument.
"""
from __future__ import annotations

import numpy as np

from ..errors import ThermalError

__all__ = [
    "slab_temperature",
    "semi_infinite_surface_temperature",
    "mikic_elastic_conductance",
    "barber_conductance",
    "semi_infinite_temperature",
    "inerfc",
    "stop_flux",
    "stop_heat",
    "stop_temperature",
    "stop_surface_temperature",
    "stop_peak_time",
    "stop_peak_temperature",
    "bulk_temperature_rise",
]


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
    """Largest surface temperature of a stop.

    ``T0 + (2 sqrt(2) / 3) q0 sqrt(t_s) / (e sqrt(pi))``.
    """
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
