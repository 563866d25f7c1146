"""The closed forms checked on their own: round trips, equilibrium, integrals."""
import numpy as np
import pytest
from scipy.integrate import quad

from brakewear import analytic as an


def test_effective_modulus_limits():
    assert an.effective_modulus(100e9, 0.3) == pytest.approx(100e9 / 0.91)
    # two identical bodies: half the single-body value
    assert an.effective_modulus(1e9, 0.25, 1e9, 0.25) == pytest.approx(0.5e9 / (1 - 0.0625))


def test_hertz_sphere_round_trip_and_load_integral():
    F, R, Es = 100.0, 0.01, 100e9
    h = an.hertz_sphere(F, R, Es)
    assert 4 * Es * h["a"] ** 3 / (3 * R) == pytest.approx(F, rel=1e-12)
    load, _ = quad(lambda r: an.hertz_sphere_pressure(r, F, R, Es) * 2 * np.pi * r, 0, h["a"])
    assert load == pytest.approx(F, rel=1e-8), f"integral of p = {load}"
    assert h["delta"] == pytest.approx(h["a"] ** 2 / R)


def test_hertz_cylinder_load_integral():
    P, R, Es = 1e4, 0.02, 70e9
    h = an.hertz_cylinder(P, R, Es)
    load, _ = quad(lambda x: h["p0"] * np.sqrt(1 - (x / h["a"]) ** 2), -h["a"], h["a"])
    assert load == pytest.approx(P, rel=1e-8)


def test_flat_punch_load_integral():
    F, a = 50.0, 0.005
    # substitute r = a sin(phi) to remove the edge singularity
    load, _ = quad(lambda ph: an.flat_punch_pressure(a * np.sin(ph), F, a) * 2 * np.pi
                   * a * np.sin(ph) * a * np.cos(ph), 0, np.pi / 2 * (1 - 1e-12))
    assert load == pytest.approx(F, rel=1e-6)
    assert an.flat_punch_settlement(F, a, 1e9) == pytest.approx(F / (2 * a * 1e9))


def test_thick_cylinder_equilibrium_and_boundaries():
    a, b, p, E, nu = 0.09, 0.15, 1e7, 110e9, 0.27
    r = np.linspace(a, b, 201)
    sr, st = an.thick_cylinder_stress(r, a, b, p)
    assert sr[0] == pytest.approx(-p) and abs(sr[-1]) < 1e-6 * p
    dsr = np.gradient(sr, r, edge_order=2)
    assert np.max(np.abs(dsr + (sr - st) / r)) < 1e-3 * p / (b - a)
    # Hooke in plane strain: eps_theta = u/r
    u = an.thick_cylinder_displacement(r, a, b, p, E, nu)
    sz = nu * (sr + st)
    strain = (st - nu * (sr + sz)) / E
    assert np.allclose(u / r, strain, rtol=1e-12, atol=1e-12 * np.abs(strain).max())


def test_uniform_wear_pressure_integrates_to_force_and_torque():
    F, th, ri, ro, mu = 3000.0, np.radians(55), 0.095, 0.138, 0.4
    load, _ = quad(lambda r: an.uniform_wear_pressure(r, F, th, ri, ro) * th * r, ri, ro)
    assert load == pytest.approx(F, rel=1e-10)
    torque, _ = quad(lambda r: mu * an.uniform_wear_pressure(r, F, th, ri, ro) * th * r * r, ri, ro)
    assert torque == pytest.approx(an.uniform_wear_torque(F, mu, ri, ro), rel=1e-10)
    # uniform pressure acts further out than uniform wear; both -> r as the ring gets thin
    assert an.uniform_pressure_effective_radius(ri, ro) > (ri + ro) / 2
    assert an.uniform_pressure_effective_radius(0.1, 0.1 + 1e-7) == pytest.approx(0.1, rel=1e-6)


def test_heat_references():
    q, L, k = 1e5, 0.01, 50.0
    x = np.linspace(0, L, 11)
    T = an.slab_temperature(x, q, L, k, T0=20.0)
    assert T[-1] == pytest.approx(20.0) and -k * np.gradient(T, x)[0] == pytest.approx(q)
    # semi-infinite surface temperature grows with sqrt(t)
    T1, T4 = an.semi_infinite_surface_temperature([1.0, 4.0], q, 50.0, 7200.0, 500.0)
    assert T4 / T1 == pytest.approx(2.0)


# ======================================================================
# Elastic foundation (Winkler) closed forms -- brakewear.interfaces.winkler_bed, issue 7
# ======================================================================

def test_johnson_modulus_formulas_and_bad_input():
    E, nu, h = 3e9, 0.25, 0.01
    assert an.johnson_modulus(E, nu, h) == pytest.approx(E * 0.75 / (1.25 * 0.5 * h), rel=1e-14)
    assert an.johnson_modulus(E, nu, h, constrained=False) == pytest.approx(E / h, rel=1e-14)
    # nu = 0: lateral constraint changes nothing
    assert an.johnson_modulus(E, 0.0, h) == pytest.approx(E / h, rel=1e-14)
    # the constrained value is the zz entry of the isotropic stiffness over h
    from brakewear.materials import Isotropic
    assert an.johnson_modulus(E, nu, h) == pytest.approx(Isotropic(E, nu).voigt()[2, 2] / h)
    for bad in ({"E": 0.0}, {"E": -1e9}, {"thickness": 0.0}, {"thickness": -1e-3},
                {"thickness": np.nan}, {"nu": 0.5}):
        args = {"E": E, "nu": nu, "thickness": h, **bad}
        name = next(iter(bad))
        with pytest.raises(ValueError, match=name):
            an.johnson_modulus(**args)


def test_winkler_sphere_round_trip_load_integral_and_hertz_ratio():
    R, k, delta = 0.01, 3e11, 2e-6
    w = an.winkler_sphere(R, k, delta=delta)
    assert w["a"] == pytest.approx(np.sqrt(2 * R * delta), rel=1e-14)
    assert an.winkler_sphere(R, k, F=w["F"])["delta"] == pytest.approx(delta, rel=1e-12)
    load, _ = quad(lambda r: an.winkler_sphere_pressure(r, R, k, delta) * 2 * np.pi * r,
                   0, w["a"])
    assert load == pytest.approx(w["F"], rel=1e-10), f"integral of p = {load}"
    assert an.winkler_sphere_pressure(w["a"] * 1.01, R, k, delta) == 0.0
    assert an.winkler_sphere_pressure(0.0, R, k, delta) == pytest.approx(w["p0"])
    # at equal approach the foundation's contact is sqrt(2) times Hertz's
    Es = 1e9
    F_h = 4 / 3 * Es * np.sqrt(R) * delta ** 1.5
    assert w["a"] / an.hertz_sphere(F_h, R, Es)["a"] == pytest.approx(np.sqrt(2), rel=1e-12)
    with pytest.raises(ValueError, match="exactly one"):
        an.winkler_sphere(R, k)


@pytest.mark.parametrize("match,ratios", [
    ("radius", {"approach": 0.5, "stiffness": 8 / 3, "peak": 4 / 3, "area": 1.0}),
    ("stiffness", {"approach": 4 / 3, "stiffness": 1.0, "peak": 0.5, "area": 8 / 3})])
def test_winkler_bed_calibrated_on_hertz(match, ratios):
    """Hertz's radius (or stiffness) at Hertz's load fixes K; the rest follows exactly."""
    F, R, Es = 12.0, 0.02, 3e9
    w = an.winkler_hertz_match(F, R, Es, match)
    a = an.hertz_sphere(F, R, Es)["a"]
    K = 16 * Es / (3 * np.pi * a) if match == "radius" else 3 * Es / (4 * np.pi * a)
    assert w["K"] == pytest.approx(K, rel=1e-14)
    for k, v in ratios.items():
        assert w["ratio"][k] == pytest.approx(v, rel=1e-12), f"{k}: {w['ratio'][k]}"
    # the bed carries the load: F = pi K R delta^2, and its stiffness is dF/d delta
    assert np.pi * w["K"] * R * w["delta"] ** 2 == pytest.approx(F, rel=1e-12)
    d = 1e-6 * w["delta"]
    dF = np.pi * w["K"] * R * ((w["delta"] + d) ** 2 - (w["delta"] - d) ** 2) / (2 * d)
    assert w["stiffness"] == pytest.approx(dF, rel=1e-8)
    with pytest.raises(ValueError, match="match"):
        an.winkler_hertz_match(F, R, Es, "area")


def test_hertz_stiffness_is_the_derivative_of_the_load():
    R, Es, delta = 0.01, 2e9, 3e-6

    def load(d):
        return 4 / 3 * Es * np.sqrt(R) * d ** 1.5

    F = load(delta)
    dd = 1e-6 * delta
    assert an.hertz_sphere_stiffness(F, R, Es) == pytest.approx(
        (load(delta + dd) - load(delta - dd)) / (2 * dd), rel=1e-8)
    assert an.hertz_sphere_stiffness(F, R, Es) == pytest.approx(
        2 * Es * an.hertz_sphere(F, R, Es)["a"], rel=1e-14)


def test_mindlin_and_the_brush_calibrated_on_it():
    a, Es = 1e-3, 1e9
    for nu in (0.0, 0.25, 0.3, 0.45):
        kt = an.mindlin_tangential_stiffness(a, Es, nu)
        # 8 G a / (2 - nu), G = E* (1 - nu) / 2 for one elastic body of E* = E / (1 - nu^2)
        assert kt == pytest.approx(8 * (Es * (1 - nu) / 2) * a / (2 - nu), rel=1e-14)
        assert kt / (2 * Es * a) == pytest.approx(2 * (1 - nu) / (2 - nu), rel=1e-14)
    assert an.mindlin_tangential_stiffness(a, Es, 0.0) == pytest.approx(2 * Es * a)
    with pytest.raises(ValueError, match="nu"):
        an.mindlin_tangential_stiffness(a, Es, 0.5)
    F, R, nu = 12.0, 0.02, 0.3
    for match in ("radius", "stiffness"):
        w = an.winkler_hertz_match(F, R, Es, match)
        kt_bed = an.brush_hertz_modulus(F, R, Es, nu, match) * np.pi * w["a"] ** 2
        assert kt_bed == pytest.approx(
            an.mindlin_tangential_stiffness(w["hertz"]["a"], Es, nu), rel=1e-12)


def test_mikic_correlation_and_barbers_analogy():
    Es, s, m, k = 3e9, 3e-6, 0.12, 3.8
    p = np.array([1e5, 1e6, 1e7])
    h = an.mikic_elastic_conductance(p, Es, s, m, k)
    assert h[1] == pytest.approx(1.54 * k * m / s * (np.sqrt(2) * 1e6 / (Es * m)) ** 0.94,
                                 rel=1e-14)
    assert h[2] / h[1] == pytest.approx(10 ** 0.94, rel=1e-12)
    assert an.mikic_elastic_conductance(0.0, Es, s, m, k) == 0.0
    assert an.mikic_elastic_conductance(1e6, Es, 2 * s, m, k) == pytest.approx(h[1] / 2)
    # one circular spot: conductance 2 kappa_s a (two half-spaces in series) from 2 E* a
    a = 50e-6
    assert an.barber_conductance(2 * Es * a, Es, k) == pytest.approx(2 * k * a, rel=1e-14)


def test_semi_infinite_profile_surface_flux_and_energy():
    q, k, rho, c, t = 2e5, 2.0, 2400.0, 1000.0, 12.0
    T_surf = an.semi_infinite_surface_temperature(t, q, k, rho, c, T0=300.0)
    assert an.semi_infinite_temperature(0.0, t, q, k, rho, c, T0=300.0) == pytest.approx(
        T_surf, rel=1e-14)
    depth = np.sqrt(k / (rho * c) * t)
    # Fourier at the surface: -kappa dT/dx = q
    h = 1e-6 * depth
    dTdx = (an.semi_infinite_temperature(h, t, q, k, rho, c)
            - an.semi_infinite_temperature(0.0, t, q, k, rho, c)) / h
    assert -k * dTdx == pytest.approx(q, rel=1e-5)
    # all the heat that entered is stored: int rho c (T - T0) dx = q t
    stored, _ = quad(lambda x: rho * c * an.semi_infinite_temperature(x, t, q, k, rho, c),
                     0.0, 40 * depth)
    assert stored == pytest.approx(q * t, rel=1e-8), f"stored {stored} vs q t {q * t}"


# ======================================================================
# A single stop: linearly falling flux on a half-space, and the bulk rise
# ======================================================================

STOP = {"q0": 1.6e6, "t_stop": 4.0, "kappa": 50.0, "rho": 7200.0, "c": 500.0}


def _duhamel(x, t, q0, t_stop, kappa, rho, c):
    """Duhamel's integral of the constant-flux kernel, ``int q(tau) dU/dt(x, t - tau) dtau``
    with ``dU/dt = sqrt(a / (pi s)) exp(-x^2 / (4 a s)) / kappa``, substituted
    ``t - tau = u^2`` to remove the ``1/sqrt(s)`` singularity."""
    a = kappa / (rho * c)

    def f(u):
        g = np.exp(-x * x / (4 * a * u * u)) if u > 0 else float(x == 0)
        return an.stop_flux(t - u * u, q0, t_stop) * 2 / kappa * np.sqrt(a / np.pi) * g

    kink = [np.sqrt(t - t_stop)] if t > t_stop else None   # the flux's end
    return quad(f, 0, np.sqrt(t), points=kink, limit=200, epsabs=0, epsrel=1e-12)[0]


def test_inerfc_values_and_integrals():
    from scipy.special import erfc, gamma
    for n in range(5):
        assert an.inerfc(n, 0.0) == pytest.approx(1 / (2 ** n * gamma(n / 2 + 1)), rel=1e-14)
    z = 0.7
    assert an.inerfc(0, z) == erfc(z)
    assert an.inerfc(1, z) == pytest.approx(np.exp(-z * z) / np.sqrt(np.pi) - z * erfc(z),
                                            rel=1e-14)
    for n in (1, 2, 3):       # i^n erfc(z) = int_z^inf i^(n-1) erfc
        integral = quad(lambda s, n=n: an.inerfc(n - 1, s), z, np.inf, epsabs=0, epsrel=1e-12)[0]
        assert an.inerfc(n, z) == pytest.approx(integral, rel=1e-10), n
    with pytest.raises(ValueError, match="n = -1"):
        an.inerfc(-1, z)


@pytest.mark.parametrize("x", [0.0, 1e-3, 5e-3, 2e-2])
def test_stop_temperature_is_duhamels_integral(x):
    """Inside the stop and after it (zero flux, cooling), at the surface and inside."""
    for t in (0.3, 2.0, 4.0, 6.0, 12.0):
        exact = _duhamel(x, t, **STOP)
        T = an.stop_temperature(x, t, **STOP)
        assert T == pytest.approx(exact, rel=1e-9, abs=1e-12 * STOP["q0"]), (x, t, T, exact)


def test_stop_surface_formula_is_the_x0_limit_and_peaks_at_half_the_stop():
    t = np.linspace(0.0, 3 * STOP["t_stop"], 301)
    Ts = an.stop_surface_temperature(t, **STOP)
    assert np.allclose(an.stop_temperature(0.0, t, **STOP), Ts, rtol=1e-13, atol=0)
    # Newcomb/Limpert during the stop
    q0, ts = STOP["q0"], STOP["t_stop"]
    e = np.sqrt(STOP["kappa"] * STOP["rho"] * STOP["c"])
    during = t <= ts
    newcomb = 2 * q0 * np.sqrt(t) / (e * np.sqrt(np.pi)) * (1 - 2 * t / (3 * ts))
    assert np.allclose(Ts[during], newcomb[during], rtol=1e-13, atol=0)
    # the maximum: at t_s / 2, of the stated value; the grid's largest lies there
    t_peak = an.stop_peak_time(ts)
    peak = an.stop_peak_temperature(**STOP)
    assert t[np.argmax(Ts)] == pytest.approx(t_peak, rel=1e-12)
    assert an.stop_surface_temperature(t_peak, **STOP) == pytest.approx(peak, rel=1e-14)
    h = 1e-4 * ts
    assert an.stop_surface_temperature(t_peak + h, **STOP) < peak
    assert an.stop_surface_temperature(t_peak - h, **STOP) < peak
    # at constant flux (t_s -> inf) it is the constant-flux surface temperature
    T_const = an.semi_infinite_surface_temperature(2.0, q0, STOP["kappa"], STOP["rho"],
                                                   STOP["c"])
    assert an.stop_surface_temperature(2.0, q0, 1e12, STOP["kappa"], STOP["rho"],
                                       STOP["c"]) == pytest.approx(T_const, rel=1e-9)


def test_stop_temperature_obeys_fourier_at_the_surface_and_stores_the_heat():
    k, rho, c, ts = STOP["kappa"], STOP["rho"], STOP["c"], STOP["t_stop"]
    depth = np.sqrt(k / (rho * c) * ts)
    for t in (1.0, 3.0, 6.0):
        h = 1e-6 * depth
        dTdx = (an.stop_temperature(h, t, **STOP) - an.stop_temperature(0.0, t, **STOP)) / h
        flux = float(an.stop_flux(t, STOP["q0"], ts))
        assert -k * dTdx == pytest.approx(flux, rel=1e-5, abs=1e-5 * STOP["q0"]), t
        stored = quad(lambda x, t=t: rho * c * an.stop_temperature(x, t, **STOP), 0, 40 * depth,
                      epsabs=0, epsrel=1e-11, limit=200)[0]
        heat = an.stop_heat(0.0, t, STOP["q0"], ts)
        assert stored == pytest.approx(heat, rel=1e-8), (t, stored, heat)
    assert an.stop_heat(0.0, 2 * ts, STOP["q0"], ts) == pytest.approx(STOP["q0"] * ts / 2,
                                                                      rel=1e-14)
    # the step's mean flux is the flux's integral over it: here its midpoint value
    assert an.stop_heat(1.0, 1.5, STOP["q0"], ts) / 0.5 == pytest.approx(
        float(an.stop_flux(1.25, STOP["q0"], ts)), rel=1e-14)
    with pytest.raises(ValueError, match="t_stop = 0"):
        an.stop_flux(1.0, STOP["q0"], 0)


def test_bulk_temperature_rise():
    m, c = np.array([3.9, 0.35, 0.2]), np.array([500.0, 1000.0, 460.0])
    E = 1e5
    dT = an.bulk_temperature_rise(E, m, c)
    assert dT * float(m @ c) == pytest.approx(E, rel=1e-14)
    assert an.bulk_temperature_rise(E, 2.0, 500.0) == pytest.approx(100.0, rel=1e-14)
    with pytest.raises(ValueError, match="sum\\(m c\\) = 0"):
        an.bulk_temperature_rise(E, 0.0, 500.0)
