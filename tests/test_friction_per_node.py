"""A friction coefficient per contact node: the friction operator, the FE and the
condensed contact solves, and the torque it gives."""
import numpy as np
import pytest

from brakewear.contact.compliant import drag_loads
from brakewear.interfaces import CondensedInterface, FEInterface
from brakewear.model import BrakeModel


@pytest.fixture(scope="module")
def fe():
    model = BrakeModel("default", size=8e-3)
    return FEInterface(model, 1e6, 0.4)


def _torque(itf, mu, p):
    """Torque about the rotor axis (N m) of the friction loads on the pad nodes under
    the nodal normal forces ``p A``, assembled by the friction operator."""
    pair, cs = itf.pair, itf.cs
    F = (drag_loads(pair, cs.K.shape[0], mu) @ (p * itf.area)).reshape(-1, 3)[pair.slave]
    x = cs.coords[:, pair.slave]
    return float((x[0] * F[:, 1] - x[1] * F[:, 0]).sum())


def test_friction_torque_of_a_speed_dependent_mu_is_the_closed_form():
    """mu(v) = a + b v with v = omega r under a uniform pressure on the annular sector:
    T = p theta [a (ro^3 - ri^3) / 3 + b omega (ro^4 - ri^4) / 4].  The nodal
    (tributary-area) quadrature converges to it at second order."""
    p, a, b, omega = 1e6, 0.45, -0.004, 60.0          # mu falls from 0.42 to 0.41 over r
    errors, sizes = [], (1.2e-2, 8e-3, 5e-3)
    for h in sizes:
        itf = FEInterface(BrakeModel("default", size=h), 1e6, 0.4)
        g = itf.model.geometry.pad
        ri, ro, th = g.inner_radius, g.outer_radius, g.arc_angle
        exact = p * th * (a * (ro ** 3 - ri ** 3) / 3 + b * omega * (ro ** 4 - ri ** 4) / 4)
        mu = a + b * omega * itf.r
        T = _torque(itf, mu, np.full(itf.r.size, p))
        errors.append(abs(abs(T) - exact) / exact)
    assert errors[-1] < 2e-3, errors
    rate = np.polyfit(np.log(sizes), np.log(errors), 1)[0]
    assert rate > 1.5, (rate, errors)


def test_a_uniform_mu_per_node_is_the_number(fe):
    a = fe.solve(np.zeros(fe.r.size), None, mu=0.4)
    b = fe.solve(np.zeros(fe.r.size), None, mu=np.full(fe.r.size, 0.4))
    assert np.array_equal(a.pressure, b.pressure)


def _cop_theta(itf, sol):
    w = sol.pressure * itf.area
    return float((w * np.arctan2(itf.x[1], itf.x[0])).sum() / w.sum())


def test_mu_per_node_moves_the_centre_of_pressure_between_its_bounds(fe):
    """Friction tilts the pad and moves the centre of pressure along the arc, the
    more the larger mu.  A mu that varies over the face between 0.2 and 0.4 moves
    it in the same direction, by less than mu = 0.4 and more than mu = 0.2; one
    larger at the nodes that carry more load moves it further than one smaller
    there (the friction force is sum mu_i p_i A_i)."""
    n = fe.r.size
    zero = _cop_theta(fe, fe.solve(np.zeros(n), None, mu=0.0))
    shift = {}
    r = (fe.r - fe.r.min()) / np.ptp(fe.r)
    cases = {"0.2": 0.2, "0.4": 0.4, "rising": 0.2 + 0.2 * r, "falling": 0.4 - 0.2 * r}
    for name, mu in cases.items():
        shift[name] = _cop_theta(fe, fe.solve(np.zeros(n), None, mu=mu)) - zero
    s02, s04 = shift["0.2"], shift["0.4"]
    assert abs(s04) > abs(s02) > 0 and np.sign(s04) == np.sign(s02)
    for name in ("rising", "falling"):
        assert min(s02, s04) < shift[name] < max(s02, s04), shift


def test_condensed_interface_takes_mu_per_node(fe):
    """The condensed solve with one mu per node is the FE solve's (to 1e-8)."""
    n = fe.r.size
    itf = CondensedInterface(fe.model, 1e6, 0.4, fe=fe)
    r = (fe.r - fe.r.min()) / np.ptp(fe.r)
    mu = 0.3 + 0.15 * r
    a = fe.solve(np.zeros(n), None, mu=mu)
    b = itf.solve(np.zeros(n), None, mu=mu)
    assert np.abs(a.pressure - b.pressure).max() <= 1e-8 * a.pressure.max()
    c = itf.solve(np.zeros(n), None, mu=0.4)
    d = itf.solve(np.zeros(n), None, mu=np.full(n, 0.4))
    assert np.array_equal(c.pressure, d.pressure)


def test_bad_mu_per_node_is_refused(fe):
    n = fe.r.size
    with pytest.raises(ValueError, match=r"mu has shape \(3,\)"):
        fe.solve(np.zeros(n), None, mu=np.full(3, 0.4))
    with pytest.raises(ValueError, match="need mu >= 0"):
        fe.solve(np.zeros(n), None, mu=np.full(n, -0.1))
    fe.solve(np.zeros(n), None, mu=0.4)
