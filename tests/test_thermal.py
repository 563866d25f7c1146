"""Heat conduction, frictional heating and thermal strain (brakewear.thermal).

Closed forms: steady slab under flux (exact for P1), the half-space under
constant flux (convergence in space and in time), free thermal expansion
(stress-free) and the bar held at both ends (sigma = -E alpha dT).  The brake:
energy balance of every step, the rotor's revolution average, the staggered
thermoelastic coupling, bad input.
"""
import dataclasses
import subprocess
import sys

import numpy as np
import pytest
import skfem as fem

from brakewear import analytic as an
from brakewear import static
from brakewear.contact import solve_contact
from brakewear.errors import ThermalError
from brakewear.fem import (
    HeatConduction,
    apply_dirichlet,
    assemble_stiffness,
    boundary_dofs,
    thermal_strain_form,
)
from brakewear.laws.base import FrictionLaw
from brakewear.materials import MATERIALS
from brakewear.model import BrakeModel
from brakewear.solvers import direct_solve
from brakewear.thermal import (
    ThermalModel,
    heat_flux,
    partition_effusivity,
    staggered_amplification,
    thermal_load_matrix,
    thermal_stress,
)

PAD = MATERIALS["pad_resin"]


def box(nx, ny, nz, L=(0.02, 1e-3, 1e-3), x=None, perturb=0.0, seed=0):
    """A box [0, Lx] x [0, Ly] x [0, Lz] with faces x0, x1, y0, y1, z0, z1."""
    xs = np.linspace(0, L[0], nx + 1) if x is None else x
    m = fem.MeshTet.init_tensor(xs, np.linspace(0, L[1], ny + 1), np.linspace(0, L[2], nz + 1))
    if perturb:
        # move interior nodes in y and z only: the x-planes stay planes
        rng = np.random.default_rng(seed)
        p = m.p.copy()
        inner = (p[1] > 1e-12) & (p[1] < L[1] - 1e-12) & (p[2] > 1e-12) & (p[2] < L[2] - 1e-12)
        p[1:, inner] += perturb * rng.uniform(-1, 1, (2, inner.sum())) * np.array(
            [[L[1] / ny], [L[2] / nz]])
        m = fem.MeshTet(p, m.t)
    tol = 1e-9 * max(L)
    return m.with_boundaries({
        "x0": lambda X: X[0] < tol, "x1": lambda X: X[0] > L[0] - tol,
        "y0": lambda X: X[1] < tol, "y1": lambda X: X[1] > L[1] - tol,
        "z0": lambda X: X[2] < tol, "z1": lambda X: X[2] > L[2] - tol})


# ------------------------------------------------------------ steady slab ---

@pytest.mark.parametrize("mesh", ["uniform", "graded", "distorted"])
def test_steady_slab_with_flux_is_exact(mesh):
    """P1 reproduces the linear exact solution on any mesh: error at round-off."""
    q, L, T0 = 2e5, 0.0105, 300.0
    th = PAD.thermal
    x = {"uniform": np.linspace(0, L, 9), "graded": L * np.linspace(0, 1, 9) ** 2,
         "distorted": np.linspace(0, L, 7)}[mesh]
    m = box(len(x) - 1, 3, 3, L=(L, 4e-3, 4e-3), x=x, perturb=0.3 if mesh == "distorted" else 0)
    body = HeatConduction(m, PAD, flux_facets="x0", fixed={"x1": T0}, name="slab")
    T = body.steady(body.flux_load(np.full(body.face.size, q)))
    exact = an.slab_temperature(m.p[0], q, L, th.kappa, T0)
    err = np.abs(T - exact).max() / (q * L / th.kappa)
    assert err < 1e-10, f"{mesh}: max error {err:.2e} of the rise q L / kappa"
    bal = body.balance(None, T, body.flux_load(np.full(body.face.size, q)), None)
    assert bal["to_fixed_W"] == pytest.approx(q * 16e-6, rel=1e-10), bal
    assert bal["relative_error"] < 1e-10


def test_steady_slab_with_convection():
    """Flux in at x = 0, convection h at x = L: T(L) = T_amb + q / h, linear inside."""
    q, L, h, Ta = 1e4, 0.01, 80.0, 293.15
    m = box(6, 2, 2, L=(L, 3e-3, 3e-3))
    body = HeatConduction(m, PAD, flux_facets="x0", convection={"x1": h}, T_ambient=Ta)
    F = body.flux_load(np.full(body.face.size, q))
    T = body.steady(F)
    exact = an.slab_temperature(m.p[0], q, L, PAD.thermal.kappa, Ta + q / h)
    assert np.abs(T - exact).max() < 1e-9 * (q / h), np.abs(T - exact).max()
    assert body.balance(None, T, F, None)["relative_error"] < 1e-10


# ------------------------------------------------------ semi-infinite body ---

Q_SI, T_PROBE, L_SI, T_AMB = 1e5, 10.0, 0.02, 300.0


def _half_space(nx, nsteps, mass="consistent"):
    """Surface temperature at T_PROBE of a 20 mm bar (7 diffusion lengths) heated at x = 0."""
    m = box(nx, 1, 1, L=(L_SI, 1e-3, 1e-3))
    body = HeatConduction(m, PAD, flux_facets="x0", mass=mass, T_ambient=T_AMB)
    T = np.full(body.n, T_AMB)
    F = body.flux_load(np.full(body.face.size, Q_SI))
    for _ in range(nsteps):
        T = body.step(T, F, T_PROBE / nsteps)
    assert body.factorizations == 1  # one factorisation for all steps of one size
    return T[body.face].mean()


def _rel_error(T):
    th = PAD.thermal
    exact = an.semi_infinite_surface_temperature(T_PROBE, Q_SI, th.kappa, th.rho, th.c, T_AMB)
    return abs(T - exact) / (exact - T_AMB)


def test_half_space_converges_in_space():
    """h -> 0 at a small time step (2000 steps): rate ~2 (P1), within 2 % from 1 mm cells."""
    nx = np.array([5, 10, 20, 40])
    err = np.array([_rel_error(_half_space(n, 2000)) for n in nx])
    rate = np.polyfit(np.log(L_SI / nx), np.log(err), 1)[0]
    assert rate > 1.8, f"space rate {rate:.2f}, errors {err}"
    assert err[-1] < 1.5e-3, f"finest (0.5 mm) error {err[-1]:.2e}"
    assert np.all(err[1:] < 0.02), f"errors {err}"


def test_half_space_converges_in_time():
    """dt -> 0 on a fine mesh (0.0625 mm): implicit Euler, rate ~1; within 2 % at 10 steps."""
    n = np.array([10, 20, 40, 80])
    err = np.array([_rel_error(_half_space(320, k)) for k in n])
    rate = np.polyfit(np.log(T_PROBE / n), np.log(err), 1)[0]
    assert 0.9 < rate < 1.1, f"time rate {rate:.2f}, errors {err}"
    assert err[-1] < 2e-3, f"finest (80 steps) error {err[-1]:.2e}"
    assert err[0] < 0.02, f"10 steps: error {err[0]:.2e}"


def test_lumped_capacity_also_converges():
    err = [_rel_error(_half_space(n, 400, "lumped")) for n in (10, 20, 40)]
    assert err[2] < err[1] < err[0] and err[2] < 5e-3, err


# ------------------------------------------------------- thermal strain ---

def test_thermal_load_matrix_equals_thermal_strain_form():
    m = box(3, 2, 2, L=(3e-3, 2e-3, 2e-3))
    dT = np.random.default_rng(1).uniform(-50, 200, m.nvertices)
    G = thermal_load_matrix(m, PAD)
    vb = fem.Basis(m, fem.ElementVector(fem.ElementTetP1()), intorder=2)
    sb = fem.Basis(m, fem.ElementTetP1(), intorder=2)
    f = thermal_strain_form(PAD.voigt(), PAD.thermal.alpha).assemble(vb, dT=sb.interpolate(dT))
    assert np.abs(G @ dT - f).max() < 1e-12 * np.abs(f).max()


def _thermal_solve(m, mat, dT, fixed):
    K, _ = assemble_stiffness(m, mat)
    f = thermal_load_matrix(m, mat) @ np.full(m.nvertices, dT)
    Kd, fd = apply_dirichlet(K, f, fixed)
    u = direct_solve(Kd, fd)
    return u, thermal_stress(m, u, mat, np.full(m.nvertices, dT))


@pytest.mark.parametrize("name", ["steel", "pad_resin"])
def test_free_expansion_is_stress_free(name):
    """Uniform dT, only symmetry planes held: u = alpha dT x, no stress (isotropic alpha,
    isotropic or transversely isotropic C)."""
    mat, dT = MATERIALS[name], 150.0
    m = box(4, 3, 3, L=(0.02, 0.01, 0.008), perturb=0.2)
    fixed = np.concatenate([boundary_dofs(m, "x0", [0]), boundary_dofs(m, "y0", [1]),
                            boundary_dofs(m, "z0", [2])])
    u, s = _thermal_solve(m, mat, dT, fixed)
    scale = np.abs(mat.voigt() @ [1, 1, 1, 0, 0, 0]).max() * mat.thermal.alpha * dT
    assert np.abs(s).max() < 1e-10 * scale, f"stress {np.abs(s).max():.3e} vs {scale:.3e}"
    assert np.abs(u.reshape(-1, 3).T - mat.thermal.alpha * dT * m.p).max() < 1e-10 * (
        mat.thermal.alpha * dT * 0.02)


def test_bar_held_at_both_ends():
    """Both ends held axially, sides free: sigma_xx = -E alpha dT, all else zero."""
    mat, dT = MATERIALS["steel"], 80.0
    m = box(6, 2, 2, L=(0.05, 0.01, 0.01))
    fixed = np.concatenate([boundary_dofs(m, "x0", [0]), boundary_dofs(m, "x1", [0]),
                            boundary_dofs(m, "y0", [1]), boundary_dofs(m, "z0", [2])])
    _, s = _thermal_solve(m, mat, dT, fixed)
    E, alpha = mat.elastic.E, mat.thermal.alpha
    expect = -E * alpha * dT
    assert np.abs(s[0] - expect).max() < 1e-10 * abs(expect), s[0][:3]
    assert np.abs(s[1:]).max() < 1e-10 * abs(expect)


# ------------------------------------------------------------ the brake ---

MU, OMEGA = 0.4, 50.0


@pytest.fixture(scope="module")
def brake():
    m = BrakeModel(size=8e-3)
    return m, static.solve_contact(m, 1e6, mu=MU)


def test_partition_formula():
    e_p, e_r = PAD.thermal.effusivity, MATERIALS["grey_cast_iron"].thermal.effusivity
    g = partition_effusivity(PAD, MATERIALS["grey_cast_iron"])
    assert g == pytest.approx(e_p / (e_p + e_r), rel=1e-14)
    assert 0.1 < 1 - g < 0.9 and 1 - g > 0.8  # docs/references.md: 0.8-0.9 into a cast-iron rotor
    ga = partition_effusivity(PAD, MATERIALS["grey_cast_iron"], area_ratio=55 / 360)
    assert ga == pytest.approx(e_p * 55 / 360 / (e_p * 55 / 360 + e_r), rel=1e-14)


def test_energy_balance_every_step(brake):
    """Heat into the bodies = friction power (= torque x omega), and heat in =
    stored + convected, to 1e-8 in every step of a drag and at steady state."""
    m, r = brake
    th = ThermalModel(m, contact_conductance=0.0)
    q = th.flux(r.interface_pressure, MU, OMEGA)
    x = m.meshes["pad"].p[:, r.interface_nodes]
    torque_power = MU * OMEGA * float(np.hypot(x[0], x[1]) @ r.interface_force[2])
    for dt in (0.1, 0.1, 1.0, 5.0, 30.0):
        th.step(q, dt)
        b = th.heat_balance()
        assert b["friction_power_W"] == pytest.approx(torque_power, rel=1e-10)
        assert b["partition_error"] < 1e-8, b
        assert b["relative_error"] < 1e-8, b
        assert b["bodies"]["pad"]["heat_in_W"] == pytest.approx(
            th.partition * torque_power, rel=1e-8)
    assert th.heat["pad"].factorizations == 4  # one per distinct dt
    th.steady(q)
    b = th.heat_balance()
    assert b["relative_error"] < 1e-8 and b["bodies"]["rotor"]["stored_W"] == 0.0, b


def test_rigid_rotor_share_leaves_the_model():
    m = BrakeModel(size=8e-3, rotor="rigid")
    th = ThermalModel(m, partition=0.3)
    assert th.bodies == ("pad",)
    q = np.full(th.pad_nodes.size, 1e5)
    th.step(q, 1.0)
    b = th.heat_balance()
    assert b["rotor_unmodelled_W"] == pytest.approx(0.7 * b["friction_power_W"], rel=1e-12)
    assert b["relative_error"] < 1e-8
    assert np.all(th.rotor_temperature_under_pad() == th.T_ambient)


def test_rotor_heating_is_a_revolution_average(brake):
    """Every rotor ring gets a uniform flux, so the rotor's temperature is nearly
    axisymmetric although the pad covers 55 deg and the mesh is not symmetric."""
    m, r = brake
    th = ThermalModel(m)
    th.step(th.flux(r.interface_pressure, MU, OMEGA), 2.0)
    Tf = th.face_temperature("rotor")
    rise = Tf.max() - th.T_ambient
    spread = max(np.ptp(Tf[th.ring == k]) for k in np.unique(th.ring))
    assert rise > 5.0 and spread < 0.05 * rise, f"ring spread {spread:.3f} K of {rise:.1f} K"
    # contrast: the same heat put only where the pad is (no revolution average)
    q = th.flux(r.interface_pressure, MU, OMEGA)
    power = th.coupling.T @ ((1 - th.partition) * q * th.pad_area)
    body = th.heat["rotor"]
    T1 = body.step(np.full(body.n, th.T_ambient), body.flux_load(power / th.rotor_area), 2.0)
    local = max(np.ptp(T1[body.face][th.ring == k]) for k in np.unique(th.ring))
    assert local > 10 * spread, f"no averaging: ring spread {local:.1f} K"
    # the rotor under the pad sees its ring temperature
    Tu = th.rotor_temperature_under_pad()
    assert Tu.shape == th.pad_nodes.shape
    eps = 1e-11 * np.abs(Tf).max()         # round-off of the ring means (K)
    assert Tf.min() - eps <= Tu.min() <= Tu.max() <= Tf.max() + eps


def test_thermal_load_global_numbering(brake):
    """A uniform rise on the rotor (one material): its load equals K (alpha dT x),
    the free expansion, in the rotor's block of the global vector; the pad's block
    is zero at T = T_ref."""
    m, _ = brake
    th = ThermalModel(m)
    dT = 120.0
    T = {"rotor": np.full(th.heat["rotor"].n, th.T_ref + dT), "pad": np.full(th.heat["pad"].n,
                                                                             th.T_ref)}
    f = th.thermal_load(T)
    assert f.shape == (m.dofs,)
    o, n = m.offsets["rotor"], m.meshes["rotor"].nvertices
    alpha = MATERIALS["grey_cast_iron"].thermal.alpha
    u = (alpha * dT * m.meshes["rotor"].p).T.ravel()
    ref = m.stiffness("rotor") @ u
    assert np.abs(f[3 * o:3 * (o + n)] - ref).max() < 1e-9 * np.abs(ref).max()
    op = m.offsets["pad"]
    assert not np.any(f[3 * op:3 * (op + m.meshes["pad"].nvertices)])
    # the free-expansion field carries no thermal stress (and the pad, at rest, none either)
    th.T = T
    s = th.stresses({"rotor": u, "pad": np.zeros(3 * m.meshes["pad"].nvertices)})
    E_alpha_dT = MATERIALS["grey_cast_iron"].elastic.E * alpha * dT
    assert np.abs(s["rotor"]).max() < 1e-10 * E_alpha_dT and not np.any(s["pad"])


def test_scene_without_thermal_builds_nothing_thermal():
    code = ("import sys; from brakewear import BrakeModel, solve_contact; "
            "m = BrakeModel(size=8e-3); solve_contact(m, 1e6, mu=0.4); "
            "assert 'brakewear.thermal' not in sys.modules, 'thermal imported'")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr[-2000:]


# ------------------------------------------------------------ staggering ---

def test_staggered_amplification_model_problem():
    """a(dt) = (1 + dt B/C) / (1 + dt L/C) is the exact step factor of the staggered
    scheme on C dT/dt = (B - L) T; stable for all dt when B < L."""
    C, Lo, B = 2.0, 3.0, 1.0
    T, dt = 1.0, 0.7
    for _ in range(5):
        T = (C / dt + B) * T / (C / dt + Lo)  # implicit heat, explicit (lagged) feedback
    assert T == pytest.approx(staggered_amplification(dt, C, Lo, B) ** 5, rel=1e-14)
    dts = np.logspace(-3, 6, 50)
    a = staggered_amplification(dts, C, Lo, B)
    assert np.all(a < 1) and np.all(np.diff(a) < 0) and a[-1] == pytest.approx(B / Lo, rel=1e-5)
    assert np.all(staggered_amplification(dts, C, B, Lo) > 1)  # B > L: grows, like the physics


def _staggered(m, thermal, dt, steps, p_line=5e5, omega=1.0):
    """One thermal update per step: contact (with the thermal load) -> q = mu p v ->
    heat step.  Returns the largest change of the pad temperature per step."""
    cs = m.contact_system(p_line, MU)
    changes, active, tmax = [], None, []
    for _ in range(steps):
        f = cs.f + cs.P.T @ thermal.thermal_load()
        res = solve_contact(cs.K, f, cs.fixed, cs.coords, [cs.pair], initial_active=active)
        active = res.active
        q = thermal.flux(res.pressure[0], MU, omega)
        old = thermal.T["pad"].copy()
        thermal.steady(q) if dt is None else thermal.step(q, dt)
        assert thermal.heat_balance()["relative_error"] < 1e-8
        changes.append(np.abs(thermal.T["pad"] - old).max())
        tmax.append(thermal.T["pad"].max())
    return np.array(changes), np.array(tmax)


@pytest.fixture(scope="module")
def steady_staggered(brake):
    """dt -> inf, the worst case of the staggering (a -> B/L), on a light drag
    (0.5 MPa, 1 rad/s, ~50 W)."""
    m, _ = brake
    return _staggered(m, ThermalModel(m, contact_conductance=0.0), None, 14)


def test_staggered_thermoelastic_steady_iteration_converges(steady_staggered):
    """Once the active set settles the staggered map is linear and its step ratio
    is the loop gain B/L (0.58 here): below 1, so every dt is stable."""
    ch, tmax = steady_staggered
    ratios = ch[1:] / ch[:-1]
    assert np.all(ratios < 0.7), f"changes {ch}"
    assert ch[-1] < 1e-3 * ch[0], f"changes {ch}"
    assert 350.0 < tmax[-1] < 400.0, tmax


def test_staggered_transient_is_bounded_by_the_steady_state(brake, steady_staggered):
    """One thermal update per 20 s step: the pad's peak temperature rises
    monotonically and stays below the steady state of the same coupling."""
    m, _ = brake
    ch, tmax = _staggered(m, ThermalModel(m, contact_conductance=0.0), 20.0, 8)
    T_steady = steady_staggered[1][-1]
    assert np.all(np.diff(tmax) > 0) and tmax[-1] < T_steady + 0.1, (tmax, T_steady)
    assert np.all(np.isfinite(ch))


# -------------------------------------------------------------- bad input ---

def _with_pad_thermal(m, **changes):
    out = []
    for e, mat in m.materials["pad"]:
        th = None if changes.get("none") and mat.name == "pad_resin" else (
            dataclasses.replace(mat.thermal, **{k: v for k, v in changes.items() if k != "none"})
            if mat.name == "pad_resin" else mat.thermal)
        out.append((e, dataclasses.replace(mat, thermal=th)))
    m.materials["pad"] = out
    return m


def test_bad_input_is_named():
    with pytest.raises(ThermalError, match=r"body 'pad'.*pad_resin.*kappa = -2"):
        ThermalModel(_with_pad_thermal(BrakeModel(size=8e-3), kappa=-2.0))
    with pytest.raises(ThermalError, match=r"body 'pad'.*pad_resin.*thermal data missing"):
        ThermalModel(_with_pad_thermal(BrakeModel(size=8e-3), none=True))
    with pytest.raises(ThermalError, match=r"body 'pad'.*alpha = 0"):
        ThermalModel(_with_pad_thermal(BrakeModel(size=8e-3), alpha=0.0))
    m = BrakeModel(size=8e-3)
    for bad in (1.5, -0.1, np.nan):
        with pytest.raises(ThermalError, match=r"partition .* must lie in \[0, 1\]"):
            ThermalModel(m, partition=bad)
    with pytest.raises(ThermalError, match="partition = 'area'"):
        ThermalModel(m, partition="area")
    with pytest.raises(ThermalError, match=r"body 'rotor': h_conv = -1"):
        ThermalModel(m, h_conv={"rotor": -1.0, "pad": 10.0})
    th = ThermalModel(m)
    with pytest.raises(ThermalError, match=r"q_pad has shape \(3,\)"):
        th.step(np.ones(3), 1.0)
    with pytest.raises(ThermalError, match="dt = 0"):
        th.step(np.ones(th.pad_nodes.size), 0.0)
    with pytest.raises(ThermalError, match="heat_balance: no thermal solve"):
        th.heat_balance()
    th0 = ThermalModel(m, h_conv=0.0)
    with pytest.raises(ThermalError, match="body 'rotor': the steady heat problem is singular"):
        th0.steady(np.ones(th.pad_nodes.size))
    with pytest.raises(ThermalError, match="sliding speed"):
        heat_flux(np.ones(2), -np.ones(2), 0.4)
    with pytest.raises(ThermalError, match="convection facets 'nope'"):
        HeatConduction(box(2, 1, 1), PAD, convection={"nope": 10.0}, name="slab")
    with pytest.raises(ThermalError, match="FrictionLaw: mu0 = -0.1"):
        FrictionLaw(-0.1)


def test_friction_law_fades():
    law = FrictionLaw(0.45, slope=-5e-4, T_ref=473.15, mu_min=0.2)
    assert law.mu() == 0.45
    assert law.mu(np.array([473.15, 673.15, 2000.0])) == pytest.approx([0.45, 0.35, 0.2])
    q = heat_flux(np.array([1e6, -1e5]), np.array([5.0, 5.0]), law.mu(np.array([673.15, 300])))
    assert q == pytest.approx([0.35 * 5e6, 0.0])


def test_state_round_trip_repeats_the_run(brake):
    """Checkpoint and resume: restored state + the same steps = the same temperatures."""
    m, r = brake
    a = ThermalModel(m)
    q = a.flux(r.interface_pressure, MU, OMEGA)
    a.step(q, 1.0)
    saved = a.state_arrays()
    a.step(q, 2.0)
    b = ThermalModel(m)
    b.load_state(saved)
    b.step(q, 2.0)
    assert all(np.array_equal(a.T[k], b.T[k]) for k in a.bodies) and b.time == a.time == 3.0
    with pytest.raises(ThermalError, match="'T_pad' has shape"):
        b.load_state({**saved, "T_pad": np.ones(3)})


# ---------------------------------------------------- contact conductance ---

@pytest.mark.parametrize("h_c", [1e3, 1e5])
def test_contact_conductance_solves_the_monolithic_system(brake, h_c):
    """The ring-mean (low-rank) solve equals the explicitly assembled coupled
    pad-rotor system; energy is conserved, the exchange included."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    m, r = brake
    th = ThermalModel(m, contact_conductance=h_c)
    q = th.flux(r.interface_pressure, MU, OMEGA)
    T0 = {b: v.copy() for b, v in th.T.items()}
    dt = 2.0
    th.step(q, dt)
    b = th.heat_balance()
    assert b["relative_error"] < 1e-8 and b["exchange_pad_to_rotor_W"] > 0, b
    P, R = th.heat["pad"], th.heat["rotor"]
    DV, U, V = th._DV, th._U, th._V
    Apr = -sp.csr_matrix(DV @ U.T)
    A = sp.bmat([[P.M / dt + P.K + P.H + P.Hc, Apr],
                 [Apr.T, R.M / dt + R.K + R.H + sp.csr_matrix(U @ (DV[th.pad_nodes].T @ V) @ U.T)]])
    assert abs(A - A.T).max() < 1e-12 * abs(A).max()  # symmetric: a conductance
    F, _ = th._loads(q)
    x = spla.spsolve(A.tocsc(), np.concatenate([P.rhs(T0["pad"], F["pad"], dt),
                                                R.rhs(T0["rotor"], F["rotor"], dt)]))
    mine = np.concatenate([th.T["pad"], th.T["rotor"]])
    assert np.abs(x - mine).max() < 1e-10 * np.abs(mine - th.T_ambient).max()


def test_large_contact_conductance_equalises_the_interface(brake):
    """h_c = 1e5 W/m^2 K: after 2 s of a 6 kW drag the pad face is within a few K
    of the rotor ring under it (with the fixed partition alone: hundreds of K)."""
    m, r = brake
    gaps = {}
    for h_c in (0.0, 1e5):
        th = ThermalModel(m, contact_conductance=h_c)
        th.step(th.flux(r.interface_pressure, MU, OMEGA), 2.0)
        gaps[h_c] = np.abs(th.face_temperature("pad") - th.rotor_temperature_under_pad()).max()
    assert gaps[0.0] > 200.0 and gaps[1e5] < 0.05 * gaps[0.0], gaps


def test_contact_conductance_bad_input():
    with pytest.raises(ThermalError, match="contact_conductance = -1"):
        ThermalModel(BrakeModel(size=8e-3), contact_conductance=-1.0)
    with pytest.raises(ThermalError, match="needs an elastic .*rigid"):
        ThermalModel(BrakeModel(size=8e-3, rotor="rigid"), contact_conductance=1e4)


def test_step_is_solved_with_the_octave_factorisation(brake):
    """dt = 1.6 s: CG preconditioned by the factorisation of dt0 = 2 s (the nearest
    power of two), the same answer as a direct solve; 1.2 s and 0.9 s share the 1 s
    factorisation; the result depends on dt only."""
    import scipy.sparse.linalg as spla

    m, r = brake
    th = ThermalModel(m, contact_conductance=0.0)
    q = th.flux(r.interface_pressure, MU, OMEGA)
    th.step(q, 1.0)
    T0 = th.T["pad"].copy()
    th.step(q, 1.6)
    body = th.heat["pad"]
    assert body.factorizations == 2 and 0 < body.cg_iterations <= 12, body.cg_iterations
    F, _ = th._loads(q)
    ref = spla.spsolve((body.M / 1.6 + body.K + body.H).tocsc(), body.rhs(T0, F["pad"], 1.6))
    assert np.abs(th.T["pad"] - ref).max() < 1e-9 * np.abs(ref - T0).max()
    assert th.heat_balance()["relative_error"] < 1e-8
    th.step(q, 1.2)
    th.step(q, 0.9)
    assert body.factorizations == 2
