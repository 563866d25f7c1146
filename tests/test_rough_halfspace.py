"""The half-space reference: kernels, the FFT convolution, Hertz to ContactMechanics'
tolerances, the contact stiffness against Mindlin and the punch, the iteration budget."""
import numpy as np
import pytest
from scipy import integrate

from brakewear import analytic as an
from brakewear.errors import ConvergenceError, RoughnessError, SolverError
from brakewear.rough import HalfSpace, contact_stiffness, pixel_kernel, self_affine, solve_normal

# ContactMechanics' Hertz test (test_hertz.py): sphere radius 20, side 5, E* 102,
# a load of 15 or an approach of 0.1 on a free grid
R, SIDE, ES = 20.0, 5.0, 102.0


def _density(direction, nu):
    if direction == "normal":
        return lambda x, y: 1.0 / np.hypot(x, y)
    return lambda x, y: 1.0 / np.hypot(x, y) + nu / (1 - nu) * x * x / np.hypot(x, y) ** 3


@pytest.mark.parametrize("direction", ["normal", "tangential"])
def test_pixel_kernel_is_the_integral_over_the_pixel(direction):
    dx, dy, nu, Es = 1.0, 0.7, 0.3, 2.0
    f = _density(direction, nu)
    for x, y in [(0.3, 0.1), (2.0, -1.5), (-3.0, 0.2), (0.0, 0.0)]:
        # split the pixel at the point: the singularity sits on the corners of the parts
        xs, ys = sorted({-dx / 2, dx / 2, min(max(x, -dx / 2), dx / 2)}), \
            sorted({-dy / 2, dy / 2, min(max(y, -dy / 2), dy / 2)})
        total = 0.0
        for x0, x1 in zip(xs[:-1], xs[1:]):
            for y0, y1 in zip(ys[:-1], ys[1:]):
                total += integrate.dblquad(lambda t, s, x=x, y=y: f(x - s, y - t), x0, x1, y0, y1,
                                           epsabs=1e-12, epsrel=1e-10)[0]
        K = pixel_kernel(x, y, (dx, dy), Es, nu, direction)
        assert K == pytest.approx(total / (np.pi * Es), rel=1e-7), (x, y)


@pytest.mark.parametrize("direction", ["normal", "tangential"])
def test_free_fft_convolution_is_the_direct_sum(direction):
    nx, ny, d = 10, 13, (1.0, 0.7)
    hs = HalfSpace((nx, ny), d, 2.0, 0.3)
    p = np.random.default_rng(0).random((nx, ny))
    u = hs.displacement(p, direction)
    X = np.arange(nx)[:, None] * d[0]
    Y = np.arange(ny)[None, :] * d[1]
    direct = sum(p[i, j] * pixel_kernel(X - i * d[0], Y - j * d[1], d, 2.0, 0.3, direction)
                 for i in range(nx) for j in range(ny))
    assert np.abs(u - direct).max() <= 1e-12 * np.abs(direct).max()


def test_periodic_kernel_is_westergaards_wave():
    """A pressure wave p0 cos(q x) moves the surface by 2 p0 / (E* q) cos(q x); a traction
    wave along x moves it along x by the same if it varies along x, and by 1 / (1 - nu)
    times that if it varies across (Cerruti's multiplier (1 - nu qx^2/q^2) / (1 - nu))."""
    n, Lx, Es, nu = 64, 2.0, 3.0, 0.3
    hs = HalfSpace((n, n), Lx / n, Es, nu, periodic=True)
    x = np.arange(n) * Lx / n
    q = 2 * np.pi * 3 / Lx
    p = np.cos(q * x)[:, None] * np.ones(n)
    assert np.allclose(hs.displacement(p), 2 / (Es * q) * p, atol=1e-12)
    assert np.allclose(hs.displacement(p, "tangential"), 2 / (Es * q) * p, atol=1e-12)
    assert np.allclose(hs.displacement(p.T, "tangential"), 2 / (Es * q * (1 - nu)) * p.T,
                       atol=1e-12)
    assert np.allclose(hs.displacement(np.ones((n, n))), 0.0), "no mean displacement"


def _hertz_grid(n):
    hs = HalfSpace((n, n), SIDE / n, ES)
    x = (np.arange(n) - n / 2) * SIDE / n
    X, Y = np.meshgrid(x, x, indexing="ij")
    r = np.hypot(X, Y)
    return hs, r, r ** 2 / (2 * R)


def _check_hertz(n, tol=1e-10):
    hs, r, g0 = _hertz_grid(n)
    for kw in ({"load": 15.0}, {"approach": 0.1}):
        res = solve_normal(hs, g0, tol=tol, **kw)
        F = res.load
        h = an.hertz_sphere(F, R, ES)
        if "load" in kw:
            assert F == pytest.approx(15.0, rel=1e-12)
            assert res.approach == pytest.approx(h["delta"], rel=1e-2), res.approach
        else:
            assert res.approach == 0.1
            F_h = 4 / 3 * ES * np.sqrt(R) * 0.1 ** 1.5
            assert F == pytest.approx(F_h, rel=1e-2), F
        assert res.area == pytest.approx(np.pi * h["a"] ** 2, rel=0.1), res.area
        inside = r < 0.99 * h["a"]
        err = np.abs(res.pressure - an.hertz_sphere_pressure(r, F, R, ES))[inside].max() / ES
        assert err < 1e-3, f"max |p - p_Hertz| / E* = {err:.2e} inside 0.99 a ({n}^2)"
        assert res.gap_error < 1e-6 * h["delta"]


def test_hertz_on_a_free_grid():
    """ContactMechanics' tolerances (force and approach 1 %, area 10 %, |p - p_H|/E* < 1e-3
    inside 0.99 a) on a 128^2 grid; the 512^2 grid of their test is the slow test below."""
    _check_hertz(128)


@pytest.mark.slow
def test_hertz_on_the_512_free_grid():
    """ContactMechanics' own grid (tolerance 1e-8: the same errors as 1e-10 on 512^2,
    in three quarters of the iterations)."""
    _check_hertz(512, tol=1e-8)


def test_hertz_converges_under_refinement():
    errs = []
    for n in (32, 64, 128):
        hs, r, g0 = _hertz_grid(n)
        res = solve_normal(hs, g0, load=15.0, tol=1e-10)
        errs.append(abs(res.approach / an.hertz_sphere(15.0, R, ES)["delta"] - 1))
    rate = np.polyfit(np.log([32, 64, 128]), np.log(errs), 1)[0]
    assert rate < -1.5 and errs[-1] < 1e-4, (errs, rate)


def test_contact_stiffness_of_hertz_and_of_a_punch():
    """Barber: the normal tangent stiffness is the punch of the contact set, 2 E* a; the
    stuck contact's tangential stiffness is Mindlin's 8 G a / (2 - nu)."""
    nu = 0.3
    n = 128
    hs = HalfSpace((n, n), SIDE / n, ES, nu)
    x = (np.arange(n) - n / 2) * SIDE / n
    X, Y = np.meshgrid(x, x, indexing="ij")
    r = np.hypot(X, Y)
    res = solve_normal(hs, r ** 2 / (2 * R), load=15.0, tol=1e-10)
    h = an.hertz_sphere(15.0, R, ES)
    kn = contact_stiffness(hs, res.contact, "normal")
    kt = contact_stiffness(hs, res.contact, "tangential")
    assert kn.stiffness == pytest.approx(an.hertz_sphere_stiffness(15.0, R, ES), rel=0.01)
    assert kt.stiffness == pytest.approx(an.mindlin_tangential_stiffness(h["a"], ES, nu),
                                         rel=0.01)
    assert kt.stiffness / kn.stiffness == pytest.approx(2 * (1 - nu) / (2 - nu), rel=2e-3)
    # the punch of a disc: the error shrinks with the pixel (first order, the staircase)
    errs = []
    for m in (32, 64, 128):
        hs = HalfSpace((m, m), SIDE / m, ES, nu)
        x = (np.arange(m) - m / 2 + 0.5) * SIDE / m
        disc = np.hypot(*np.meshgrid(x, x, indexing="ij")) < 1.0
        a_eq = np.sqrt(disc.sum() * hs.pixel_area / np.pi)
        errs.append(abs(contact_stiffness(hs, disc).stiffness / (2 * ES * a_eq) - 1))
    assert errs[-1] < 6e-3 and errs[0] > errs[-1], errs


def test_periodic_rough_contact_balances_the_load_and_grows_with_it():
    t = self_affine(64, 1.0, 0.8, rms_height=0.01, cutoff=1 / 16, seed=0)
    hs = HalfSpace(t.shape, t.pixel, 1.0, periodic=True)
    fractions = []
    for pm in (1e-4, 1e-3, 1e-2):
        res = solve_normal(hs, -t.heights, load=pm * 1.0, tol=1e-10)
        assert res.load == pytest.approx(pm, rel=1e-12)
        assert res.pressure.min() >= 0
        g = -t.heights + res.displacement - res.approach
        assert g.min() >= -1e-6 * t.rms_height()
        fractions.append(res.contact_fraction)
    assert fractions[0] < fractions[1] < fractions[2] < 1


def test_the_iteration_budget_raises_with_its_figures():
    hs, r, g0 = _hertz_grid(64)
    with pytest.raises(ConvergenceError, match=r"did not converge in 3 iterations.*change") \
            as exc:
        solve_normal(hs, g0, load=15.0, tol=1e-12, max_iter=3)
    assert isinstance(exc.value, SolverError)
    assert exc.value.info["iterations"] == 3 and exc.value.info["change"] > 1e-12
    disc = r < 1.0
    with pytest.raises(ConvergenceError, match="conjugate gradients did not reach"):
        contact_stiffness(hs, disc, max_iter=2)


@pytest.mark.parametrize("kw,match", [
    ({"gap": np.zeros((8, 8)), "load": 1.0}, "shape"),
    ({"load": 1.0, "approach": 0.1}, "exactly one"), ({}, "exactly one"),
    ({"load": -1.0}, "load"), ({"load": np.nan}, "load"),
    ({"load": 1.0, "tol": 2.0}, "tol")])
def test_bad_normal_input_is_refused(kw, match):
    hs, r, g0 = _hertz_grid(16)
    with pytest.raises(RoughnessError, match=match):
        solve_normal(hs, **{"gap": g0, **kw})


def test_bad_halfspace_and_stiffness_input_is_refused():
    with pytest.raises(RoughnessError, match="shape"):
        HalfSpace((8,), 1.0, 1.0)
    with pytest.raises(RoughnessError, match="modulus"):
        HalfSpace((8, 8), 1.0, -1.0)
    with pytest.raises(RoughnessError, match="poisson"):
        HalfSpace((8, 8), 1.0, 1.0, 0.5)
    hp = HalfSpace((8, 8), 1.0, 1.0, periodic=True)
    with pytest.raises(RoughnessError, match="free grid"):
        solve_normal(hp, np.zeros((8, 8)), approach=0.1)
    with pytest.raises(RoughnessError, match="no pixel"):
        contact_stiffness(hp, np.zeros((8, 8), bool))
    with pytest.raises(RoughnessError, match="unbounded"):
        contact_stiffness(hp, np.ones((8, 8), bool))
    with pytest.raises(RoughnessError, match="direction"):
        hp.displacement(np.zeros((8, 8)), "shear")
