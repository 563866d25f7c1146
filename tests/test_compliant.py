"""Contact through a compliant layer (the implicit wear step), brakewear.contact.compliant."""
import numpy as np
import pytest

from brakewear.contact import compliant_preconditioner, solve_compliant_contact, solve_contact
from brakewear.model import BrakeModel


@pytest.fixture(scope="module")
def system():
    model = BrakeModel("default", size=8e-3)
    return model.contact_system(1e6, 0.4)


@pytest.fixture(scope="module")
def base(system):
    return compliant_preconditioner(system.K, system.fixed, system.coords)


def _lagrange(system):
    res = solve_contact(system.K, system.f, system.fixed, system.coords, [system.pair], tol=1e-10)
    return res.pressure[0]


def _solve(system, base, eps, **kw):
    eps = np.full(system.pair.slave.size, eps) if np.isscalar(eps) else eps
    return solve_compliant_contact(system.K, system.f, system.fixed, system.coords, system.pair,
                                   eps, solver=base, **kw)


def test_force_balance_and_sign_conditions(system, base):
    res = _solve(system, base, 1e-15)
    # the springs carry the clamp force; compressed exactly where active
    assert res.info["normal_force"] == pytest.approx(system.clamp_force, rel=1e-8)
    assert np.array_equal(res.active, res.gap < 0)
    assert np.all(res.pressure >= 0) and np.all(res.pressure[~res.active] == 0)
    # spring law: force = -kappa gap on the active nodes
    kappa = system.pair.area / 1e-15
    assert np.allclose(res.force[res.active], -kappa[res.active] * res.gap[res.active],
                       rtol=1e-12, atol=0)


def test_vanishing_compliance_tends_to_lagrange_contact(system, base):
    # a stiffer layer approaches the rigid (Lagrange) contact, first order in eps
    p_ref = _lagrange(system)
    errs = []
    for eps in (1e-13, 1e-14, 1e-15):
        p = _solve(system, base, eps).pressure
        errs.append(np.abs(p - p_ref).max() / p_ref.max())
    # measured 1.21e-2, 1.27e-3, 1.28e-4: first order (each tenfold stiffer layer ~10x)
    assert errs[1] < errs[0] / 8 and errs[2] < errs[1] / 8
    assert errs[2] < 3e-4


def test_loose_phase_and_warm_start_do_not_change_the_answer(system, base):
    eps = 5e-15 * 55.0 * 0.12 * 18.0          # k v dt of an 18 s step
    tight = _solve(system, base, eps, loose_tol=None)
    loose = _solve(system, base, eps, loose_tol=1e-3)
    scale = tight.pressure.max()
    assert np.array_equal(tight.active, loose.active)
    assert np.abs(tight.pressure - loose.pressure).max() <= 1e-6 * scale
    # a warm start from a nearby solution (a slightly different layer) needs fewer
    # linear iterations and gives the same pressure
    near = _solve(system, base, 1.05 * eps)
    warm = _solve(system, base, eps, x0=near.u, initial_active=near.active)
    assert np.abs(warm.pressure - tight.pressure).max() <= 1e-6 * scale
    assert warm.info["linear_iterations"] < tight.info["linear_iterations"]


def test_result_depends_only_on_inputs(system, base):
    eps = 1e-14
    a = _solve(system, base, eps)
    b = _solve(system, base, eps)
    assert np.array_equal(a.pressure, b.pressure)


@pytest.mark.parametrize("kw,match", [
    ({"compliance": -1.0}, "compliance"),
    ({"compliance": np.ones(3)}, "compliance"),
    ({"loose_tol": 2.0}, "loose_tol"),
    ({"x0": np.zeros(5)}, "x0"),
])
def test_bad_input_is_named(system, base, kw, match):
    eps = kw.pop("compliance", 1e-14)
    with pytest.raises(ValueError, match=match):
        _solve(system, base, eps, **kw)
