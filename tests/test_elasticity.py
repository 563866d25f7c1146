"""Elasticity: the fast assembly against scikit-fem's forms, constraints, loads, stress."""
import numpy as np
import pytest
import skfem as fem

from brakewear.errors import MeshError
from brakewear.fem import (
    apply_dirichlet,
    assemble_pressure,
    assemble_stiffness,
    assemble_traction,
    boundary_dofs,
    elasticity_form,
    element_stress,
    scalar_element,
    thermal_strain_form,
    von_mises,
)
from brakewear.materials import Isotropic, MaterialError, TransverselyIsotropic, get_material
from brakewear.mesh import annulus_mesh, mapped_mesh, structured_tets
from brakewear.solvers import direct_solve, rigid_body_modes


def box(n=(3, 2, 2), L=(1.0, 0.5, 0.4), order=1):
    p, t = structured_tets(*(np.linspace(0, Li, ni + 1) for Li, ni in zip(L, n)))
    m = mapped_mesh(p, t, lambda x: x, order=order)
    return m.with_boundaries({"x0": lambda x: x[0] < 1e-9, "x1": lambda x: x[0] > L[0] - 1e-9})


@pytest.mark.parametrize("order", [1, 2])
def test_fast_assembly_matches_skfem_form(order):
    m = annulus_mesh(1.0, 2.0, 0.5, 2, 8, 2, angle=np.pi / 2, order=order)
    half = np.arange(m.nelements) < m.nelements // 2
    C1, C2 = get_material("pad_resin").voigt(), get_material("steel").voigt()
    K, _ = assemble_stiffness(m, [(np.nonzero(half)[0], C1), (np.nonzero(~half)[0], C2)],
                              chunk=29)
    el = fem.ElementVector(scalar_element(m))
    q = 1 if order == 1 else 4
    Kr = elasticity_form(C1).assemble(
        fem.Basis(m, el, intorder=q, elements=np.nonzero(half)[0])
    ) + elasticity_form(C2).assemble(fem.Basis(m, el, intorder=q, elements=np.nonzero(~half)[0]))
    err = abs(K.tocsr() - Kr).max() / abs(Kr).max()
    assert err < 1e-13, f"fast assembly differs from skfem by {err:.2e}"


def test_pattern_reuse_and_rigid_body_nullspace():
    m = box()
    K1, pat = assemble_stiffness(m, get_material("steel"))
    K2, pat2 = assemble_stiffness(m, get_material("steel"), pattern=pat)
    assert pat2 is pat and abs(K1 - K2).max() == 0
    B = rigid_body_modes(m.p)
    assert np.abs(K1 @ B).max() < 1e-12 * abs(K1).max()
    assert np.linalg.matrix_rank(B) == 6


def test_material_groups_must_cover_mesh():
    m = box()
    with pytest.raises(ValueError, match="cover"):
        assemble_stiffness(m, [(np.arange(3), get_material("steel"))])


@pytest.mark.parametrize("order", [1, 2])
def test_linear_patch_test_is_exact(order):
    """A linear displacement field imposed on the boundary is reproduced inside."""
    m = box(order=order)
    mat = get_material("pad_resin").elastic
    K, _ = assemble_stiffness(m, mat)
    X = fem.Basis(m, scalar_element(m), intorder=1).doflocs
    G = np.array([[1e-3, 2e-4, -1e-4], [3e-4, -5e-4, 2e-4], [1e-4, 0.0, 4e-4]])
    u_ex = (G @ X).T.ravel()
    bnd = np.unique(np.concatenate([boundary_dofs(m, m.boundary_facets())]))
    Kd, fd = apply_dirichlet(K, np.zeros(K.shape[0]), bnd, u_ex[bnd])
    u = direct_solve(Kd, fd)
    assert np.abs(u - u_ex).max() < 1e-10 * np.abs(u_ex).max()
    s = element_stress(m, u, mat)
    eps = np.array(
        [G[0, 0], G[1, 1], G[2, 2], G[1, 2] + G[2, 1], G[0, 2] + G[2, 0], G[0, 1] + G[1, 0]]
    )
    # relative to the stress magnitude: a zero component carries round-off of
    # order 1e-9 of the largest one, which an absolute tolerance in Pa cannot judge
    s_ex = (mat.voigt() @ eps)[:, None]
    assert np.abs(s - s_ex).max() <= 1e-8 * np.abs(s_ex).max()


def test_apply_dirichlet_keeps_symmetry_and_values():
    m = box()
    K, _ = assemble_stiffness(m, get_material("steel"))
    f = np.random.default_rng(0).normal(size=K.shape[0])
    d = boundary_dofs(m, "x0")
    Kd, fd = apply_dirichlet(K, f, d, 1e-3)
    assert abs(Kd - Kd.T).max() < 1e-12 * abs(K).max()
    u = direct_solve(Kd, fd)
    assert np.allclose(u[d], 1e-3, rtol=1e-12, atol=0)     # the prescribed 1 mm
    free = np.setdiff1d(np.arange(K.shape[0]), d)
    scale = abs(K).max() * np.abs(u).max()
    assert np.abs((K @ u - f)[free]).max() < 1e-12 * scale
    # input untouched
    K2, _ = assemble_stiffness(m, get_material("steel"))
    assert abs(K - K2).max() == 0


def test_boundary_dofs_unknown_name():
    with pytest.raises(MeshError, match="x9"):
        boundary_dofs(box(), "x9")


def test_traction_and_pressure_loads_total_force():
    m = box(order=2)
    f = assemble_traction(m, "x1", (1e6, 0, -2e6))
    A = 0.5 * 0.4
    assert f[0::3].sum() == pytest.approx(1e6 * A) and f[2::3].sum() == pytest.approx(-2e6 * A)
    fp = assemble_pressure(m, "x1", 3e6)  # pushes against the outward normal (+x) -> -x
    assert fp[0::3].sum() == pytest.approx(-3e6 * A)


def test_free_thermal_expansion_is_stress_free():
    m = box()
    mat = get_material("grey_cast_iron")
    K, _ = assemble_stiffness(m, mat)
    alpha, dT = mat.thermal.alpha, 80.0
    vb = fem.Basis(m, fem.ElementVector(fem.ElementTetP1()), intorder=1)
    f = thermal_strain_form(mat.voigt(), alpha).assemble(vb, dT=dT)
    u_free = (alpha * dT * m.p).T.ravel()
    res = np.abs(K @ u_free - f).max() / np.abs(f).max()
    assert res < 1e-10, f"free expansion not in equilibrium with the thermal load: {res:.2e}"
    sig = element_stress(m, u_free, mat) - (mat.voigt() @ np.r_[[alpha * dT] * 3, [0] * 3])[:, None]
    assert np.abs(sig).max() < 1e-10 * mat.elastic.E * alpha * dT


def test_bar_held_at_both_ends_gets_minus_E_alpha_dT():
    m = box(n=(6, 2, 2))
    mat = Isotropic(E=210e9, nu=0.3)
    alpha, dT = 1.2e-5, 50.0
    K, _ = assemble_stiffness(m, mat)
    vb = fem.Basis(m, fem.ElementVector(fem.ElementTetP1()), intorder=1)
    f = thermal_strain_form(mat.voigt(), alpha).assemble(vb, dT=dT)
    # ends held axially; one point on x0 pinned laterally, lateral rotation stopped
    fixed = np.concatenate([boundary_dofs(m, "x0", [0]), boundary_dofs(m, "x1", [0])])
    corner = np.nonzero(np.all(m.p < 1e-12, axis=0))[0][0]
    side = np.nonzero((m.p[0] < 1e-12) & (m.p[1] < 1e-12) & (m.p[2] > 0.39))[0][0]
    sidey = np.nonzero((m.p[0] < 1e-12) & (m.p[1] > 0.49) & (m.p[2] < 1e-12))[0][0]
    fixed = np.unique(np.concatenate([fixed, [3 * corner + 1, 3 * corner + 2, 3 * side + 1,
                                              3 * sidey + 2]]))
    Kd, fd = apply_dirichlet(K, f, fixed)
    u = direct_solve(Kd, fd)
    s = element_stress(m, u, mat) - (mat.voigt() @ np.r_[[alpha * dT] * 3, [0] * 3])[:, None]
    expected = -mat.E * alpha * dT
    assert np.allclose(s[0], expected, rtol=1e-8, atol=0), (
        f"sigma_xx {s[0].min()}..{s[0].max()} vs {expected}"
    )
    assert np.abs(s[1:]).max() < 1e-8 * abs(expected)


def test_von_mises_of_uniaxial_and_hydrostatic():
    assert von_mises(np.array([5.0, 0, 0, 0, 0, 0])) == pytest.approx(5.0)
    assert von_mises(np.array([3.0, 3.0, 3.0, 0, 0, 0])) == pytest.approx(0.0, abs=1e-12 * 3.0)


def test_material_validation():
    with pytest.raises(MaterialError, match="nu"):
        Isotropic(E=1e9, nu=0.5)
    with pytest.raises(MaterialError, match="E"):
        Isotropic(E=-1.0, nu=0.3)
    with pytest.raises(MaterialError, match="positive definite"):
        TransverselyIsotropic(E_p=10e9, E_t=0.1e9, nu_p=0.3, nu_tp=0.45, G_t=1e9)
    with pytest.raises(MaterialError, match="known materials"):
        get_material("unobtainium")
    # transversely isotropic with equal constants is isotropic
    ti = TransverselyIsotropic(E_p=5e9, E_t=5e9, nu_p=0.25, nu_tp=0.25, G_t=5e9 / 2.5)
    iso = Isotropic(5e9, 0.25).voigt()
    assert np.allclose(ti.voigt(), iso, rtol=1e-10, atol=1e-12 * np.abs(iso).max())
