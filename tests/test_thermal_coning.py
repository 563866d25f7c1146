"""Thermal coning (brakewear.thermal.hat_cone, studies/thermal_coning.py): the closed forms,
the free plate's stress-free dish, the hat rotor's cone against the axisymmetric model and
the closed forms, on small settings."""
from __future__ import annotations

import json

import numpy as np
import pytest
import skfem as fem

from brakewear.geometry import load_geometry
from brakewear.mesh import rotor_mesh
from brakewear.thermal import hat_cone as hc
from brakewear.thermal.strain import thermal_load, thermal_load_matrix
from studyload import load_study

tc = load_study("thermal_coning")


def test_shell_edge_stiffness_long_shell_is_the_semi_infinite_one():
    beta, D = hc.shell_constants(110e9, 0.27, 0.087, 0.006)
    k_inf = hc.shell_edge_stiffness(beta, D)
    k_long = hc.shell_edge_stiffness(beta, D, 12.0 / beta)
    assert np.allclose(k_long, k_inf, rtol=1e-4), (k_long, k_inf)
    k_short = hc.shell_edge_stiffness(beta, D, 2.0 / beta)
    assert np.allclose(k_short, k_short.T, rtol=1e-10)
    assert np.all(np.linalg.eigvalsh(k_short) > 0)
    # a clamped far end stiffens a short shell
    assert k_short[0, 0] > k_inf[0, 0] and k_short[1, 1] > k_inf[1, 1]


def test_annulus_edge_narrow_ring_limit():
    """A narrow annulus stores only hoop strain: s -> ln(a/b) / b."""
    b, nu = 0.1, 0.27
    err = [abs(hc.annulus_edge(b, b + w, nu) * b / np.log((b + w) / b) - 1) for w in (1e-2, 1e-3)]
    assert err[0] < 0.5 * 1e-2 / b and err[1] < 0.12 * err[0], err  # first order in the width
    s, slope, rise = hc.annulus_edge(b, 0.15, nu, np.array([b, 0.15]))
    assert slope[0] == pytest.approx(1.0) and rise[0] == 0.0 and 0 < slope[1] < 1


def test_thermal_load_reuses_the_library_matrix():
    g = load_geometry("default")
    m = rotor_mesh(g, size=0.016, full=True)
    T = np.random.default_rng(0).uniform(0, 100, m.nvertices)
    mat = g.rotor.material
    ref = thermal_load_matrix(m, mat) @ T
    assert np.allclose(thermal_load(m, mat, T), ref, rtol=0, atol=1e-12 * np.abs(ref).max())


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    out = tmp_path_factory.mktemp("coning")
    res = tc.main(out=out, plate_sizes=(0.016, 0.012), hat_sizes=(0.012,), axi_sizes=(0.002, 0.001),
                  figures=True)
    return out, res


def test_free_plate_bends_into_the_stress_free_dish(study):
    _, res = study
    coarse, fine = res["plate"]
    # kappa = alpha dT / t, P2
    assert fine["kappa_error"] < 0.01, f"curvature error {fine['kappa_error']:.2e}"
    assert fine["kappa_error"] < 0.8 * coarse["kappa_error"], (coarse, fine)
    # nearly stress-free: a few % of the fully restrained thermal stress, falling
    assert fine["stress_ratio"] < 0.03 and fine["stress_ratio"] < coarse["stress_ratio"]
    # the 3-2-1 support takes no load: the thermal load is self-equilibrated
    assert fine["reaction_ratio"] < 1e-8


def test_hat_cone_against_the_axisymmetric_model_and_the_closed_form(study):
    _, res = study
    axi, est = res["axisymmetric"], res["estimate"]
    assert axi["cone_mrad"] < 0, "the outer edge moves toward the hat"
    assert abs(axi["richardson_change"]) < 0.01, axi
    (h3,) = res["hat"]
    # 3D P2 at 12 mm (hat 6 mm) against the converged section model
    assert abs(h3["diff_vs_axisymmetric"]) < 0.06, h3
    # closed forms: annular plate on a shell within 15 %, rigid section within 30 %
    assert abs(est["plate"]["diff_vs_axisymmetric"]) < 0.15, est["plate"]
    assert abs(est["rigid"]["diff_vs_axisymmetric"]) < 0.30, est["rigid"]
    assert abs(est["plate"]["runout_diff_vs_axisymmetric"]) < 0.15, est["plate"]


def test_results_written(study):
    out, res = study
    data = json.loads((out / "data" / "thermal_coning.json").read_text())
    assert data["per_100K"]["cone_mrad"] == pytest.approx(res["per_100K"]["cone_mrad"])
    assert (out / "figures" / "thermal_coning.png").stat().st_size > 10_000


def test_axisymmetric_model_converges():
    g = tc.hat_geometry()
    cones = [hc.axisymmetric_cone(g, 100.0, h)["cone"] for h in (0.004, 0.002, 0.001)]
    d1, d2 = abs(cones[1] - cones[0]), abs(cones[2] - cones[1])
    assert d2 < 0.7 * d1 and d2 < 0.01 * abs(cones[2]), cones
    # the section is clamped on the bolt-circle annulus only
    m = hc.section_mesh(g, 0.002)
    clamp = fem.FacetBasis(m, fem.ElementTriP1(), facets=m.boundaries["clamp"]).dx.sum()
    assert clamp == pytest.approx(g.rotor.hat.bolt_circle_radius - g.rotor.hat.bore_radius)


def test_the_docstring_examples_run():
    import doctest

    res = doctest.testmod(hc)
    assert res.attempted >= 1 and res.failed == 0


def test_a_heated_subdomain_load_is_self_equilibrated_and_refuses_an_unknown_one():
    from brakewear.errors import ThermalError
    from brakewear.model import BrakeModel
    from brakewear.thermal.strain import heated_subdomain_load

    model = BrakeModel("floating", size=12e-3, layout="full")
    f = heated_subdomain_load(model, "rotor", "ring", 100.0).reshape(-1, 3)
    # a free thermal strain loads nothing as a whole: each direction sums to zero
    assert np.abs(f.sum(axis=0)).max() < 1e-9 * np.abs(f).sum()
    off, n = model.offsets["rotor"], model.meshes["rotor"].nvertices
    assert np.abs(f[off:off + n]).sum() > 0 and not np.delete(f, np.s_[off:off + n], 0).any()
    with pytest.raises(ThermalError, match="no subdomain 'hub'"):
        heated_subdomain_load(model, "rotor", "hub", 100.0)
    with pytest.raises(ThermalError, match="materials"):
        heated_subdomain_load(model, "pad", "friction_layer", 100.0)
