"""The bedded state (brakewear.cleaning.bedding, brakewear.cleaning.steady): the steady
state of Archard wear solved directly against its closed form (``p r`` constant on pads
held square) and against the bedding history it stands for."""
from dataclasses import replace

import numpy as np
import pytest

from brakewear import CondensedInterface, ConvergenceError, WearError, load_geometry
from brakewear.cleaning import bedding as bd
from brakewear.cleaning.steady import bedded_gap
from brakewear.geometry import SupportGeometry
from brakewear.model import BrakeModel

K_PAD, K_IRON = 5e-15, 5e-16


@pytest.fixture(scope="module")
def held():
    g = replace(load_geometry("floating"), support=SupportGeometry())
    m = BrakeModel(g, size=12e-3, layout="full", rotor="elastic")
    return m, CondensedInterface(m, 1e6, 0.4, cache=False)


def _solve(itf, m, **kw):
    g = m.geometry
    return bedded_gap(itf, bd.BeddingDuty((1.5e6,), (1.0,), (0.0,)), mu=0.4, k_pad=K_PAD,
                      k_rotor=K_IRON, band=(g.pad.inner_radius, g.pad.outer_radius),
                      thickness=g.rotor.thickness, **kw)


def test_pads_held_square_bed_to_p_r_constant_in_a_few_dozen_solves(held):
    """On pads held square the steady state is p r constant (the rotor's wear, a tenth of
    the pad's, adds its rings' average of it): each face's effective radius is the band's
    mid radius (95-138 mm: 116.5 mm) within 0.3 mm, and p r is flat within 5 % (rms)."""
    m, itf = held
    st = _solve(itf, m)
    assert st.solves <= 60 and st.residuals[-1] <= 5e-3
    t = m.geometry.rotor.thickness
    for face, flat in zip(bd.face_masks(itf, t), bd.face_masks(itf, t, on_face=True)):
        p = st.pressure[face]
        load = p * itf.area[face]
        r_eff = load @ itf.r[face] / load.sum()
        assert r_eff == pytest.approx(0.1165, abs=0.3e-3), r_eff
        pr = (st.pressure * itf.r)[flat]
        assert np.sqrt(np.average((pr / pr.mean() - 1) ** 2, weights=itf.area[flat])) < 0.05
        assert st.gap[face].min() == 0.0           # each face touches
    # a new flat pad is far from it: the bedding moved the radius by millimetres
    new = itf.solve(np.zeros(itf.area.size), None, mu=0.4).pressure
    radii = bd.face_radii(new, itf, bd.face_masks(itf, t))
    assert max(abs(r - 0.1165) for r in radii) > 2e-3


def test_a_hot_duty_beds_the_reverse_of_its_coning(held):
    """Bedded under a thermal coning c, the pads' gap against the cold rotor holds -c
    (the coning's reverse) up to the elastic shape: the inboard gap rises toward the
    inner radius by about c across the band, the outboard one toward the outer."""
    m, itf = held
    g = m.geometry
    band, t = (g.pad.inner_radius, g.pad.outer_radius), g.rotor.thickness
    cold = _solve(itf, m)
    hot = bedded_gap(itf, bd.BeddingDuty((1.5e6,), (1.0,), (40e-6,)), mu=0.4, k_pad=K_PAD,
                     k_rotor=K_IRON, band=band, thickness=t)
    diff = hot.gap - cold.gap
    for face, sign in zip(bd.face_masks(itf, t, on_face=True), (-1.0, 1.0)):
        slope = np.polyfit(itf.r[face], diff[face], 1)[0] * (band[1] - band[0])
        assert slope == pytest.approx(sign * 40e-6, rel=0.1), slope


def test_the_bedded_gap_of_pads_held_square_scales_with_the_load(held):
    """The pads held square are linear: the steady pressure, and the gap that carries it,
    scale with the line pressure (a draw's bedded gap is its level's, scaled:
    brakewear.cleaning.sample), to the solve's tolerance."""
    m, itf = held
    g = m.geometry
    kw = dict(mu=0.4, k_pad=K_PAD, k_rotor=K_IRON, band=(g.pad.inner_radius,
              g.pad.outer_radius), thickness=g.rotor.thickness, tol=1e-4, max_iter=200)
    one = bedded_gap(itf, bd.BeddingDuty((1e6,), (1.0,), (0.0,)), **kw)
    two = bedded_gap(itf, bd.BeddingDuty((2e6,), (1.0,), (0.0,)), **kw)
    assert np.abs(two.gap - 2 * one.gap).max() < 0.01 * np.abs(two.gap).max()
    assert bd.pressure_change(two.pressure, 2 * one.pressure, itf.area) < 1e-3


def test_a_state_that_does_not_settle_raises_with_its_figures(held):
    m, itf = held
    with pytest.raises(ConvergenceError, match="did not settle in 2 iterations"):
        _solve(itf, m, max_iter=2)
    with pytest.raises(WearError, match="k_pad = 0"):
        bedded_gap(itf, bd.BeddingDuty((1e6,), (1.0,), (0.0,)), mu=0.4, k_pad=0.0,
                   band=(0.095, 0.138))
    with pytest.raises(WearError, match="one weight and one coning per line pressure"):
        bd.BeddingDuty((1e6, 2e6), (1.0,), (0.0,))


def test_the_duty_mean_weighs_by_the_angle_slid():
    d = bd.BeddingDuty((1e6, 3e6), (3.0, 1.0), (0.0, 40e-6)).mean()
    assert d.line_pressure == (pytest.approx(1.5e6),) and d.coning == (pytest.approx(10e-6),)


@pytest.mark.slow
def test_the_direct_solve_is_the_bedding_history():
    """studies/cleaning_bedding.py on the pads held square (8 mm), cold and hot: the
    bedding history (blocks of five stops from 80 km/h at 3 m/s^2 through the study car's
    blending, 60 s apart, each application five of them; hot: the stops' heat cones the
    rotor) until the first cold stop's pressure changes by less than 0.2 % over a block,
    and the direct solve of its duty: the first cold stop's pressure maps within 5 % (L2),
    each face's effective radius within 0.5 mm, the direct solve in at most 100 contact
    solves.  Hot, the pads bed to the coning's reverse: against the cold rotor the inboard
    pad bears outward of the mid radius and the outboard one inward."""
    from studyload import load_study

    study = load_study("cleaning_bedding")
    for hot in (False, True):
        r = study.main(brake="held", size=8.0, hot=hot)
        assert r["history"]["settled"]
        assert r["l2_direct_vs_history"] < 0.05, r["l2_direct_vs_history"]
        for a, b in zip(r["radii_history_mm"], r["radii_direct_mm"]):
            assert abs(a - b) < 0.5
        assert r["direct"]["solves"] <= 100
    inboard, outboard = r["radii_direct_mm"]
    assert inboard > r["mid_radius_mm"] + 5 > r["mid_radius_mm"] - 5 > outboard
