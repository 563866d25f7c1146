"""Backward Euler on both surfaces: the rotor's rings wear with the end-of-step pressure.

The implicit scheme solves the rotor's ring-averaged wear of a step with the
pad's (:mod:`brakewear.contact.compliant_rings`, :class:`~brakewear.interfaces.StepCompliance`).
Checked here: the uniform-wear steady state of both surfaces against its
closed form (docs/references.md, Wear), at steps far beyond the explicit
rings' stability bound; volume conservation of every step; first-order
convergence in the step where the pad-only scheme with explicit rings
oscillates; and the same answer from the FE, condensed and foundation
interfaces.
"""
import numpy as np
import pytest

from brakewear.interfaces import (
    CondensedInterface,
    FEInterface,
    FoundationInterface,
    StepCompliance,
    WinklerInterface,
)
from brakewear.laws.base import WearLaw
from brakewear.mesh.rings import ring_coupling, rotor_wear_rate
from brakewear.model import BrakeModel
from brakewear.wear import Numerics, Run, wear_history
from test_wear_steady import stiff_backing_model

P_LINE, OMEGA, MU = 1e6, 55.0, 0.4
K_PAD = 5e-13       # 100 x a resin pad's k (only k times the sliding distance sets the shape)
K_ROT = 1e-11       # 20 x the pad's: the rings wear three times as deep as the pad


@pytest.fixture(scope="module")
def stiff():
    model = stiff_backing_model()
    return model, FEInterface(model, P_LINE, MU)


def rings_bound(itf, k_rot) -> float:
    """The explicit rings' monotone step (s): 1 / max_j sum_i k v s_i / A_ring_j."""
    q = k_rot * OMEGA * itf.r * itf.normal_stiffness
    return 1.0 / float(rotor_wear_rate(q, itf.W, itf.ring, itf.rotor_area).max())


def history(model, itf, duration, steps, scheme="implicit"):
    return list(
        wear_history(
            Run(
                model,
                P_LINE,
                OMEGA,
                duration,
                WearLaw(K_PAD),
                WearLaw(K_ROT),
                MU,
                interface=itf,
                numerics=Numerics(scheme=scheme, steps=steps),
            )
        )
    )


@pytest.fixture(scope="module")
def steady(stiff):
    model, itf = stiff
    return history(model, itf, 12.0, 24)


def test_both_surfaces_run_in_to_the_uniform_wear_rates(stiff, steady):
    """Steady uniform wear with both surfaces wearing: p r = C = F / (theta (ro - ri)), the
    pad wears k_pad omega C everywhere and every ring under it k_rot omega C theta / (2 pi)
    (the pad passes over a ring's point theta / 2 pi of each revolution)."""
    model, itf = stiff
    g = model.geometry.pad
    a, b = steady[-2], steady[-1]
    assert b.dt > 5 * rings_bound(itf, K_ROT)     # 8.5 x the explicit rings' bound
    F = P_LINE * model.geometry.clamp_area
    C = F / (g.arc_angle * (g.outer_radius - g.inner_radius))
    pad_rate = (b.pad_wear - a.pad_wear) / b.dt
    ring_rate = (b.rotor_wear - a.rotor_wear) / b.dt
    assert b.active_end.all()
    pr = b.pressure_end * itf.r
    assert (pr.max() - pr.min()) / pr.mean() < 0.02
    assert pad_rate.mean() == pytest.approx(K_PAD * OMEGA * C, rel=5e-3)
    assert np.abs(pad_rate / (K_PAD * OMEGA * C) - 1).max() < 0.01
    # the rings at the pad's edges carry half a band of pad and of rotor: within 1 %
    assert np.abs(ring_rate / (K_ROT * OMEGA * C * g.arc_angle / (2 * np.pi)) - 1).max() < 0.01


def test_every_step_conserves_the_worn_volumes(steady):
    for s in steady:
        assert s.rotor_volume == pytest.approx(s.rotor_archard, rel=1e-12)
        assert s.pad_volume == pytest.approx(s.pad_archard, rel=1e-12)
    # and the two surfaces wear in the ratio of their coefficients (same p v)
    s = steady[-1]
    assert s.rotor_volume / s.pad_volume == pytest.approx(K_ROT / K_PAD, rel=1e-12)


@pytest.mark.slow
def test_long_steps_beyond_the_rings_bound_converge_at_first_order(stiff):
    """Steps of 3 to 13 x the explicit rings' bound: the implicit rings are stable
    and the error halves with the step; at the longest step the pad-only scheme
    (explicit rings) overshoots to a p r spread 18 x the converged one, where the
    implicit one's spread falls step by step and lags (first order) by a twentieth
    of that."""
    model, itf = stiff
    T = 3.0
    fine = {n: history(model, itf, T, n)[-1] for n in (32, 64)}
    ref = 2 * fine[64].pad_wear - fine[32].pad_wear
    ref_rot = 2 * fine[64].rotor_wear - fine[32].rotor_wear
    assert T / 4 > 12 * rings_bound(itf, K_ROT)
    err, err_rot = [], []
    for n in (4, 8, 16):
        last = history(model, itf, T, n)[-1]
        err.append(np.abs(last.pad_wear - ref).max() / ref.max())
        err_rot.append(np.abs(last.rotor_wear - ref_rot).max() / ref_rot.max())
    rates = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    assert np.all(rates > 0.8), (err, rates)
    assert err[-1] < 5e-3 and max(err_rot) < 1e-3, (err, err_rot)
    def spread(s):
        pr = s.pressure_end * itf.r
        return float(np.ptp(pr) / np.mean(pr))

    ok = [spread(s) for s in history(model, itf, T, 4)]
    bad = spread(history(model, itf, T, 4, scheme="implicit_pad")[-1])
    conv = spread(fine[64])
    assert np.all(np.diff(ok) < 0) and bad > 10 * conv, (ok, bad, conv)
    assert abs(ok[-1] - conv) < 0.1 * abs(bad - conv), (ok, bad, conv)


@pytest.mark.slow
def test_the_step_count_does_not_grow_as_the_mesh_is_refined():
    """A fast-wearing rotor under the dp_tol control, 12 and 6 mm (660 and 2 700 DOFs): the
    implicit rings take the same steps on both meshes; explicit rings (``implicit_pad``)
    are held to their bound, which shrinks with the face's elements (94 -> 149 steps)."""
    counts = {}
    for size in (12e-3, 6e-3):
        model = stiff_backing_model(size)
        itf = FEInterface(model, P_LINE, MU)
        for scheme in ("implicit", "implicit_pad"):
            recs = list(
                wear_history(
                    Run(
                        model,
                        P_LINE,
                        OMEGA,
                        6.0,
                        WearLaw(K_PAD),
                        WearLaw(K_ROT),
                        MU,
                        interface=itf,
                        numerics=Numerics(scheme=scheme, dp_tol=0.1),
                    )
                )
            )
            counts[size, scheme] = len(recs)
            if scheme == "implicit":
                assert not any(r.limit == "rotor_stability" for r in recs)
    assert counts[6e-3, "implicit"] <= 1.2 * counts[12e-3, "implicit"], counts
    assert counts[12e-3, "implicit"] < 0.3 * counts[12e-3, "implicit_pad"], counts
    assert counts[6e-3, "implicit_pad"] > 1.4 * counts[12e-3, "implicit_pad"], counts


# ---------------------------------------------------------------- interfaces --
@pytest.fixture(scope="module")
def interfaces():
    model = BrakeModel(size=8e-3)
    fe = FEInterface(model, P_LINE, MU, tol=1e-12)
    cd = CondensedInterface(model, P_LINE, MU, fe=fe, cache=False)
    return model, fe, cd


def step_compliance(itf, dt, ratio):
    v = OMEGA * itf.r
    return StepCompliance(dt * K_PAD * v, dt * ratio * K_PAD * v,
                          *ring_coupling(itf.W, itf.ring, itf.rotor_area))


def check_defining_equations(itf, sol, comp, offset, **kw):
    """The rings' depths are the revolution average of the solved pressure, and the
    pad-only solve with those depths in the gap gives the same pressure."""
    d = comp.ring_depth(sol.pressure, itf.area)
    assert np.abs(d - sol.info["ring_depth"]).max() <= 1e-8 * np.abs(d).max()
    alone = itf.solve(offset + comp.ring_gap @ d, sol.active, compliance=comp.pad, **kw)
    assert np.abs(alone.pressure - sol.pressure).max() <= 1e-8 * sol.pressure.max()


@pytest.mark.parametrize("ratio", [0.1, 20.0])
def test_fe_and_condensed_solve_the_same_ring_coupled_step(interfaces, ratio):
    model, fe, cd = interfaces
    start = fe.solve(np.zeros(fe.area.size), None)
    offset = 2e-6 * (fe.r - fe.r.min()) / np.ptp(fe.r)        # a worn taper
    comp = step_compliance(fe, 5.0, ratio)
    a = fe.solve(offset, start.active, compliance=comp, x0=start.u)
    b = cd.solve(offset, start.active, compliance=comp)
    assert np.array_equal(a.active, b.active)
    assert np.abs(a.pressure - b.pressure).max() <= 1e-8 * b.pressure.max()
    ring = b.info["ring_depth"]
    assert np.abs(a.info["ring_depth"] - ring).max() <= 1e-8 * np.abs(ring).max()
    check_defining_equations(fe, a, comp, offset, x0=a.u)
    check_defining_equations(cd, b, comp, offset)


def test_the_rings_with_the_pads_abutment_stops():
    """A push-type bracket (rigid stops, eliminated in the solve) with the rings: the
    same defining equations."""
    from dataclasses import replace

    from brakewear.geometry import SupportGeometry, load_geometry

    g = load_geometry("default")
    model = BrakeModel(replace(g, support=SupportGeometry(type="push", clearance=1e-4)),
                       size=8e-3, rotor="rigid")
    itf = FEInterface(model, P_LINE, MU, tol=1e-12)
    assert itf.supports
    start = itf.solve(np.zeros(itf.area.size), None)
    offset = np.zeros(itf.area.size)
    comp = step_compliance(itf, 5.0, 20.0)
    sol = itf.solve(offset, start.active, compliance=comp, x0=start.u)
    check_defining_equations(itf, sol, comp, offset, x0=sol.u)


@pytest.mark.parametrize("ratio", [0.1, 20.0, 1000.0])
def test_the_foundation_solves_its_ring_coupled_step(ratio):
    model = BrakeModel(size=8e-3, rotor="rigid")
    itf = FoundationInterface(model, WinklerInterface.from_model(model), P_LINE, MU)
    offset = np.zeros(itf.area.size)
    for dt in (0.1, 10.0, 1e3):
        comp = step_compliance(itf, dt, ratio)
        sol = itf.solve(offset, None, compliance=comp)
        check_defining_equations(itf, sol, comp, offset)
        assert sol.info["ring_iterations"] <= 40


def test_fe_and_condensed_histories_agree_with_implicit_rings(interfaces):
    model, fe, cd = interfaces
    runs = [
        list(
            wear_history(
                Run(
                    model,
                    P_LINE,
                    OMEGA,
                    600.0,
                    WearLaw(5e-15),
                    WearLaw(5e-15),
                    MU,
                    interface=itf,
                    numerics=Numerics(dp_tol=0.1),
                )
            )
        )
        for itf in (fe, cd)
    ]
    assert [s.dt for s in runs[0]] == pytest.approx([s.dt for s in runs[1]], rel=1e-8)
    a, b = runs[0][-1], runs[1][-1]
    assert np.abs(a.pad_wear - b.pad_wear).max() <= 1e-8 * b.pad_wear.max()
    assert np.abs(a.rotor_wear - b.rotor_wear).max() <= 1e-8 * b.rotor_wear.max()
    assert np.abs(a.pressure_end - b.pressure_end).max() <= 1e-8 * b.pressure_end.max()


def test_bad_input_is_refused_with_the_alternative(stiff, tmp_path):
    from brakewear.errors import SceneError, WearError
    from brakewear.scene import load_scene

    model, itf = stiff
    with pytest.raises(WearError, match=r"rotor wear law linear in p .* 'implicit_pad'"):
        next(
            wear_history(
                Run(
                    model,
                    P_LINE,
                    OMEGA,
                    1.0,
                    WearLaw(K_PAD),
                    WearLaw(K_ROT, a=0.8),
                    MU,
                    interface=itf,
                )
            )
        )
    # the pad-only scheme takes it (its rings are explicit)
    next(
        wear_history(
            Run(
                model,
                P_LINE,
                OMEGA,
                1.0,
                WearLaw(K_PAD),
                WearLaw(K_ROT, a=0.8),
                MU,
                interface=itf,
                numerics=Numerics(scheme="implicit_pad", steps=2),
            )
        )
    )
    import dataclasses
    sc = load_scene("default")
    with pytest.raises(SceneError, match=r"wear\.rotor\.a.*implicit_pad"):
        dataclasses.replace(sc, rotor_wear=dataclasses.replace(sc.rotor_wear, a=0.8))
    n = itf.area.size
    B, area = ring_coupling(itf.W, itf.ring, itf.rotor_area)
    for kw, msg in ((dict(pad=-np.ones(n)), "pad must be"),
                    (dict(pad=np.ones(n), rotor=np.ones(n)), "needs ring_gap"),
                    (dict(pad=np.ones(n), rotor=np.ones(n + 1), ring_gap=B, ring_area=area),
                     "rotor must be"),
                    (dict(pad=np.ones(n), rotor=np.ones(n), ring_gap=B, ring_area=area[:-1]),
                     "ring_gap has shape"),
                    (dict(pad=np.ones(n), rotor=np.ones(n), ring_gap=B, ring_area=0 * area),
                     "area > 0")):
        with pytest.raises(ValueError, match=msg):
            StepCompliance(**kw)
