"""The caliper's joint solver (brakewear.caliper.joint) against the nested one it
replaces (brakewear.caliper.sets) and against a sparse direct solve of the FE
equations of the state found: the same answers on the suite's caliper cases --
contact solves rigid and compliant, with the rings' wear and another friction
coefficient, and stops of a schedule -- to the nested path's own accuracy
(its eliminations lose digits: 6e-12 of the clamp force in the contact forces,
1e-9 in the rows' against the direct solve, where the joint path's refined
solution is at 1e-14 and 1e-12); and the issue's reproduction (a hot, strongly
coned stop where the nested solves lost the contact) run to its end."""
import copy
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from brakewear import BrakeModel, CaliperInterface, Numerics, WearLaw, load_geometry
from brakewear.caliper.sets import RowSets
from brakewear.interfaces import StepCompliance
from brakewear.mesh.rings import ring_coupling

REL = 1e-9           # the fast path's pressures against the reference path's (its accuracy)


def _rel(a, b):
    return float(np.abs(a - b).max() / max(np.abs(b).max(), 1e-300))


@pytest.fixture(scope="module")
def pair():
    g = load_geometry("floating")
    g = replace(g, support=replace(g.support, abutment_friction=0.03))
    model = BrakeModel(g, size=12e-3, piston="rigid")
    joint = CaliperInterface(model, 1e6, 0.4)
    nested = copy.copy(joint)                    # the same condensation and rows
    nested.solver = "nested"
    nested.sets = RowSets(joint.cond, joint.rows, joint.gap_tol, joint.tol)
    r = joint.fe.r
    return model, joint, nested, 15e-6 * (r - r.min()) / np.ptp(r)


def _compliance(itf, dt=2.0, rings=True):
    v = 60.0 * itf.r
    eps = dt * 5e-15 * v
    if not rings:
        return eps
    return StepCompliance(eps, dt * 2e-15 * v, *ring_coupling(itf.W, itf.ring, itf.rotor_area))


@pytest.mark.parametrize("case", ["rigid", "compliant", "rings", "friction"])
def test_the_joint_solve_is_the_nested_solve(pair, case):
    _, joint, nested, offset = pair
    kw = {"mu": 0.4}
    if case == "compliant":
        kw["compliance"] = _compliance(joint, rings=False)
    elif case == "rings":
        kw["compliance"] = _compliance(joint)
    elif case == "friction":                     # another mu than the reference's
        kw.update(mu=0.37, compliance=_compliance(joint))
    for itf in (joint, nested):                  # from the same rows' start
        itf.sets.state = itf.sets._initial_state()
    a = joint.solve(offset, None, **kw)
    b = nested.solve(offset, None, **kw)
    assert np.array_equal(a.active, b.active)
    assert 0 < a.active.sum() < a.active.size    # a partial contact, a real test
    assert _rel(a.pressure, b.pressure) < REL
    ca, cb = a.info["caliper"], b.info["caliper"]
    assert np.array_equal(ca["state"], cb["state"])
    F = 1e6 * joint.model.geometry.clamp_area
    assert np.abs(ca["force"] - cb["force"]).max() < 1e-8 * F
    if "compliance" in kw and case != "compliant":
        assert _rel(a.info["ring_depth"], b.info["ring_depth"]) < REL


def test_the_joint_solve_is_the_direct_fe_solve_of_its_state(pair):
    """The state found, its FE equations solved directly (tests/test_caliper.py):
    contact and rows' forces to 1e-12 and 1e-10 of the clamp force."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from test_caliper import _fe_solve

    model, joint, _, offset = pair
    sol = joint.solve(offset, None, mu=0.4)
    cal = sol.info["caliper"]
    u, q, lamA, lam_s = _fe_solve(joint, sol, offset, 0.4, 1e6)
    F = 1e6 * model.geometry.clamp_area
    assert np.abs(lamA - cal["lam"][sol.active]).max() < 1e-12 * F
    assert np.abs(lam_s - cal["force"]).max() < 1e-10 * F


def test_stops_of_a_schedule_agree(pair):
    """Two stops by deceleration (the torque iteration, implicit steps, rings): line
    pressures, pressures and wear of both solvers to round-off."""
    from brakewear import Run
    from brakewear.duty import Stop, Vehicle, run_schedule

    model, joint, nested, offset = pair
    car = Vehicle(mass=1800.0, front_share=0.7, tyre_radius=0.32)
    out = {}
    for name, itf in (("joint", joint), ("nested", nested)):
        itf.sets.state = itf.sets._initial_state()
        run = Run(model, pad_law=WearLaw(5e-14), rotor_law=WearLaw(1e-14), mu=0.4,
                  interface=itf, numerics=Numerics(scheme="implicit", steps=3),
                  initial_gap=offset, vehicle=car,
                  schedule=[Stop(80 / 3.6, decel=2.0), Stop(80 / 3.6, decel=3.0)])
        out[name] = list(run_schedule(run))
    for a, b in zip(out["joint"], out["nested"]):
        assert a.line_pressure == pytest.approx(b.line_pressure, rel=REL)
        assert _rel(a.pressure, b.pressure) < REL
        assert _rel(a.rotor_wear, b.rotor_wear) < REL


def _brake_with_radius(radius):
    """A brake whose contact solve returns its line pressure as the pressure field
    and whose effective radius is ``radius(pressure)`` (it counts its solves)."""
    from brakewear.duty.runner import _Brake

    class Brake(_Brake):
        def __init__(self):
            self.mu, self.clamp_area, self.calls = 0.4, 1e-3, 0

        def solve(self, p):
            self.calls += 1
            return type("Solution", (), {"pressure": p})()

        def r_eff(self, pressure, p):
            return radius(pressure)
    return Brake()


def test_the_torque_iteration_brackets_a_jump_of_the_radius():
    """A radius that jumps up with the load (a pad rocking onto its other edge) leaves
    the torque's target inside the jump: the plain fixed point oscillates between
    the two sides, the bracketed iteration closes on the jump."""
    b = _brake_with_radius(lambda pressure: 0.10 if pressure < 1.0e6 else 0.12)
    k = 2 * 0.4 * 1e-3                       # the torque per Pa and m of radius
    p, r = b.pressure_for_torque(k * 0.11e6, 0.8e6, rtol=1e-10, max_iter=80)
    assert p == pytest.approx(1.0e6, rel=1e-9)
    assert b.calls < 80
    # a smooth radius: the fixed point's answer, to the tolerance
    smooth = _brake_with_radius(lambda pressure: 0.11 + 0.01 * (pressure / 1e6 - 1.0))
    p, r = smooth.pressure_for_torque(k * 0.11e6, 0.8e6)
    assert k * p * r == pytest.approx(k * 0.11e6, rel=1e-9)


@pytest.mark.slow
def test_the_reproduction_draw_runs_through(monkeypatch, tmp_path):
    """Draw 17 of the new-pad priors (seed 37), stops from 100 km/h at 1 m/s^2 at 8 mm,
    heat on: the outboard pad rocks on its fingers' edge in the first two stops; the
    routine runs through without a solver error."""
    from brakewear.cleaning.car import packaged_car
    from brakewear.cleaning.priors import cleaning_inputs, draw
    from brakewear.cleaning.routine import Routine
    from brakewear.cleaning.sample import RoutineSettings, run_routine
    from brakewear.duty import KMH

    x = draw(20, 37, cleaning_inputs("new"))[17]
    r = run_routine(x, Routine(2, 100 * KMH, 1.0, 120.0), packaged_car(),
                    RoutineSettings(size=8e-3, start="new", run_to_end=True))
    assert "error" not in r, r.get("error")
    assert len(r["rows"]) == 2 and all(row["line_pressure_MPa"] > 0 for row in r["rows"])


def test_the_torque_iteration_closes_on_a_jump_it_approaches_by_secants():
    """A radius with a slope on both sides of its jump (the pad rocking onto its
    other edge while the contact spreads): secant steps inside the bracket shorten
    one side at a time; the iteration bisects when the bracket does not halve in
    two steps and closes on the jump to the tolerance."""
    jump = 2.047e6
    b = _brake_with_radius(lambda pressure: (0.0959 if pressure < jump else 0.1008)
                           + 0.02 * (pressure / 1e6 - 2.0))
    k = 2 * 0.4 * 1e-3
    target = k * jump * 0.0985                # inside the jump of k p r at ``jump``
    p, _ = b.pressure_for_torque(target, 2.2e6)
    assert p == pytest.approx(jump, rel=1e-9)
    assert b.calls <= 2 * int(np.log2(0.2 / 1e-10)) + 4


@pytest.mark.parametrize("case", ["rigid", "rings"])
def test_the_complementarity_fallback_finds_the_active_set_state(pair, monkeypatch, case):
    """The rows' iteration refused: the damped Newton fallback, from rest, finds the
    state the active-set iteration finds, to its accuracy; the answer holds
    complementarity (no tension, no penetration, Coulomb on the friction rows)
    and the caliper's rigid parts' equilibrium (forces and moments)."""
    from brakewear.caliper.joint import JointSets
    from brakewear.errors import SolverError

    model, joint, _, offset = pair
    kw = {"mu": 0.4}
    if case == "rings":
        kw["compliance"] = _compliance(joint)
    joint.sets.state = joint.sets._initial_state()
    a = joint.solve(offset, None, **kw)
    counts = dict(joint.sets.counts)

    def refuse(*args, **kwargs):
        raise SolverError("the rows' iteration refused (test)")
    monkeypatch.setattr(JointSets, "_row_iteration", refuse)
    joint.sets.state = joint.sets._initial_state()
    b = joint.solve(offset, None, **kw)
    used = sum(joint.sets.counts.get(k, 0) - counts.get(k, 0) for k in ("newton", "fischer"))
    assert used == 1
    assert np.array_equal(a.active, b.active)
    assert 0 < b.active.sum() < b.active.size
    ca, cb = a.info["caliper"], b.info["caliper"]
    assert np.array_equal(ca["state"], cb["state"])
    assert _rel(b.pressure, a.pressure) < REL
    F = 1e6 * model.geometry.clamp_area
    assert np.abs(ca["force"] - cb["force"]).max() < 1e-8 * F
    # complementarity, from the answer alone
    rows, lam, lam_s, g_s = joint.rows, cb["lam"], cb["force"], cb["gap"]
    assert lam[b.active].min() >= -1e-9 * F
    # no penetration beyond the tolerance; with a wear step's compliance a node in
    # contact closes by its own wear, c lam, and no further
    closing = 0.0 if case == "rigid" else float((kw["compliance"].pad / joint.area * lam).max())
    assert b.info["min_gap"] >= -closing * (1 + 1e-9) - joint.gap_tol
    nrm, closed = rows.normal, cb["state"] == 1
    assert lam_s[nrm & closed].min(initial=0.0) >= -1e-9 * F
    assert np.abs(lam_s[nrm & ~closed]).max(initial=0.0) <= 1e-12 * F
    assert g_s[nrm & ~closed].min(initial=0.0) >= -joint.gap_tol
    bound = rows.mu * (rows.cap @ np.maximum(lam_s, 0.0))
    assert np.all(np.abs(lam_s[~nrm]) <= bound[~nrm] + 1e-9 * F)
    # the rigid parts' equilibrium: R^T lam_s + K_q q = p f_q
    p = joint.line_pressure
    res = rows.R.T @ lam_s + rows.K_q @ cb["q"] - p * rows.f_q
    terms = np.abs(rows.R.T) @ np.abs(lam_s) + np.abs(rows.K_q) @ np.abs(cb["q"]) \
        + np.abs(p * rows.f_q)
    assert np.abs(res).max() <= 1e-10 * terms.max()
