"""Coulomb friction with stick and slip (brakewear.contact.friction) against
Cattaneo-Mindlin: a cylinder (plane strain) and a sphere on a flat of one material,
meshed and condensed by brakewear.tribology.bodies, under a normal load and then a
tangential load below mu P; gross slip once the master is moved further.

The blocks are flat-faced and the curvature is the initial gap x^2 / 2R (Hertz's and
Mindlin's half-space idealisation), so the comparison is with the closed forms' own
assumptions; both bodies are one block and its mirror image (one material: the
normal and tangential problems do not couple)."""
import math

import numpy as np
import pytest

import brakewear.analytic as an
from brakewear.contact.friction import OPEN, SLIP, STICK, solve_friction, solve_sliding
from brakewear.errors import ContactError
from brakewear.materials import Isotropic
from brakewear.solvers.threads import blas_threads
from brakewear.tribology.bodies import block, mirrored

E, NU, MU = 200e9, 0.3, 0.5
ES = E / (2 * (1 - NU ** 2))
MAT = Isotropic(E, NU)


def _pair(dim, a, per_a, half_width_a):
    h = a / per_a
    with blas_threads(1):
        A = block("flat", MAT, half_width_a * a, half_width_a * a, 1.3 * a, h, dim, below=True)
    return A, mirrored(A, "counterface")


class Cylinder:
    """Plane strain: R = 10 mm, 200 kN/m, a = 0.15 mm; 24 face nodes per a."""
    R, P = 0.01, 2e5

    def __init__(self, per_a=24):
        self.a = an.hertz_cylinder(self.P, self.R, ES)["a"]
        self.A, self.B = _pair(2, self.a, per_a, 30)
        self.C = self.A.compliance + self.B.compliance
        self.x = self.A.x[0]
        self.g0 = self.x ** 2 / (2 * self.R)
        self.h = self.a / per_a

    def normal(self):
        return solve_friction(self.C, self.g0, MU, self.P, shift=[0.0])

    def loaded(self, Q, mu=MU):
        n = self.normal()
        return solve_friction(self.C, self.g0, mu, self.P, Q=[Q], w_prev=n.w, start=n)


@pytest.fixture(scope="module")
def cyl():
    return Cylinder()


def test_normal_load_is_hertz(cyl):
    n = cyl.normal()
    p = n.normal / cyl.A.area
    hz = an.hertz_cylinder(cyl.P, cyl.R, ES)
    assert p.max() == pytest.approx(hz["p0"], rel=0.02), p.max() / hz["p0"]
    half = np.sum(cyl.A.area[n.state != OPEN]) / 2
    assert abs(half - hz["a"]) < 1.5 * cyl.h, (half / hz["a"])
    # one material: a normal load alone leaves no tangential traction to speak of
    assert np.abs(n.tangential).max() < 1e-3 * MU * p.max() * cyl.h


@pytest.mark.parametrize("ratio", [0.2, 0.5, 0.8])
def test_cylinder_stick_zone_traction_and_slip(cyl, ratio):
    Q = ratio * MU * cyl.P
    s = cyl.loaded(Q)
    cm = an.cattaneo_mindlin_cylinder(cyl.P, Q, MU, cyl.R, ES)
    assert -s.tangential.sum() == pytest.approx(Q, rel=1e-9)
    stick = s.state == STICK
    c = np.sum(cyl.A.area[stick]) / 2
    # the stick zone's half-width, to a node spacing
    assert abs(c - cm["c"]) < 1.0 * cyl.h, (c / cm["a"], cm["c"] / cm["a"])
    assert np.all(np.abs(cyl.x[stick]) < cm["c"] + cyl.h)
    # the shear traction, relative L2 away from the edges it falls at (the contact's,
    # within two node spacings, where a node's lumped traction stands for a sqrt(a - x)
    # fall over its length; and the stick zone's, known to a node spacing)
    q = -s.tangential[:, 0] / cyl.A.area
    qa = an.cattaneo_mindlin_cylinder_traction(cyl.x, cyl.P, Q, MU, cyl.R, ES)
    inner = (np.abs(cyl.x) < cm["a"] - 2 * cyl.h) & (np.abs(np.abs(cyl.x) - cm["c"]) > 1.5 * cyl.h)
    err = np.linalg.norm((q - qa)[inner]) / np.linalg.norm(qa[inner])
    assert err < 0.03, err
    # the slip of the surfaces in the slip zone (the accumulated w; zero where stuck),
    # where the slip zone spans five nodes or more
    if cm["a"] - cm["c"] < 5 * cyl.h:
        return
    sa = an.cattaneo_mindlin_cylinder_slip(cyl.x, cyl.P, Q, MU, cyl.R, ES)
    ws = np.abs(s.w[:, 0] - s.w[stick, 0].mean())
    inside = np.abs(cyl.x) < cm["a"]
    err = np.abs(ws - sa)[inside].max() / sa.max()
    assert err < 0.06, err
    assert np.all(s.state[np.abs(cyl.x) > cm["a"] + 1.5 * cyl.h] == OPEN)


def test_cylinder_slip_compliance(cyl):
    """What the slip adds to the tangential approach: the partial-slip shift minus
    the shift with mu = 1e6 (all stuck).  24 nodes per a give 1.032, 1.018, 1.008
    of the closed form at Q / mu P = 0.5, 0.7, 0.9; 48 give 0.969, 0.977, 0.983
    (the blocks end at 30 a: the clamp's share is of order a / 30)."""
    for ratio in (0.5, 0.7, 0.9):
        Q = ratio * MU * cyl.P
        slip = cyl.loaded(Q).shift[0] - cyl.loaded(Q, mu=1e6).shift[0]
        cm = an.cattaneo_mindlin_cylinder_slip_compliance(cyl.P, Q, MU, cyl.R, ES)
        assert slip == pytest.approx(cm, rel=0.05), (ratio, slip / cm)


def test_gross_slip_under_a_moving_master(cyl):
    """Displacement control beyond the partial-slip range: every node in contact
    slips and the tangential force is mu P; force control at mu P is refused."""
    n = cyl.normal()
    cm_gross = MU * cyl.P / (math.pi * ES)            # what slip adds at Q -> mu P
    prev, last = n, None
    for s in np.linspace(0.2, 3.0, 8) * (cyl.loaded(0.99 * MU * cyl.P).shift[0] + cm_gross):
        prev = solve_friction(cyl.C, cyl.g0, MU, cyl.P, shift=[s], w_prev=prev.w, start=prev)
        last = prev
    touching = last.state != OPEN
    assert np.all(last.state[touching] == SLIP)
    assert -last.tangential.sum() == pytest.approx(MU * cyl.P, rel=1e-9)
    assert np.allclose(-last.tangential[touching, 0], MU * last.normal[touching], rtol=1e-9)
    with pytest.raises(ContactError, match="slide as a whole"):
        solve_friction(cyl.C, cyl.g0, MU, cyl.P, Q=[MU * cyl.P])


def test_sliding_is_the_gross_slip_of_the_general_solve(cyl):
    moved = solve_friction(cyl.C, cyl.g0, MU, cyl.P, shift=[1e-4])
    slid = solve_sliding(cyl.C, cyl.g0, MU, cyl.P, [1.0])
    assert np.allclose(moved.normal, slid.normal, rtol=1e-8, atol=1e-10 * cyl.P)
    assert np.allclose(moved.tangential, slid.tangential, rtol=1e-8, atol=1e-10 * cyl.P)


@pytest.mark.slow
def test_cylinder_converges_under_refinement():
    errs = []
    for per_a in (12, 24, 48):
        c = Cylinder(per_a)
        Q = 0.7 * MU * c.P
        cm = an.cattaneo_mindlin_cylinder_slip_compliance(c.P, Q, MU, c.R, ES)
        slip = c.loaded(Q).shift[0] - c.loaded(Q, mu=1e6).shift[0]
        errs.append(abs(slip / cm - 1))
    assert errs[-1] < 0.035 and errs[-1] < errs[0] / 3, errs


class Sphere:
    """R = 5 mm, 10 N: a = 70 um.  The face nodes' spacing ``h`` is what the
    refinement reaches (a power of two of the coarse box's), at most ``a / per_a``."""
    R, F = 0.005, 10.0

    def __init__(self, per_a):
        self.a = an.hertz_sphere(self.F, self.R, ES)["a"]
        self.A, self.B = _pair(3, self.a, per_a, 12)
        self.C = self.A.compliance + self.B.compliance
        self.r = np.hypot(self.A.x[0], self.A.x[1])
        self.g0 = self.r ** 2 / (2 * self.R)
        self.h = math.sqrt(np.median(self.A.area))

    def loaded(self, Q, mu=MU):
        with blas_threads(1):
            n = solve_friction(self.C, self.g0, mu, self.F, shift=[0.0, 0.0])
            return solve_friction(self.C, self.g0, mu, self.F, Q=[Q, 0.0], w_prev=n.w,
                                  start=n)

    def check(self, tol_total, tol_slip):
        """The stick zone's radius (from its area) to half a node spacing; Mindlin's
        tangential approach; what the slip adds to it (the shift minus the shift with
        mu = 1e6, a difference of close numbers at small Q)."""
        for ratio, tol in zip((0.3, 0.75), tol_slip):
            Q = ratio * MU * self.F
            s = self.loaded(Q)
            assert -s.tangential[:, 0].sum() == pytest.approx(Q, rel=1e-9)
            assert np.abs(s.tangential[:, 1].sum()) < 1e-9 * Q
            cm = an.cattaneo_mindlin_sphere(self.F, Q, MU, self.R, ES)
            c = math.sqrt(np.sum(self.A.area[s.state == STICK]) / math.pi)
            assert abs(c - cm["c"]) < 0.5 * self.h, (ratio, c / cm["a"], cm["c"] / cm["a"])
            d = an.cattaneo_mindlin_sphere_displacement(self.F, Q, MU, self.R, E, NU, E, NU)
            assert s.shift[0] == pytest.approx(d["delta"], rel=tol_total)
            stuck = self.loaded(Q, mu=1e6).shift[0]
            assert s.shift[0] - stuck == pytest.approx(d["slip"], rel=tol), ratio


def test_sphere_coarse():
    """293 face nodes (h = a / 9): c within 0.17 h, the approach within 1 %, the
    slip's share 1.17 and 1.07 of Mindlin's at Q / mu P = 0.3 and 0.75."""
    Sphere(6).check(tol_total=0.03, tol_slip=(0.3, 0.15))


@pytest.mark.slow
def test_sphere_fine():
    """593 face nodes (h = a / 13): the slip's share 0.90 and 0.97."""
    Sphere(10).check(tol_total=0.025, tol_slip=(0.15, 0.05))
