"""Heat in the cleaning stops: the reduced rotor against the full heat conduction it
reduces, the elastic rotor's thermal coning against the hat's figure, the stop-by-stop
routine against one schedule, and the full model's heat check (studies/cleaning_heat.py)."""
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from brakewear import MATERIALS, BrakeModel, FEInterface, Numerics, WearLaw, load_geometry
from brakewear.cleaning.routine import routine_run
from brakewear.cleaning.rust import RustLaw, RustLayer
from brakewear.duty import KMH, Dwell, Stop, run_schedule, study_car
from brakewear.thermal import SpeedConvection, ThermalModel
from brakewear.thermal.coning import RotorConing
from brakewear.thermal.reduced import ReducedRotorHeat, hat_nodes
from brakewear.wear import Run

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "studies"))


@pytest.fixture(scope="module")
def hat():
    g = load_geometry("floating")
    m = BrakeModel(g, size=8e-3, layout="full", rotor="elastic")
    th = ThermalModel(m, h_conv={"pad": 40.0, "rotor": SpeedConvection.solid()},
                      contact_conductance=0.0, partition=0.03)
    band = (g.pad.inner_radius, g.pad.outer_radius)
    return g, m, th, band


def _full_march(heat, T, F0, F1, w0, w1, dur, max_dt, scale):
    n = max(1, int(np.ceil(dur / max_dt)))
    for k in range(n):
        s = (k + 0.5) / n
        A = (heat.M * (n / dur) + heat.K + scale(w0 + (w1 - w0) * s) * heat.H1).tocsc()
        T = spla.spsolve(A, heat.M @ T * (n / dur) + F0 + (F1 - F0) * s)
    return T


def test_reduced_rotor_follows_the_full_heat_conduction(hat):
    """Two stops and a dwell: the ring's and the hat's capacity-weighted means within 2 %
    of the ring's rise of the full implicit-Euler solution on the same mesh; the steady
    state under a constant input is the full one (the basis holds A^-1 B) to 1e-9."""
    from brakewear.mesh.rings import rotor_wear_rate
    from brakewear.thermal.convection import rounded

    g, m, th, band = hat
    red = ReducedRotorHeat(th, band=band)
    heat = th.heat["rotor"]
    pad = m.meshes["pad"].p[:, th.pad_nodes]
    r, out = np.hypot(pad[0], pad[1]), pad[2] < -0.5 * g.rotor.thickness
    power = r * th.pad_area
    power *= 8e3 / power.sum()                       # W at the stop's start
    u = red.ring_powers(r, power, out)
    F0 = heat.flux_load(rotor_wear_rate((1 - 0.03) * power, th.coupling, th.ring,
                                        th.rotor_area))
    law = SpeedConvection.solid()
    scale = lambda w: rounded(law.h(w) / th.h_assembled["rotor"])  # noqa: E731
    hat_n = hat_nodes(m)
    mm = np.asarray(heat.M @ np.ones(heat.n)).ravel()
    T = np.zeros(heat.n)
    for app in ("stop", "dwell", "stop"):
        if app == "stop":
            T = _full_march(heat, T, F0, 0 * F0, 43.4, 0.0, 13.9, 1.0, scale)
            red.heat(u, 13.9, 43.4, 0.0)
        else:
            T = _full_march(heat, T, 0 * F0, 0 * F0, 43.4, 43.4, 106.1, 5.0, scale)
            red.cool(106.1, 43.4)
        ring, hatm = (
            mm[~hat_n] @ T[~hat_n] / mm[~hat_n].sum(),
            mm[hat_n] @ T[hat_n] / mm[hat_n].sum(),
        )
        assert abs(red.T_ring - th.T_ambient - ring) < 0.02 * ring
        assert abs(red.T_hat - th.T_ambient - hatm) < 0.02 * ring
    # steady state at the basis's reference speed: the full solve, to round-off
    red.restore((np.zeros_like(red.a), 0.0))
    Ts = spla.spsolve((heat.K + scale(red._omega_ref) * heat.H1).tocsc(), red.input_loads @ u)
    red.heat(u, 1e7, red._omega_ref, red._omega_ref, u_end=u, max_dt=1e6)
    assert np.abs(red.field - th.T_ambient - Ts).max() < 1e-9 * np.abs(Ts).max()


def test_the_elastic_hat_cones_toward_its_figure(hat):
    """The ring 100 K over the hat: linear tetrahedra bend too stiffly, so the P1 rotor
    cones less than the converged section model's 66 um across the pad
    (docs/thermal.md), and more on the finer mesh; both faces alike.  The reduced
    rotor's coning is the elastic rotor's under its own field (linear: 1e-9), scaled
    so that the even step is the figure (exactly)."""
    g, m, th, band = hat
    con = RotorConing(th, band)
    c8 = con(th.T_ambient + 100.0 * ~hat_nodes(m))
    m6 = BrakeModel(g, size=6e-3, layout="full", rotor="elastic")
    th6 = ThermalModel(m6, contact_conductance=0.0, partition=0.03)
    c6 = RotorConing(th6, band)(th6.T_ambient + 100.0 * ~hat_nodes(m6))
    for f in ("in", "out"):
        assert 0.5 * 66e-6 < c8[f] < c6[f] < 66e-6
    assert c8["in"] == pytest.approx(c8["out"], rel=0.03)
    red = ReducedRotorHeat(th, band=band)
    red.add_coning(con, reference=None)
    red.heat(np.linspace(1e3, 3e3, red.inputs.size), 10.0, 40.0, 0.0)
    direct = con(red.field)
    assert red.coning() == pytest.approx(np.mean(list(direct.values())), rel=1e-9)
    red.add_coning(con)
    assert red.coning_scale == pytest.approx(66e-6 / np.mean(list(c8.values())), rel=1e-9)


def test_the_routine_with_its_states_is_the_schedule_run_by_hand():
    """Without heat and with the plain layered law the routine's run (the rust layer, the
    pads' touch and a warm start as schedule states and interface) wears as one
    run_schedule call that updates a layered rotor by hand in its on_step (1e-9; the pads'
    wear 1e-8, the two paths' contact solves agreeing to their tolerance): the touch moves
    a pad held by tractions rigidly."""
    from brakewear.cleaning.corrosion import CorrodedRotor

    model = BrakeModel("default", size=12e-3, rotor="rigid")
    itf = FEInterface(model, 1e6, 0.4)
    g = model.geometry
    car = study_car().with_friction_share(1.0)
    sched = [Stop(60 * KMH, 0.0, decel=2.0), Dwell(30.0, speed=60 * KMH),
             Stop(60 * KMH, 0.0, decel=2.0)]
    num = Numerics(scheme="implicit", steps=4)
    pad = WearLaw(MATERIALS["pad_resin"].wear_k)
    k_iron = MATERIALS["grey_cast_iron"].wear_k
    old = CorrodedRotor(itf, g.pad.inner_radius, g.pad.outer_radius, 3e-6, 1e-12, k_iron)
    whole = [
        r
        for r in run_schedule(
            Run(
                model,
                pad_law=pad,
                rotor_law=old.law,
                mu=0.4,
                schedule=sched,
                vehicle=car,
                numerics=num,
                interface=itf,
            ),
            on_step=lambda r, s, pw, rw: old.update(rw),
        )
    ]
    layer = RustLayer(itf, RustLaw(thickness=3e-6, k_rust=1e-12), k_iron, pad)
    parts = list(run_schedule(routine_run(model, itf, car, layer, 0.4, sched, numerics=num)))
    assert old.through.any() and (old.through == layer.through).all()
    for a, b in zip(whole, parts):
        assert a.kind == b.kind
        if a.kind == "stop":
            assert b.line_pressure == pytest.approx(a.line_pressure, rel=1e-9)
            assert np.abs(b.rotor_wear - a.rotor_wear).max() < 1e-9 * a.rotor_wear.max()
            assert np.abs(b.pad_wear - a.pad_wear).max() < 1e-8 * a.pad_wear.max()


@pytest.mark.slow
def test_heat_study_closes_energy_and_cones_as_the_field_says(tmp_path):
    """studies/cleaning_heat.py on 8 mm, two stops, the floating caliper as it holds its
    pads: energy closure per stop with road load,
    regeneration and heat on (1e-10; the model's work within its drift), heat = friction
    work (1e-9), the first stop's band temperature within 0.6-1.0 of the slab closed form
    and within 0.08 of the share of the heat the swept slab holds,
    the reduced rotor's ring and hat within 5 % of the ring's rise of the full model's
    and its coning (before its scale to the converged figure) within 15 % of the full
    field's."""
    import cleaning_heat as ch

    r = ch.main(tmp_path, stops=2, size=8.0)
    stops = [x for x in r["rows"] if x["kind"] == "stop"]
    for x in stops:
        assert abs(x["closure"]) < 1e-10
        assert x["regenerated_J"] > 0 and x["road_J"] > 0
        assert abs(x["heat_over_friction"]) < 1e-9
        # the caliper's pads: wear and the faces' thermal strain move r_eff within a stop
        # by 1-1.5 % (duty.md: thermal coupling 0.4-1 %, tested below 2 %)
        assert abs(x["torque_drift"]) < 0.02
    fs = r["first_stop"]
    assert 0.6 < fs["ratio_at_end"] < 1.0
    # the slab keeps all the heat under the band; the ring spreads a third of it beyond
    assert fs["ratio_at_end"] == pytest.approx(fs["slab_heat_share_at_end"], abs=0.08)
    for x in r["rows"]:
        rise = x["ring_C"] - 20.0
        assert abs(x["reduced_ring_C"] - x["ring_C"]) < 0.05 * rise
        assert abs(x["reduced_hat_C"] - x["hat_C"]) < 0.05 * rise
        # the reduced rotor's coning, unscaled, against the full field's (this mesh)
        fe = 0.5 * (x["coning_um"]["in"] + x["coning_um"]["out"])
        assert x["reduced_coning_um"] / r["coning_scale"] == pytest.approx(fe, rel=0.15)
    assert (tmp_path / "figures" / "cleaning_heat.png").exists()
