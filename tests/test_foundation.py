"""Winkler (elastic-foundation) interface: closed forms, balance, calibration, bad input."""
from dataclasses import replace

import numpy as np
import pytest

from brakewear import analytic as an
from brakewear.analytic import johnson_modulus
from brakewear.errors import FoundationError, FoundationSolveError
from brakewear.interfaces import WinklerInterface, calibrate, compare, fe_approach, layer_modulus
from brakewear.model import BrakeModel
from brakewear.static import solve_contact

# ------------------------------------------------------------- sphere ---

def sphere_interface(R, k, half, n):
    """A square patch of foundation (side 2 half, n x n nodes) under a rigid sphere."""
    xs = np.linspace(-half, half, n)
    X, Y = np.meshgrid(xs, xs)
    h = xs[1] - xs[0]
    # tributary areas of a grid: edge nodes half, corners a quarter
    w = np.ones(n)
    w[[0, -1]] = 0.5
    A = np.outer(w, w).ravel() * h * h
    xy = np.vstack([X.ravel(), Y.ravel()])
    return WinklerInterface(xy, A, k, (0.0, 0.0), offset=(xy ** 2).sum(axis=0) / (2 * R)), h


def test_sphere_on_winkler_nodal_pressure_and_contact_radius_exact():
    R, k, F = 0.01, 3e11, 1.0
    wi, h = sphere_interface(R, k, 1e-3, 81)
    res = wi.solve_force(F)
    r = np.hypot(*wi.xy)
    # the closed form at the solved approach, node by node, to round-off
    p_exact = an.winkler_sphere_pressure(r, R, k, res.approach)
    assert np.abs(res.pressure - p_exact).max() <= 1e-12 * p_exact.max()
    # the active set is exactly the disc r < sqrt(2 R delta)
    a = an.winkler_sphere(R, k, delta=res.approach)["a"]
    assert np.array_equal(res.active, r < a)
    assert res.force == pytest.approx(F, rel=1e-12) and res.residual < 1e-12
    # tilts (rad) relative to approach / contact radius, the tilt that would move the rim
    assert np.allclose(res.tilts, 0.0, rtol=0, atol=1e-10 * res.approach / a)
    # Hertz at the same approach: a = sqrt(R delta), sqrt(2) times smaller
    Es = 1e9
    F_h = 4 / 3 * Es * np.sqrt(R) * res.approach ** 1.5
    assert a / an.hertz_sphere(F_h, R, Es)["a"] == pytest.approx(np.sqrt(2), rel=1e-12)


def test_sphere_load_approach_converges_to_closed_form():
    """F = pi k R delta^2 holds for the integral; the nodal sum converges to it."""
    R, k, F = 0.01, 3e11, 1.0
    hs, errs = [], []
    for n in (21, 41, 81, 161):
        wi, h = sphere_interface(R, k, 1e-3, n)
        res = wi.solve_force(F)
        hs.append(h)
        errs.append(abs(res.approach / an.winkler_sphere_approach(F, R, k) - 1))
    rate = np.polyfit(np.log(hs), np.log(errs), 1)[0]
    assert rate > 1.5, f"rate {rate:.2f}, errors {errs}"
    assert errs[-1] < 2e-4, f"finest error {errs[-1]:.2e}"


# -------------------------------------------------------------- brake ---

@pytest.fixture(scope="module")
def model():
    return BrakeModel(size=6e-3, rotor="elastic")


@pytest.fixture(scope="module")
def fe(model):
    return {mu: solve_contact(model, 1e6, mu) for mu in (0.0, 0.4)}


def test_from_model_nodes_areas_modulus(model):
    wi = WinklerInterface.from_model(model)
    g = model.geometry
    from brakewear.mesh.surface import surface_nodes
    assert np.array_equal(wi.nodes, surface_nodes(model.meshes["pad"], "friction"))
    assert wi.area.sum() == pytest.approx(g.pad.area, rel=2e-2)  # faceted arcs
    C33 = g.pad.friction_material.elastic.voigt()[2, 2]
    assert np.allclose(wi.modulus, C33 / g.pad.friction_thickness, rtol=1e-14, atol=0)
    wf = WinklerInterface.from_model(model, rotor="foundation")
    k_r = johnson_modulus(g.rotor.material.elastic.E, g.rotor.material.elastic.nu,
                          0.5 * g.rotor.thickness)
    assert np.allclose(1 / wf.modulus, 1 / wi.modulus + 1 / k_r, rtol=1e-14, atol=0)
    assert wi.lever_arm == pytest.approx(g.pad.friction_thickness + g.pad.backplate_thickness / 2)


def test_flat_pad_under_its_centroid_has_uniform_pressure(model):
    wi = WinklerInterface.from_model(model)
    centroid = (wi.xy * wi.area).sum(axis=1) / wi.area.sum()
    wi = replace(wi, load_point=centroid)
    F = 2500.0
    res = wi.solve_force(F)
    assert res.active.all()
    assert np.abs(res.pressure / (F / wi.area.sum()) - 1).max() < 1e-12
    extent = np.ptp(wi.xy, axis=1).max()     # tilts relative to approach / pad size
    assert np.allclose(res.tilts, 0.0, rtol=0, atol=1e-9 * res.approach / extent)
    assert res.approach == pytest.approx(F / (wi.area.sum() * wi.modulus[0]), rel=1e-12)


def test_moment_balance_centre_of_pressure_is_load_point(model):
    wi = WinklerInterface.from_model(model)
    for lp in (wi.load_point, wi.load_point + [8e-3, 0.0], wi.load_point + [0.0, -30e-3]):
        res = replace(wi, load_point=lp).solve(1e6)
        assert res.force == pytest.approx(1e6 * wi.hydraulic_area, rel=1e-12)
        assert np.abs(res.centre - lp).max() < 1e-12 * np.abs(lp).max(), res.centre - lp
    # far off-centre: part of the pad lifts off, balance still exact
    lp = wi.load_point + [0.0, -45e-3]
    res = replace(wi, load_point=lp).solve(1e6)
    assert 0 < res.active.mean() < 1
    assert np.all(res.pressure[~res.active] == 0)
    assert np.abs(res.centre - lp).max() < 1e-12 * np.abs(lp).max()


def test_friction_moves_centre_of_pressure_to_leading_edge(model):
    wi = WinklerInterface.from_model(model)
    r0, r4 = wi.solve(1e6, 0.0), wi.solve(1e6, 0.4)
    th0, th4 = (np.degrees(np.arctan2(r.centre[1], r.centre[0])) for r in (r0, r4))
    assert th4 < th0 - 2.0, (th0, th4)                      # toward the leading edge
    assert th4 > np.degrees(model.geometry.pad.leading_angle)
    # the exact balance with the friction couple: CoP = load point - lever mu <d>
    fz = wi.area * r4.pressure
    dbar = (wi.drag * fz).sum(axis=1) / fz.sum()
    assert np.abs(r4.centre - (wi.load_point - wi.lever_arm * 0.4 * dbar)).max() < 1e-12
    ref = 0.4 * (wi.drag * fz).sum(axis=1)
    assert np.allclose(r4.friction, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())
    # no lever arm, no tipping
    r4f = replace(wi, lever_arm=0.0).solve(1e6, 0.4)
    assert np.abs(r4f.centre - wi.load_point).max() < 1e-12


def test_gap_from_wear(model):
    wi = WinklerInterface.from_model(model)
    base = wi.solve(1e6)
    x, y = wi.xy - wi.load_point[:, None]
    # a planar gap is a rigid-body motion of the backing: same pressure
    planar = 2e-6 + 1e-4 * x - 3e-5 * y
    res = wi.solve(1e6, gap=planar)
    assert np.abs(res.pressure - base.pressure).max() < 1e-9 * base.pressure.max()
    assert res.approach == pytest.approx(base.approach + 2e-6, rel=1e-9)
    # wear on the leading half unloads it
    worn = np.where(y < 0, 0.5 * base.approach, 0.0)
    res = wi.solve(1e6, gap=worn)
    assert res.pressure[y < 0].mean() < base.pressure[y < 0].mean()
    assert res.force == pytest.approx(base.force, rel=1e-12)


def test_no_equilibrium_raises_clear_error(model):
    wi = WinklerInterface.from_model(model)
    with pytest.raises(FoundationSolveError, match="no equilibrium"):
        replace(wi, load_point=wi.load_point + [0.0, 0.2]).solve(1e6)   # load off the pad
    with pytest.raises(FoundationSolveError, match="outside the contact face"):
        wi.solve(1e6, mu=6.0)                                           # the pad tips over
    # inside the face but the gaps leave three nodes far ahead: still balanced
    gap = np.full(wi.n, 1e-3)
    gap[:3] = 0.0
    res = wi.solve(1e6, gap=gap)
    assert res.residual < 1e-10


def test_bad_input(model):
    wi = WinklerInterface.from_model(model)
    n = wi.n
    for bad in (0.0, -1e11, np.nan):
        with pytest.raises(FoundationError, match="modulus"):
            WinklerInterface.from_model(model, modulus=bad)
    per_node = np.full(n, 1e11)
    per_node[3] = 0.0
    with pytest.raises(FoundationError, match="modulus = 0.0 at node 3"):
        WinklerInterface.from_model(model, modulus=per_node)
    with pytest.raises(FoundationError, match=r"modulus has shape \(5,\)"):
        WinklerInterface.from_model(model, modulus=np.ones(5))
    for bad in (0.0, -1e-3):
        with pytest.raises(FoundationError, match="thickness"):
            johnson_modulus(3e9, 0.25, bad)
        with pytest.raises(FoundationError, match="thickness"):
            layer_modulus(model.geometry.pad.friction_material, bad)
    with pytest.raises(FoundationError, match="E = 0"):
        johnson_modulus(0.0, 0.25, 0.01)
    with pytest.raises(FoundationError, match=rf"gap has shape \({n - 1},\); need \({n},\)"):
        wi.solve(1e6, gap=np.zeros(n - 1))
    with pytest.raises(FoundationError, match="rotor = 'elastic'"):
        WinklerInterface.from_model(model, rotor="elastic")
    with pytest.raises(FoundationError, match="mu = -0.1"):
        wi.solve(1e6, mu=-0.1)
    with pytest.raises(FoundationError, match="line_pressure = 0"):
        wi.solve(0.0)
    with pytest.raises(FoundationError, match="match = 'area'"):
        calibrate(wi, None, match="area")


# -------------------------------------------------------- calibration ---

def test_fe_stiffness_is_load_independent(model, fe):
    """Zero initial gaps: the FE contact is positively homogeneous, so its
    secant stiffness F / w is also the tangent one (the calibration relies on it)."""
    wi = WinklerInterface.from_model(model)
    fe2 = solve_contact(model, 2e6, 0.0)
    k1 = fe[0.0].clamp_force / fe_approach(wi, fe[0.0])
    k2 = fe2.clamp_force / fe_approach(wi, fe2)
    assert k2 == pytest.approx(k1, rel=1e-6)
    assert np.array_equal(fe2.active, fe[0.0].active)


@pytest.mark.parametrize("rotor", ["rigid", "foundation"])
def test_calibrate_stiffness_report(model, fe, rotor):
    wi = WinklerInterface.from_model(model, rotor=rotor)
    for mu, f in fe.items():
        rep = calibrate(wi, f, "stiffness")
        assert rep.matched == "stiffness"
        assert set(rep.errors) == {"stiffness", "contact_area", "peak_pressure",
                                   "cop_distance_m", "cop_dtheta_deg", "cop_dr_m",
                                   "pressure_l2"}
        assert abs(rep.errors["stiffness"]) < 1e-9, rep.errors
        # the rigid backing keeps the whole face in contact, the FE pad does not;
        # figures measured on this mesh (docs/foundation.md has the default mesh)
        assert rep.errors["contact_area"] > 0.1
        assert rep.errors["peak_pressure"] < -0.2
        assert 0.3 < rep.errors["pressure_l2"] < 1.0
        assert rep.errors["cop_distance_m"] < 1e-3
        assert rep.speed_ratio > 10
        res = rep.interface.solve(1e6, mu)
        assert res.force / res.approach == pytest.approx(f.clamp_force / fe_approach(wi, f),
                                                         rel=1e-9)


def test_lever_arm_from_fe_abutment(model, fe):
    """The FE abutment reaction acts low on the backplate's end faces; with its
    height as the lever arm the Winkler friction shift matches the FE's."""
    from brakewear.interfaces import fe_lever_arm
    g = model.geometry.pad
    lever = fe_lever_arm(model, fe[0.4])
    assert g.friction_thickness < lever < g.friction_thickness + 0.5 * g.backplate_thickness
    wi = WinklerInterface.from_model(model)
    geo = calibrate(wi, fe[0.4], "stiffness")                 # geometric mid-height
    cal = calibrate(wi, fe[0.4], "stiffness", model=model)    # FE lever arm
    assert cal.interface.lever_arm == pytest.approx(lever)
    assert cal.summary()["lever_arm_m"] == pytest.approx(lever)
    assert abs(cal.errors["cop_dtheta_deg"]) < 0.5 * abs(geo.errors["cop_dtheta_deg"])
    with pytest.raises(FoundationError, match="mu > 0"):
        fe_lever_arm(model, fe[0.0])


def test_calibrate_pressure_reproduces_fe_and_reports_elsewhere(model, fe):
    wi = WinklerInterface.from_model(model)
    rep = calibrate(wi, fe[0.0], "pressure", model=model)
    assert rep.matched == "pressure"
    assert rep.errors["pressure_l2"] < 1e-10 and abs(rep.errors["stiffness"]) < 1e-10
    assert rep.errors["contact_area"] == 0.0
    # away from its calibration point it is off again: friction it never saw
    other = compare(rep.interface, fe[0.4])
    assert 1e-3 < other["errors"]["pressure_l2"] < 0.5, other["errors"]
    with pytest.raises(FoundationError, match="model="):
        calibrate(wi, fe[0.0], "pressure")


# ------------------------------------------------------------- study ---

def test_study_runs_on_a_coarse_mesh(tmp_path):
    """studies/foundation.py end to end (6 mm mesh): files, speed, lever arm."""
    import importlib.util
    import json
    from pathlib import Path
    spec = importlib.util.spec_from_file_location(
        "foundation_study", Path(__file__).parents[1] / "studies" / "foundation.py")
    study = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(study)
    res = study.main(6.0, out_data=tmp_path, out_fig=tmp_path)
    saved = json.loads((tmp_path / "foundation_study.json").read_text())
    assert saved["sphere"]["nodal_solve"]["active_set_is_disc_r_lt_sqrt_2R_delta"]
    assert min(res["speed_ratio"]["fe_first_over_winkler"].values()) > 100
    sh = res["friction_shift"]
    # the FE lever arm brings the Winkler shift closer to the FE's than the geometric one
    assert (abs(sh["winkler_fe_lever"]["cop_shift_deg"] - sh["fe"]["cop_shift_deg"])
            < abs(sh["winkler"]["cop_shift_deg"] - sh["fe"]["cop_shift_deg"]))
    assert (tmp_path / "foundation_pressure.png").stat().st_size > 10_000
    assert (tmp_path / "foundation_profile.csv").read_text().startswith("theta_deg,")


def test_a_fixed_caliper_presses_the_foundation_with_all_its_pistons():
    """Two pistons on one side: the line pressure acts on the sum of their
    hydraulic areas (``geometry.clamp_area``), as in the FE model."""
    from brakewear.geometry import CaliperGeometry, load_geometry
    g = load_geometry("default")
    p1 = replace(g.piston, diameter=0.040, rim_inner_diameter=0.036, bore_diameter=0.040,
                 radius=0.119, angle=np.radians(-12.0))
    fixed = replace(g, caliper=CaliperGeometry("fixed"), piston=p1,
                    extra_pistons=(replace(p1, angle=np.radians(12.0)),))
    itf = WinklerInterface.from_model(BrakeModel(fixed, size=12e-3, rotor="rigid"))
    assert itf.hydraulic_area == pytest.approx(2 * p1.hydraulic_area, rel=1e-15)
    res = itf.solve(1e6)
    assert float((res.pressure * itf.area).sum()) == pytest.approx(
        1e6 * fixed.clamp_area, rel=1e-9)
