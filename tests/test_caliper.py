"""The pad as the caliper holds it: a rigid piston in its bore and seal, rim, fingers
and abutments one-sided with Coulomb friction (brakewear.caliper.rows,
brakewear.caliper.interface).

Every body in balance with friction on; the condensed answer is the FE answer of
the same rows' state (a sparse direct solve of the whole saddle-point system);
closed forms: a rigid pad rocking on a compliant rim ring (its linear force
distribution and lift-off moment), a rigid piston tilted in its bore (the wall
engages at 2c/L and carries the rest of the moment), the seal's springs
against the bonded ring's closed forms."""
from dataclasses import replace

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from brakewear import BrakeModel, CaliperInterface, load_geometry
from brakewear.caliper import analytic
from brakewear.caliper.parts import CaliperParts, rigid_map, seal_springs
from brakewear.caliper.rows import caliper_rows
from brakewear.caliper.sets import CLOSED, SLIP_DOWN, SLIP_UP, STICK, RowSets
from brakewear.caliper.static import abutment_friction_work
from brakewear.contact.compliant import constraint_rows, drag_loads
from brakewear.static import pad_balance, solve_contact

SIZE = 12e-3


def _floating(**guide):
    # abutments of low friction (0.03): each end face's friction acts on the face as a
    # whole, and below about 0.04 both bearing faces slip at 1 MPa (a test of both laws:
    # the rim's friction sticks)
    g = load_geometry("floating")
    return replace(g, piston=replace(g.piston, guide=replace(g.piston.guide, **guide)),
                   support=replace(g.support, abutment_friction=0.03))


@pytest.fixture(scope="module")
def solved():
    model = BrakeModel(_floating(), size=SIZE, piston="rigid")
    itf = CaliperInterface(model, 1e6, 0.4)
    r = itf.fe.r
    offset = 15e-6 * (r - r.min()) / np.ptp(r)     # a coned pair: the pads must tilt
    res = solve_contact(model, 1e6, mu=0.4)
    return model, itf, offset, res


def test_every_body_balances_with_friction_on(solved):
    model, itf, _, res = solved
    bal = pad_balance(model, res, 1e6)
    for pad in ("in", "out"):
        assert bal[pad]["force"] < 1e-9 and bal[pad]["moment"] < 1e-9, bal[pad]
    assert bal["piston in"]["force"] < 1e-9 and bal["piston in"]["moment"] < 1e-9
    assert bal["housing"]["axial"] < 1e-9
    cal = res.info["caliper"]
    rows, st = itf.rows, cal["state"]
    # a real test: friction on at every family, some rows slipping, some sticking
    fr = ~rows.normal
    assert np.any(fr & ((st == SLIP_UP) | (st == SLIP_DOWN))) and np.any(fr & (st == STICK))
    assert np.any(rows.normal & (st != CLOSED)) and np.any(rows.normal & (st == CLOSED))
    # Coulomb's law at every friction row
    lam, gap = cal["force"], cal["gap"]
    k = np.nonzero(fr)[0]
    cap = rows.mu[k] * (rows.cap[k] @ lam)
    assert np.all(np.abs(lam[k]) <= cap * (1 + 1e-9) + 1e-9 * res.clamp_force)
    slip = (st[k] == SLIP_UP) | (st[k] == SLIP_DOWN)
    assert np.all(lam[k][slip] * gap[k][slip] <= 1e-12 * res.clamp_force * 1e-6)
    # the abutments' friction takes work from the application, on the bearing (trailing) end
    work = abutment_friction_work(res)
    assert work["abutment trailing (inboard)"] > 0 and work["abutment trailing (outboard)"] > 0


def _fe_solve(itf, sol, offset, mu, p):
    """The FE equations of the rows' state ``sol`` found, as one sparse direct solve
    of the whole saddle-point system (no condensation): displacements, rigid DOFs,
    the active contact nodes' and the holding rows' forces."""
    cs, rows = itf.fe.cs, itf.rows
    N, nq = cs.K.shape[0], rows.K_q.shape[0]
    cal = sol.info["caliper"]
    st, A = cal["state"], sol.active
    C = constraint_rows(cs.pair, N).tocsr()
    G = drag_loads(cs.pair, N, mu=mu).tocsr()
    hold = np.where(rows.normal, st == CLOSED, st == STICK)
    h = np.nonzero(hold)[0]
    col_of = -np.ones(rows.n, dtype=int)
    col_of[h] = np.arange(h.size)
    # each row's force in terms of the holding rows' (slip: +-mu lam_normal)
    S = sp.lil_matrix((rows.n, h.size))
    for k in range(rows.n):
        if hold[k]:
            S[k, col_of[k]] = 1.0
        elif st[k] in (SLIP_UP, SLIP_DOWN):
            for j in rows.cap[k].indices:
                S[k, col_of[j]] = (1.0 if st[k] == SLIP_UP else -1.0) * rows.mu[k]
    S = S.tocsr()
    free = np.setdiff1d(np.arange(N), cs.fixed)
    K = cs.K[free][:, free]
    CA = C[A][:, free]
    GA = G[free][:, A]
    Cs = rows.C[:, free]
    top = sp.hstack([K, sp.csr_matrix((free.size, nq)), -(CA.T + GA), -(Cs.T @ S)])
    mid = sp.hstack([sp.csr_matrix((nq, free.size)), sp.csr_matrix(rows.K_q), sp.csr_matrix(
        (nq, A.sum())), sp.csr_matrix(rows.R.T) @ S])
    con = sp.hstack([CA, sp.csr_matrix((A.sum(), nq)), sp.csr_matrix((A.sum(), A.sum() + h.size))])
    hrow = sp.hstack([Cs[h], -sp.csr_matrix(rows.R[h]), sp.csr_matrix((h.size, A.sum())),
                      sp.diags(rows.compliance[h])])
    M = sp.vstack([top, mid, con, hrow]).tocsc()
    gap_s = rows.g0 + p * rows.g1
    rhs = np.concatenate([cs.f[free], p * rows.f_q, -(itf.g0 + offset)[A], -gap_s[h]])
    lu = spla.splu(M)
    x = lu.solve(rhs)
    for _ in range(2):                 # the saddle point is ill-conditioned: refine
        x += lu.solve(rhs - M @ x)
    u = np.zeros(N)
    u[free] = x[:free.size]
    i = free.size
    q, lamA, lamH = x[i:i + nq], x[i + nq:i + nq + A.sum()], x[i + nq + A.sum():]
    return u, q, lamA, S @ lamH


def test_the_condensed_answer_is_the_fe_answer_of_its_state(solved):
    model, itf, offset, _ = solved
    sol = itf.solve(offset, None, mu=0.4)
    cal = sol.info["caliper"]
    u, q, lamA, lam_s = _fe_solve(itf, sol, offset, 0.4, 1e6)
    F = 1e6 * model.geometry.clamp_area
    assert np.abs(lamA - cal["lam"][sol.active]).max() < 1e-8 * F
    assert np.abs(lam_s - cal["force"]).max() < 1e-8 * F
    assert np.abs(q - cal["q"]).max() < 1e-8 * np.abs(q).max()
    # and the state is admissible in the FE solution: open contact nodes open
    g = constraint_rows(itf.fe.cs.pair, u.size) @ u + itf.g0 + offset
    assert g[~sol.active].min() > -1e-10 * np.ptp(itf.fe.cs.coords, axis=1).max()


@pytest.mark.parametrize("call, match", [
    (lambda: analytic.bonded_ring_axial_stiffness(1e6, 0.02, 0.01, 5e-3), "r_i < r_o"),
    (lambda: analytic.bonded_ring_torsion_stiffness(1e6, 0.01, 0.01, 5e-3), "r_i < r_o"),
    (lambda: analytic.bonded_ring_torsion_stiffness(-1e6, 0.01, 0.02, 5e-3),
     r"G: -1000000\.0 Pa is not allowed; it must be > 0 Pa"),
    (lambda: analytic.bonded_strip_compression_modulus(1e6, 2e-3, 0.0), "thickness"),
    (lambda: analytic.ring_tilt_stiffness(float("nan"), 0.02), "axial_stiffness: nan"),
    (lambda: analytic.rigid_ring_liftoff_moment(-5.0, 0.02), "force"),
    (lambda: analytic.bore_contact_tilt(1e-4, 0.0), "engagement"),
])
def test_the_closed_forms_refuse_what_is_not_a_part(call, match):
    """No negative stiffness, no ZeroDivisionError: a named GeometryError (exit 2)."""
    from brakewear.errors import GeometryError
    with pytest.raises(GeometryError, match=match):
        call()


def test_seal_springs_are_the_bonded_ring_closed_forms():
    g = _floating()
    guide = g.piston.guide
    R = 0.5 * g.piston.diameter
    k = seal_springs(guide, R)
    G = guide.seal_modulus / 3
    ka = analytic.bonded_ring_axial_stiffness(G, R, R + guide.seal_width, guide.seal_height)
    kt = analytic.bonded_ring_torsion_stiffness(G, R, R + guide.seal_width, guide.seal_height)
    assert k["axial_total"] == pytest.approx(ka, rel=1e-12)
    assert k["torsion"] == pytest.approx(kt, rel=1e-12)
    # what the ring of springs gives the rigid piston (about the centre of its face)
    P = CaliperParts(g, full=False)
    from brakewear.caliper.parts import seal_stiffness
    K, f = seal_stiffness(P)
    d = guide.stand_out + guide.seal_position            # the seal's plane above the face
    assert K[2, 2] == pytest.approx(ka, rel=1e-12)
    assert K[5, 5] == pytest.approx(kt, rel=1e-12)
    assert K[0, 0] == pytest.approx(k["radial_total"], rel=1e-12)
    tilt = analytic.ring_tilt_stiffness(ka, k["radius"]) + k["radial_total"] * d ** 2
    assert K[3, 3] == pytest.approx(tilt, rel=1e-12)
    assert K[4, 4] == pytest.approx(tilt, rel=1e-12)
    # the hydraulic force on the piston, toward the pad
    assert f[2] == pytest.approx(-g.piston.hydraulic_area, rel=1e-12)
    # the reviewer's estimate: 0.2-0.3 kN m/rad about the seal's plane
    assert 0.1e3 < k["tilt"] < 0.4e3


def _synthetic(rows, n_modes_map, contact_points, contact_c, line_pressure=1.0):
    """A condensation of a rigid pad (``n_modes_map(x)``: (3, m) its displacement per
    mode at x) under contact points (normal +z, compliance ``contact_c`` m/N each)
    held by ``rows``: no elastic compliance, every row's response through the modes."""
    class Cond:
        pass
    c = Cond()
    E_c = np.array([n_modes_map(x)[2] for x in contact_points.T])
    E_s = np.array([rows.direction[:, k] @ n_modes_map(rows.point[:, k])
                    if rows.plus[k] == "pad" else np.zeros(E_c.shape[1]) for k in range(rows.n)])
    n_c, m = E_c.shape
    n = n_c + rows.n
    c.H, c.Ht, c.hf = np.zeros((n, n)), np.zeros((n, n_c)), np.zeros(n)
    c.E, c.Dt, c.zf, c.n_c = np.vstack([E_c, E_s]), np.zeros((m, n_c)), np.zeros(m), n_c
    return c


def _pad_modes(ref):
    """uz, and rotations about x and y through ``ref``: a pad's out-of-plane modes."""
    def modes(x):
        return rigid_map(x, ref)[:, [2, 3, 4]]
    return modes


def test_a_rigid_pad_rocks_on_the_rim_ring_as_the_closed_form_says():
    g = _floating(rim_friction=0.0)
    model = BrakeModel(g, size=10e-3, rotor="rigid", piston="rigid")
    cs = model.contact_system(1e6)
    allrows = caliper_rows(g, model.meshes["pad"], model.offsets["pad"], cs.col, cs.K.shape[0],
                           full=False)
    rim = allrows.subset(np.array([grp == "rim in" for grp in allrows.group]))
    outer = np.isclose(np.hypot(*(rim.point[:2] - np.array(g.piston_center)[:, None])),
                       0.5 * g.piston.diameter)
    rim = rim.subset(outer)                                      # the outer edge's ring
    a, npt = 0.5 * g.piston.diameter, rim.n
    # a compliant ring (1 kN/mm per point) under a piston free to move along its axis
    # and held square (1e16 N m/rad: its tilt changes the ring's forces by 1e-9)
    rim = replace(rim, compliance=np.full(npt, 1e-9),
                  K_q=np.diag([1e6, 1e6, 0.0, 1e16, 1e16, 1e3]))
    centre = np.array([*g.piston_center, g.pad.thickness])
    p = 1e6
    F = p * g.piston.hydraulic_area
    for ecc in (0.3 * a, 0.5 * a, 0.8 * a):
        # the pad rests on one point of the rotor, ``ecc`` from the piston's axis
        pt = np.array([[centre[0] + ecc], [centre[1]], [0.0]])
        cond = _synthetic(rim, _pad_modes(centre), pt, None)
        sets = RowSets(cond, rim, gap_tol=1e-15)
        sol = sets.solve(np.zeros(1), np.zeros(3), rim.g0.copy(), p, None, None, np.zeros(1))
        lam = sol.force
        assert sol.lam[0] == pytest.approx(F, rel=1e-10)       # the point carries F
        assert lam.sum() == pytest.approx(F, rel=1e-10)
        # moment balance about the piston's axis: the ring's resultant on the point
        x = rim.point[0] - centre[0]
        assert (lam * x).sum() / F == pytest.approx(ecc, rel=1e-9)
        cosphi = x / a
        if ecc <= analytic.rigid_ring_liftoff_moment(F, a) / F:
            # the ring's linear distribution, all points pressed
            assert np.allclose(lam, F / npt * (1 + 2 * ecc * cosphi / a), rtol=1e-6,
                               atol=1e-9 * F)
        else:
            assert np.sum(lam <= 0) > 0 and np.all(lam >= -1e-12 * F)   # part lifts off


def test_a_piston_tilted_in_its_bore_engages_the_wall_at_2c_over_L():
    L = 20e-3
    c = 0.08e-3
    g = _floating(bore_friction=0.0, engagement=L, seal_position=0.5 * L, clearance=c)
    model = BrakeModel(g, size=10e-3, rotor="rigid", piston="rigid")
    cs = model.contact_system(1e6)
    allrows = caliper_rows(g, model.meshes["pad"], model.offsets["pad"], cs.col, cs.K.shape[0],
                           full=False)
    bore = allrows.subset(np.array([grp == "bore in" for grp in allrows.group]))
    # a pure moment turns the piston about the seal's centre, which sits mid-way along
    # the guided length: both ends reach the wall together
    k_tilt = seal_springs(g.piston.guide, 0.5 * g.piston.diameter)["tilt"]
    theta_w = analytic.bore_contact_tilt(c, L)
    for M in (0.5 * k_tilt * theta_w, 3.0 * k_tilt * theta_w):
        # a moment about the pad's tangent (y) on the piston; no hydraulic force
        rows = replace(bore, f_q=np.zeros(6))
        rows.f_q[4] = M
        # a contact node of its own, touching without force, no modes
        cond = _synthetic(rows, lambda x: np.zeros((3, 0)), np.array([[1.0], [0.0], [0.0]]), None)
        cond.H[0, 0] = 1e-9
        sets = RowSets(cond, rows, gap_tol=1e-15)
        sol = sets.solve(np.zeros(1), np.zeros(0), rows.g0.copy(), 1.0, None, None, np.zeros(1))
        tilt = sol.q[4]
        if M < k_tilt * theta_w:
            assert tilt == pytest.approx(M / k_tilt, rel=1e-9)    # the seal alone
            assert np.all(sol.force == 0.0)
        else:
            # both ends on the wall: the tilt is the clearance's, the wall carries the rest
            assert tilt == pytest.approx(theta_w, rel=1e-6)
            wall = sol.force
            ends = np.round(rows.point[2] - rows.point[2].min(), 9)
            arm = L
            couple = wall[ends > 0].sum() * arm
            assert couple == pytest.approx(M - k_tilt * theta_w, rel=1e-3)


def test_another_load_path_on_the_same_condensation_is_a_fresh_interface(solved):
    """CaliperInterface.with_load_path shares the condensation (which the rows' places
    decide) and gives the answer of an interface built for that geometry."""
    model, itf, offset, _ = solved
    g = replace(model.geometry, support=replace(model.geometry.support, abutment_friction=0.4),
                piston=replace(model.geometry.piston, guide=replace(
                    model.geometry.piston.guide, seal_modulus=12e6, rim_friction=0.3)))
    other = itf.with_load_path(g)
    assert other.cond is itf.cond
    fresh = CaliperInterface(BrakeModel(g, size=SIZE, piston="rigid"), 1e6, 0.4)
    a = other.solve(offset, None, mu=0.4)
    b = fresh.solve(offset, None, mu=0.4)
    assert np.array_equal(a.active, b.active)
    assert np.abs(a.pressure - b.pressure).max() < 1e-9 * np.abs(b.pressure).max()
    assert not np.allclose(a.pressure, itf.solve(offset, None, mu=0.4).pressure, rtol=1e-6)
    with pytest.raises(Exception, match="load-path parameters only"):
        itf.with_load_path(replace(g, pad=replace(g.pad, slot_width=0.0)))


def test_the_caliper_is_a_registered_interface_model(solved):
    """``interface="caliper"`` names the caliper in a run (the registry builds it and
    the run checks its capabilities: no geometry update, no quadratic meshes), and its
    first contact solve is the interface's own; a scene without a rigid piston
    is refused naming components.piston."""
    from brakewear import Run
    from brakewear.errors import SceneError, WearError
    from brakewear.interfaces import capabilities_of, interface_model
    from brakewear.laws.base import WearLaw
    from brakewear.scene import InterfaceSpec, Scene
    from brakewear.wear import Numerics

    model, itf, offset, _ = solved
    entry = interface_model("caliper")
    assert {"accepts_load", "implicit_rings"} <= capabilities_of(entry)
    assert not {"follows_geometry", "quadratic"} & capabilities_of(entry)
    run = Run(model, 1e6, 55.0, 10.0, WearLaw(k=5e-15), mu=0.4,
              interface="caliper").resolved()
    assert isinstance(run.interface, CaliperInterface)
    assert run.interface_record == {"requested": "caliper", "model": "caliper"}
    a = run.interface.solve(offset, None, mu=0.4)
    b = itf.solve(offset, None, mu=0.4)
    assert np.abs(a.pressure - b.pressure).max() <= 1e-12 * np.abs(b.pressure).max()
    with pytest.raises(WearError, match="follows_geometry"):
        Run(model, 1e6, 55.0, 10.0, WearLaw(k=5e-15), mu=0.4, interface="caliper",
            numerics=Numerics(update="geometry")).resolved()
    with pytest.raises(SceneError, match=r"interface\.model: 'caliper' .*components\.piston "
                                         r"= 'traction'"):
        Scene(geometry="floating", interface=InterfaceSpec(model="caliper"))
