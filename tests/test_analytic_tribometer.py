"""The tribometer closed forms on their own: doctests, equilibrium, the half-plane
kernel they come from, limits and round trips (brakewear.analytic.tribometer)."""
import doctest
import math

import numpy as np
import pytest
from scipy.integrate import quad

import brakewear.analytic as an
import brakewear.analytic.tribometer as at
from brakewear.errors import ContactError

P, MU, R, ES = 1.0e5, 0.6, 0.01, 1.1e11          # N/m, -, m, Pa


def test_doctests():
    res = doctest.testmod(at)
    assert res.attempted >= 8 and res.failed == 0, res


def test_the_closed_forms_are_reached_through_analytic():
    for name in at.__all__:
        assert getattr(an, name) is getattr(at, name), name


@pytest.mark.parametrize("ratio", [0.1, 0.5, 0.9])
def test_cylinder_traction_balances_q_and_stays_in_the_cone(ratio):
    Q = ratio * MU * P
    r = at.cattaneo_mindlin_cylinder(P, Q, MU, R, ES)
    assert r["c"] / r["a"] == pytest.approx(math.sqrt(1 - ratio), rel=1e-12)
    a, c = r["a"], r["c"]
    th = np.linspace(-np.pi / 2, np.pi / 2, 400001)
    x = a * np.sin(th)
    q = at.cattaneo_mindlin_cylinder_traction(x, P, Q, MU, R, ES)
    total = np.trapezoid(q * a * np.cos(th), th)
    assert total == pytest.approx(Q, rel=1e-6)
    p = an.hertz_cylinder(P, R, ES)["p0"] * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))
    assert np.all(q <= MU * p * (1 + 1e-12))
    slip = np.abs(x) > c
    assert np.allclose(q[slip], MU * p[slip], rtol=1e-12)
    assert np.all(q[~slip] < MU * p[~slip] + 1e-9 * MU * p.max())


def _log_potential(w, a, x):
    """int_{-a}^{a} w(s) ln|x - s| ds, through s = a sin(theta) (w may be singular at +-a)."""
    def f(th):
        return w(a * np.sin(th)) * a * np.cos(th) * np.log(abs(x - a * np.sin(th)))

    brk = [math.asin(max(-1.0, min(1.0, x / a)))] if abs(x) < a else []
    return quad(f, -np.pi / 2, np.pi / 2, points=brk or None, limit=400, epsabs=0,
                epsrel=1e-11)[0]


def test_cylinder_slip_is_the_half_plane_response_to_the_traction():
    """The relative tangential displacement of two half-planes of one material under
    the shear traction q is -(2 / (pi E*)) int q ln|x - s| ds: constant in the stick
    zone, and its rise in the slip zone is the closed-form slip."""
    Q = 0.6 * MU * P
    r = at.cattaneo_mindlin_cylinder(P, Q, MU, R, ES)
    a, c = r["a"], r["c"]
    def q(s):
        return at.cattaneo_mindlin_cylinder_traction(s, P, Q, MU, R, ES)

    def u(x):
        return -2.0 / (math.pi * ES) * _log_potential(q, a, x)

    u0 = u(0.0)
    for x in (0.3 * c, 0.9 * c):
        assert u(x) - u0 == pytest.approx(0.0, abs=1e-7 * abs(u0))
    for x in (1.1 * c, 0.5 * (a + c), 0.99 * a):
        s = float(at.cattaneo_mindlin_cylinder_slip(x, P, Q, MU, R, ES))
        assert s > 0
        assert abs(u(x) - u0) == pytest.approx(s, rel=1e-6), (x / a, u(x) - u0, s)
    assert float(at.cattaneo_mindlin_cylinder_slip(0.5 * c, P, Q, MU, R, ES)) == 0.0


@pytest.mark.parametrize("ratio", [0.2, 0.6, 0.95])
def test_cylinder_slip_compliance_is_the_kernel_on_the_traction_difference(ratio):
    Q = ratio * MU * P
    r = at.cattaneo_mindlin_cylinder(P, Q, MU, R, ES)
    a = r["a"]
    def dq(s):
        return (at.cattaneo_mindlin_cylinder_traction(s, P, Q, MU, R, ES)
                - Q / (math.pi * np.sqrt(np.clip(a * a - s * s, 1e-300, None))))

    # the surface moves along the load by -(2 / (pi E*)) int q ln|x - s| ds from remote points
    d = -2.0 / (math.pi * ES) * _log_potential(dq, a, 0.0)
    expected = at.cattaneo_mindlin_cylinder_slip_compliance(P, Q, MU, R, ES)
    assert expected > 0
    assert d == pytest.approx(expected, rel=1e-6)


def test_cylinder_slip_compliance_limits():
    assert at.cattaneo_mindlin_cylinder_slip_compliance(P, 0.0, MU, R, ES) == 0.0
    near = at.cattaneo_mindlin_cylinder_slip_compliance(P, MU * P * (1 - 1e-12), MU, R, ES)
    assert near == pytest.approx(MU * P / (math.pi * ES), rel=1e-6)
    qs = np.linspace(0.05, 0.95, 10) * MU * P
    d = [at.cattaneo_mindlin_cylinder_slip_compliance(P, q, MU, R, ES) for q in qs]
    assert np.all(np.diff(d) > 0)


@pytest.mark.parametrize("ratio", [0.3, 0.8])
def test_sphere_traction_balances_q(ratio):
    F, Rs = 20.0, 5e-3
    Q = ratio * MU * F
    s = at.cattaneo_mindlin_sphere(F, Q, MU, Rs, ES)
    assert s["c"] / s["a"] == pytest.approx((1 - ratio) ** (1 / 3), rel=1e-12)
    total = quad(lambda r: at.cattaneo_mindlin_sphere_traction(r, F, Q, MU, Rs, ES)
                 * 2 * math.pi * r, 0, s["a"], points=[s["c"]], epsrel=1e-11)[0]
    assert total == pytest.approx(Q, rel=1e-8)


def test_sphere_displacement_limits_and_slope():
    F, Rs, E, nu = 20.0, 5e-3, 2e11, 0.3
    d0 = at.cattaneo_mindlin_sphere_displacement(F, 1e-6 * MU * F, MU, Rs, E, nu, E, nu)
    assert d0["delta"] / d0["stick"] == pytest.approx(1.0, rel=1e-5)
    G = E / (2 * (1 + nu))
    a = d0["a"]
    # the stuck contact's stiffness is Mindlin's 8 G a / (2 - nu) per body, in series
    assert 1e-6 * MU * F / d0["stick"] == pytest.approx(
        an.mindlin_tangential_stiffness(a, E / (1 - nu ** 2), nu) / 2, rel=1e-12)
    dg = at.cattaneo_mindlin_sphere_displacement(F, MU * F * (1 - 1e-12), MU, Rs, E, nu, E, nu)
    K = 2 * (2 - nu) / G
    assert dg["delta"] == pytest.approx(3 * MU * F * K / (16 * a), rel=1e-6)
    assert dg["slip"] > 0 and dg["slip"] == pytest.approx(dg["delta"] - dg["stick"])


def test_partial_slip_needs_q_below_mu_p():
    with pytest.raises(ContactError, match="mu P"):
        at.cattaneo_mindlin_cylinder(P, MU * P, MU, R, ES)
    with pytest.raises(ContactError, match="mu P"):
        at.cattaneo_mindlin_sphere(10.0, 11.0, 1.0, R, ES)
    with pytest.raises(ContactError, match="R = -1"):
        at.cattaneo_mindlin_cylinder(P, 0.0, MU, -1, ES)


@pytest.mark.parametrize("h_over_R", [1e-4, 0.01, 0.3, 0.99])
def test_spherical_cap_round_trip_and_small_cap_limit(h_over_R):
    Rs = 5e-3
    V = float(at.spherical_cap_volume(h_over_R * Rs, Rs))
    c = at.spherical_cap_height(V, Rs)
    assert c["h"] == pytest.approx(h_over_R * Rs, rel=1e-12)
    assert c["radius"] ** 2 == pytest.approx(2 * Rs * c["h"] - c["h"] ** 2, rel=1e-12)
    if h_over_R < 0.01:             # a thin cap is a paraboloid: V = pi r^4 / (4 R)
        assert V == pytest.approx(math.pi * c["radius"] ** 4 / (4 * Rs), rel=3 * h_over_R)
    with pytest.raises(ContactError, match="half sphere"):
        at.spherical_cap_height(1.0, Rs)


def test_conforming_block_on_ring_geometry_and_balance():
    Pb, Rr, k = 2.0e4, 0.0175, 2e-14
    for s in (10.0, 1e3, 1e5):
        r = at.conforming_block_on_ring(Pb, Rr, s, k, k_ring=0.2 * k)
        assert float(at.circular_segment_area(r["width"], Rr)) == pytest.approx(k * Pb * s,
                                                                                rel=1e-10)
        # the load: int (p0 cos - p1) cos R dtheta over the scar
        th0 = r["theta0"]
        p0, p1 = r["p0"], r["p1"]
        load = quad(lambda t, p0=p0, p1=p1: (p0 * math.cos(t) - p1) * math.cos(t) * Rr,
                    -th0, th0)[0]
        assert load == pytest.approx(Pb, rel=1e-10)
        assert r["depth"] == pytest.approx(Rr - math.sqrt(Rr ** 2 - r["width"] ** 2 / 4))
        assert r["ring_depth"] == pytest.approx(0.2 * k * Pb * s / (2 * math.pi * Rr))
    small = at.conforming_block_on_ring(Pb, Rr, 1.0, k)
    assert small["area"] == pytest.approx(small["width"] ** 3 / (12 * Rr), rel=1e-3)
