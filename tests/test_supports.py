"""The pad's support in the bracket (brakewear.contact.supports) and contact pairs with
in-plane normals in both solve paths (Lagrange and compliant)."""
from dataclasses import replace

import numpy as np
import pytest
import scipy.sparse as sp

from brakewear.caliper.geometry import SupportGeometry
from brakewear.contact import (
    ContactPair,
    compliant_preconditioner,
    solve_compliant_contact,
    solve_contact,
)
from brakewear.contact.supports import (
    abutment_faces,
    abutment_pairs,
    end_normal,
    support_springs,
    with_supports,
)
from brakewear.fem import assemble_stiffness, assemble_traction, boundary_dofs
from brakewear.materials import Isotropic
from brakewear.mesh import mapped_mesh, structured_tets
from brakewear.model import BrakeModel

L = 0.01   # cube edge (m)
F = 1e3    # push toward the wall (N)
FZ = 2e3   # press on the floor (N)


def _cube_on_floor(angle: float, clearance: float, k_normal: float, k_tangential=1e6):
    """A cube of edge L (turned by ``angle`` about z) on a rigid floor z = 0, pressed
    down by FZ and pushed by F toward a rigid wall (normal ``n`` in the plane) at
    ``clearance`` from its face; its top face held by springs to ground along the
    wall (``k_tangential``) and across it (``k_normal``), N/m in all."""
    c, si = np.cos(angle), np.sin(angle)
    n, t = np.array([c, si, 0.0]), np.array([-si, c, 0.0])
    s = np.linspace(0.0, L, 4)
    p, tets = structured_tets(s, s, s)
    p = np.outer(n, p[0]) + np.outer(t, p[1]) + np.outer([0, 0, 1.0], p[2])
    tol = 1e-9 * L
    m = mapped_mesh(p, tets, lambda x: x).with_boundaries({
        "wall": lambda x: np.abs(n @ x) < tol, "load": lambda x: np.abs(n @ x - L) < tol,
        "bottom": lambda x: np.abs(x[2]) < tol, "top": lambda x: np.abs(x[2] - L) < tol})
    K = assemble_stiffness(m, Isotropic(2e11, 0.3))[0].tocsr()
    f = (assemble_traction(m, "load", tuple(-F / L ** 2 * n))
         + assemble_traction(m, "top", (0.0, 0.0, -FZ / L ** 2)))
    top = np.unique(m.facets[:, m.boundaries["top"]])
    K = (K + _springs(top, t, k_tangential, K.shape[0])
         + _springs(top, n, k_normal, K.shape[0])).tocsr()
    bottom = np.unique(m.facets[:, m.boundaries["bottom"]])
    wall = np.setdiff1d(np.unique(m.facets[:, m.boundaries["wall"]]), bottom)
    floor = ContactPair(bottom, np.full(bottom.size, L ** 2 / bottom.size),
                        np.repeat([[0.0], [0.0], [1.0]], bottom.size, axis=1),
                        np.zeros(bottom.size), name="floor")
    stop = ContactPair(wall, np.full(wall.size, L ** 2 / wall.size),
                       np.repeat(n[:, None], wall.size, axis=1), np.full(wall.size, clearance),
                       name="wall")
    return m, K, f, [floor, stop], n


def _springs(nodes, d, k, n_dofs):
    """Springs to ground of total stiffness ``k`` along ``d``, shared by ``nodes``."""
    rows = 3 * nodes[:, None, None] + np.arange(3)[None, :, None]
    cols = 3 * nodes[:, None, None] + np.arange(3)[None, None, :]
    vals = np.broadcast_to(k / nodes.size * np.outer(d, d), rows.shape[:1] + (3, 3))
    return sp.csr_matrix((vals.ravel(), (np.broadcast_to(rows, vals.shape).ravel(),
                                         np.broadcast_to(cols, vals.shape).ravel())),
                         shape=(n_dofs, n_dofs))


@pytest.mark.parametrize("angle", [0.0, np.radians(30.0)])
@pytest.mark.parametrize("linear", ["direct", "amg"])
def test_a_block_pressed_against_a_wall_in_the_plane_carries_the_load(angle, linear):
    # springs only along the wall: the wall carries the whole push, the floor the press
    m, K, f, pairs, n = _cube_on_floor(angle, 0.0, 0.0)
    res = solve_contact(K, f, np.zeros(0, dtype=int), m.p, pairs, linear=linear, tol=1e-11)
    floor, wall = res.info["normal_force"]
    assert wall == pytest.approx(F, rel=1e-8) and floor == pytest.approx(FZ, rel=1e-8)
    assert res.info["min_gap"] > -1e-10 * L


@pytest.mark.parametrize("angle", [0.0, np.radians(30.0)])
def test_a_wall_clearance_closes_only_under_enough_load(angle):
    # springs across the wall: the cube moves about F / k = 0.1 mm before it meets it
    k = 1e7
    for clearance in (2e-4, 5e-5):
        m, K, f, pairs, n = _cube_on_floor(angle, clearance, k)
        res = solve_contact(K, f, np.zeros(0, dtype=int), m.p, pairs, linear="direct")
        wall, lam, active = pairs[1], res.force[1], res.active[1]
        approach = -(res.u.reshape(-1, 3)[wall.slave] @ n)
        r = (K @ res.u - f).reshape(-1, 3).sum(axis=0)      # = floor + wall forces
        assert r @ n == pytest.approx(lam.sum(), rel=1e-8, abs=1e-12 * F)
        if clearance > F / k:
            assert not active.any() and np.all(lam == 0)
            assert np.all(res.gap[1] > 0) and approach.max() < clearance
            assert approach.mean() == pytest.approx(F / k, rel=0.05)
        else:
            assert active.any() and 0 < lam.sum() < F
            assert np.all(res.gap[1] > -1e-10 * L)
            # the nodes in contact have moved by exactly the clearance
            assert np.allclose(approach[active], clearance, rtol=1e-8, atol=0)


# ---------------------------------------------------------------- the pad --
MU = 0.4


@pytest.fixture(scope="module")
def pad_model():
    return BrakeModel(rotor="rigid", size=6e-3)


def _pad_system(model, support, mu):
    """The pad on the rigid rotor plane held by ``support``:
    ``(K + springs, f, fixed, coords, [friction pair, *abutment pairs], springs, F)``."""
    pad, off = model.meshes["pad"], model.offsets["pad"]
    cs = with_supports(model.contact_system(1e6, mu), pad, off, model.geometry.pad, support)
    Ks = support_springs(pad, off, model.geometry.pad, support, model.dofs)
    return cs.K, cs.f, cs.fixed, cs.coords, [cs.pair, *cs.supports], Ks, cs.clamp_force


def _pad_forces(res, pairs, K_springs, f, n_nodes):
    """Nodal forces (n_nodes, 3) on the pad: contact (normal + friction), each
    abutment's, the springs' and the load."""
    contact = np.zeros((n_nodes, 3))
    fr = pairs[0]
    np.add.at(contact, fr.slave, (fr.normal * res.force[0] + res.friction[0]).T)
    abut = []
    for pr, lam in zip(pairs[1:], res.force[1:]):
        a = np.zeros((n_nodes, 3))
        np.add.at(a, pr.slave, (pr.normal * lam).T)
        abut.append(a)
    springs = -(K_springs @ res.u).reshape(-1, 3)
    return contact, abut, springs, f.reshape(-1, 3)


def _resultant(forces, x):
    """Force and moment (about the origin) of nodal forces (n, 3) at points x (3, n)."""
    return forces.sum(axis=0), np.cross(x.T, forces).sum(axis=0)


@pytest.mark.parametrize("kind", ["push", "pull"])
def test_the_bearing_abutment_carries_the_drag_and_the_pad_balances(pad_model, kind):
    g = pad_model.geometry
    c = g.pad.center_angle
    tang = np.array([-np.sin(c), np.cos(c), 0.0])
    x = pad_model.coordinates()
    for spring in (0.0, 1e5):
        support = SupportGeometry(type=kind, clearance=1e-4, spring_stiffness=spring)
        K, f, fixed, coords, pairs, Ks, F = _pad_system(pad_model, support, MU)
        res = solve_contact(K, f, fixed, coords, pairs, linear="direct")
        contact, abut, springs, load = _pad_forces(res, pairs, Ks, f, x.shape[1])
        names = [pr.name for pr in pairs[1:]]
        assert names == [f"abutment {support.bearing_end} (inboard)",
                         f"abutment {'leading' if kind == 'push' else 'trailing'} (inboard)"]
        # force and moment balance of the pad (no other support holds it)
        total = [contact, *abut, springs, load]
        fsum, msum = _resultant(sum(total), x)
        R = np.hypot(x[0], x[1]).max()
        assert np.abs(fsum).max() < 1e-8 * F and np.abs(msum).max() < 1e-8 * F * R
        # the bearing end takes the friction drag (less the anti-rattle spring's share);
        # the other end's stop stays open
        drag = contact.sum(axis=0) @ tang
        bearing = abut[0].sum(axis=0) @ tang
        assert drag == pytest.approx(MU * F, rel=0.05)
        assert bearing + springs.sum(axis=0) @ tang == pytest.approx(-drag, rel=1e-8)
        if spring == 0.0:
            assert bearing == pytest.approx(-drag, rel=1e-8)
        else:
            assert bearing == pytest.approx(-drag, rel=1e-3)
        assert not res.active[2].any() and np.all(res.force[2] == 0)
        assert res.info["normal_force"][0] == pytest.approx(F, rel=1e-8)


@pytest.mark.parametrize("kind", ["push", "pull"])
def test_without_friction_no_abutment_bears_and_the_springs_hold_the_pad(pad_model, kind):
    support = SupportGeometry(type=kind, clearance=1e-4)
    K, f, fixed, coords, pairs, Ks, F = _pad_system(pad_model, support, 0.0)
    res = solve_contact(K, f, fixed, coords, pairs, linear="amg")
    assert res.info["normal_force"][0] == pytest.approx(F, rel=1e-8)
    # the bearing stop (no clearance) is touched only by the pad's lateral expansion
    # under the clamp load; the other stop stays open
    assert abs(res.info["normal_force"][1]) < 1e-4 * F
    assert not res.active[2].any()


def test_a_clearance_larger_than_the_pads_give_keeps_that_side_free(pad_model):
    # pull: the trailing end has the clearance; the pad's elastic tangential
    # displacement under the drag is well below 0.1 mm, so that stop never bears
    support = SupportGeometry(type="pull", clearance=1e-4)
    K, f, fixed, coords, pairs, Ks, F = _pad_system(pad_model, support, MU)
    res = solve_contact(K, f, fixed, coords, pairs, linear="direct")
    trailing = pairs[2]
    give = (res.u.reshape(-1, 3)[trailing.slave] @ -trailing.normal[:, 0]).max()
    assert 0 < give < 0.5 * support.clearance
    assert not res.active[2].any() and np.all(res.gap[2] > 0.5 * support.clearance)
    # with no clearance the same stop shares the drag
    K, f, fixed, coords, pairs, Ks, F = _pad_system(pad_model, replace(support, clearance=0.0),
                                                    MU)
    res0 = solve_contact(K, f, fixed, coords, pairs, linear="direct")
    assert res0.info["normal_force"][2] > 0.1 * MU * F


def test_support_pieces_on_a_two_pad_mesh(pad_model):
    # the outboard pad: the inboard one mirrored below a 20 mm rotor, in one mesh
    pad = pad_model.meshes["pad"]
    t = pad.t
    low = pad.p * np.array([[1.0], [1.0], [-1.0]]) - np.array([[0.0], [0.0], [0.02]])
    both = type(pad)(np.hstack([pad.p, low]), np.hstack([t, t[[0, 2, 1, 3]] + pad.p.shape[1]]))
    both = both.with_boundaries({
        "abutment": lambda X: pad_model_abutment(pad_model, X),
        "leading": lambda X: _on_end(pad_model, X, "leading"),
        "trailing": lambda X: _on_end(pad_model, X, "trailing")})
    support = SupportGeometry(type="push", clearance=1e-4)
    faces = abutment_faces(both, "trailing")
    assert sorted(faces) == ["inboard", "outboard"]
    pairs = abutment_pairs(both, 5, pad_model.geometry.pad, support)
    assert len(pairs) == 4
    one = abutment_pairs(pad, 5, pad_model.geometry.pad, support)
    n = pad.p.shape[1]
    for k, pr in enumerate(one):
        inb, outb = pairs[2 * k], pairs[2 * k + 1]
        assert np.array_equal(inb.slave, pr.slave) and np.allclose(inb.area, pr.area)
        assert np.allclose(outb.area.sum(), pr.area.sum(), rtol=1e-12)
        assert np.allclose(outb.normal, pr.normal[:, :1]) and np.all(outb.slave >= n + 5)
    Ks = support_springs(both, 5, pad_model.geometry.pad, support, 3 * (2 * n + 5))
    K1 = support_springs(pad, 5, pad_model.geometry.pad, support, 3 * (2 * n + 5))
    # each pad has its own rails and spring: twice the stiffness of one pad
    one_dir = np.array([1.0, 0.0, 0.0])
    e = np.tile(one_dir, 2 * n + 5)
    assert e @ Ks @ e == pytest.approx(2 * (e @ K1 @ e), rel=1e-12)
    assert abs(Ks - Ks.T).max() == 0


def _on_end(model, X, end):
    a = model.geometry.pad.leading_angle if end == "leading" else model.geometry.pad.trailing_angle
    return np.abs(-np.sin(a) * X[0] + np.cos(a) * X[1]) < 1e-9


def pad_model_abutment(model, X):
    tf = model.geometry.pad.friction_thickness
    return (_on_end(model, X, "leading") | _on_end(model, X, "trailing")) & (
        (X[2] > tf) | (X[2] < -0.02 - tf))


def test_spring_stiffness_and_directions(pad_model):
    pad, g = pad_model.meshes["pad"], pad_model.geometry
    support = SupportGeometry(type="push", rail_stiffness=3e8, spring_stiffness=2e5)
    Ks = support_springs(pad, 0, g.pad, support, pad_model.dofs)
    c = g.pad.center_angle
    radial = np.tile([np.cos(c), np.sin(c), 0.0], pad.p.shape[1])
    tang = np.tile([-np.sin(c), np.cos(c), 0.0], pad.p.shape[1])
    # a rigid translation loads the springs by their total stiffness
    assert radial @ Ks @ radial == pytest.approx(2 * 3e8, rel=1e-12)
    assert tang @ Ks @ tang == pytest.approx(2e5, rel=1e-12)
    assert abs(radial @ Ks @ tang) < 1e-12 * 3e8
    assert support_springs(pad, 0, g.pad, SupportGeometry(), pad_model.dofs).nnz == 0
    assert abutment_pairs(pad, 0, g.pad, SupportGeometry()) == []
    e = end_normal(g.pad, "trailing")
    assert abs(e @ [np.cos(g.pad.trailing_angle), np.sin(g.pad.trailing_angle), 0.0]) < 1e-15
    assert e[1] > 0 if abs(g.pad.trailing_angle) < np.pi / 2 else True


def test_bad_support_input_is_refused(pad_model):
    pad, g = pad_model.meshes["pad"], pad_model.geometry
    with pytest.raises(ValueError, match="support.type = 'sideways'"):
        abutment_pairs(pad, 0, g.pad, SupportGeometry(type="sideways"))
    with pytest.raises(ValueError, match="support.clearance = -0.001 m"):
        abutment_pairs(pad, 0, g.pad, SupportGeometry(type="push", clearance=-1e-3))
    with pytest.raises(ValueError, match="names no facets 'abutment_trailing'"):
        abutment_pairs(type(pad)(pad.p, pad.t), 0, g.pad, SupportGeometry(type="push"))


def test_compliant_step_with_abutments_tends_to_the_rigid_contact(pad_model):
    # the implicit wear step's solver with the abutments as rigid stops: as the
    # layer's compliance vanishes it gives the Lagrange solve's pressure and
    # abutment forces (first order in the compliance)
    support = SupportGeometry(type="push", clearance=1e-4)
    K, f, fixed, coords, pairs, Ks, F = _pad_system(pad_model, support, MU)
    ref = solve_contact(K, f, fixed, coords, pairs, linear="direct", tol=1e-11)
    base = compliant_preconditioner(K, fixed, coords, supports=pairs[1:])
    errs, ferrs = [], []
    for eps in (1e-13, 1e-14, 1e-15):
        res = solve_compliant_contact(K, f, fixed, coords, pairs[0],
                                      np.full(pairs[0].slave.size, eps), solver=base,
                                      supports=pairs[1:], tol=1e-11)
        assert res.info["normal_force"] == pytest.approx(F, rel=1e-8)
        errs.append(np.abs(res.pressure - ref.pressure[0]).max() / ref.pressure[0].max())
        ferrs.append(abs(res.info["support_normal_force"][0] - ref.info["normal_force"][1])
                     / ref.info["normal_force"][1])
        assert not res.support_active[1].any() and res.support_active[0].any()
        assert np.all(res.support_gap[0] > -1e-10) and np.all(res.support_force[1] == 0)
    assert errs[1] < errs[0] / 5 and errs[2] < errs[1] / 5 and errs[2] < 1e-3, errs
    assert ferrs[2] < 1e-3 and ferrs[2] < ferrs[0], ferrs
    # a compliant solve without supports is unchanged by an empty list
    cs = pad_model.contact_system(1e6, MU)
    eps = np.full(cs.pair.slave.size, 1e-14)
    a = solve_compliant_contact(cs.K, cs.f, cs.fixed, cs.coords, cs.pair, eps)
    b = solve_compliant_contact(cs.K, cs.f, cs.fixed, cs.coords, cs.pair, eps, supports=[])
    assert np.array_equal(a.u, b.u) and b.support_force == []


class _PushModel(BrakeModel):
    """The rigid-rotor brake with a push support in its contact system (what the
    model assembles for a push support: stops, springs, no in-plane Dirichlet)."""

    support = SupportGeometry(type="push", clearance=1e-4)

    def contact_system(self, *args, **kw):
        return with_supports(super().contact_system(*args, **kw), self.meshes["pad"],
                             self.offsets["pad"], self.geometry.pad, self.support)


def test_the_fe_interface_carries_the_supports_into_both_solve_paths():
    from brakewear.interfaces import FEInterface

    model = _PushModel(rotor="rigid", size=6e-3)
    iface = FEInterface(model, 1e6, mu=MU)
    assert [s.name for s in iface.supports] == ["abutment trailing (inboard)",
                                               "abutment leading (inboard)"]
    cs = model.contact_system(1e6, MU)
    ref = solve_contact(cs.K, cs.f, cs.fixed, cs.coords, [cs.pair, *cs.supports],
                        linear="direct", tol=1e-11)
    zero = np.zeros(iface.pair.slave.size)
    lag = iface.solve(zero, None)
    scale = ref.pressure[0].max()
    assert np.abs(lag.pressure - ref.pressure[0]).max() < 1e-6 * scale
    assert lag.info["support_normal_force"][0] == pytest.approx(ref.info["normal_force"][1],
                                                                rel=1e-6)
    again = iface.solve(zero, lag.active)       # a wear step's start: the last sets
    assert np.abs(again.pressure - lag.pressure).max() < 1e-6 * scale
    eps = np.full(zero.size, 1e-15)
    comp = iface.solve(zero, lag.active, compliance=eps, x0=lag.u)
    assert np.abs(comp.pressure - ref.pressure[0]).max() < 1e-3 * scale
    assert comp.info["support_normal_force"][0] == pytest.approx(
        ref.info["normal_force"][1], rel=1e-3)
    assert iface.at_line_pressure(2e6).cs.supports is iface.cs.supports


def test_with_supports_releases_exactly_the_bilateral_support(pad_model):
    pad, off = pad_model.meshes["pad"], pad_model.offsets["pad"]
    cs = pad_model.contact_system(1e6, 0.0)
    push = with_supports(cs, pad, off, pad_model.geometry.pad, SupportGeometry(type="push"))
    released = np.setdiff1d(cs.fixed, push.fixed)
    assert np.array_equal(released, 3 * off + boundary_dofs(pad, "abutment", [0, 1]))
    assert with_supports(cs, pad, off, pad_model.geometry.pad, SupportGeometry()) is cs
    assert cs.supports == [] and len(push.supports) == 2


def test_quadratic_pad_balances_under_a_push_support():
    model = BrakeModel(rotor="rigid", size=12e-3, order=2)
    support = SupportGeometry(type="push", clearance=1e-4)
    pad, off = model.meshes["pad"], model.offsets["pad"]
    cs = with_supports(model.contact_system(1e6, MU), pad, off, model.geometry.pad, support)
    assert cs.supports[0].basis is not None
    res = solve_contact(cs.K, cs.f, cs.fixed, cs.coords, [cs.pair, *cs.supports],
                        linear="direct")
    F = cs.clamp_force
    assert res.info["normal_force"][0] == pytest.approx(F, rel=1e-8)
    c = model.geometry.pad.center_angle
    tang = np.array([-np.sin(c), np.cos(c), 0.0])
    drag = (res.friction[0].sum(axis=1)) @ tang
    stop = res.info["normal_force"][1] * cs.supports[0].normal[:, 0] @ tang
    Ks = support_springs(pad, off, model.geometry.pad, support, model.dofs)
    u = cs.P @ res.u
    spring = -(Ks @ u).reshape(-1, 3).sum(axis=0) @ tang
    assert stop + spring == pytest.approx(-drag, rel=1e-8)
    assert res.info["normal_force"][2] == 0


def test_the_condensed_interface_refuses_abutment_stops():
    from brakewear.errors import WearError
    from brakewear.interfaces import CondensedInterface

    model = _PushModel(rotor="rigid", size=10e-3)
    with pytest.raises(WearError, match="2 abutment stop pair"):
        CondensedInterface(model, 1e6)


def test_two_pads_in_one_mesh_each_bear_on_their_own_trailing_stop(pad_model):
    # the full model's layout: the inboard pad (z > 0) and its mirror below a 20 mm
    # rotor (z < -20 mm) as one body, each pressed on its rotor face, dragged in +theta
    pad, g = pad_model.meshes["pad"], pad_model.geometry
    n, t_rotor = pad.p.shape[1], 0.02
    cs = pad_model.contact_system(1e6, MU)
    lo = pad.p * np.array([[1.0], [1.0], [-1.0]]) - np.array([[0.0], [0.0], [t_rotor]])
    both = type(pad)(np.hstack([pad.p, lo]), np.hstack([pad.t, pad.t[[0, 2, 1, 3]] + n]))
    tf = g.pad.friction_thickness
    both = both.with_boundaries({
        f"abutment_{end}": (lambda X, e=end: _on_end(pad_model, X, e)
                            & ((X[2] > tf) | (X[2] < -t_rotor - tf)))
        for end in ("leading", "trailing")})
    S = sp.diags(np.tile([1.0, 1.0, -1.0], n))                 # the mirror on DOFs
    K = sp.block_diag([cs.K, S @ cs.K @ S], format="csr")     # cs.K: the pad alone
    f = np.concatenate([cs.f, S @ cs.f])
    pr = cs.pair
    out = ContactPair(pr.slave + n, pr.area, -pr.normal, pr.g0, None, MU, pr.drag, "out")
    support = SupportGeometry(type="push", clearance=1e-4)
    stops = abutment_pairs(both, 0, g.pad, support)
    Ks = support_springs(both, 0, g.pad, support, 6 * n)
    res = solve_contact((K + Ks).tocsr(), f, np.zeros(0, dtype=int), both.p,
                        [pr, out, *stops], linear="direct")
    F = cs.clamp_force
    assert res.info["normal_force"][:2] == pytest.approx([F, F], rel=1e-8)
    c = g.pad.center_angle
    tang = np.array([-np.sin(c), np.cos(c), 0.0])
    u = res.u.reshape(-1, 3)
    for k, side in enumerate(("inboard", "outboard")):
        assert stops[k].name == f"abutment trailing ({side})"
        assert stops[2 + k].name == f"abutment leading ({side})"
        drag = res.friction[k].sum(axis=1) @ tang
        stop = res.info["normal_force"][2 + k] * stops[k].normal[:, 0] @ tang
        nodes = slice(0, n) if side == "inboard" else slice(n, 2 * n)
        spring = -(Ks @ res.u).reshape(-1, 3)[nodes].sum(axis=0) @ tang
        assert stop + spring == pytest.approx(-drag, rel=1e-8), side
        assert res.info["normal_force"][4 + k] == 0.0
    # mirror symmetry: the outboard pad's in-plane displacement is the inboard one's
    assert np.abs(u[n:, :2] - u[:n, :2]).max() < 1e-6 * np.abs(u[:n, :2]).max()


def test_the_floating_calipers_two_pads_balance_on_their_push_stops():
    # the packaged floating caliper (push support, 0.2 mm clearance) as the full model:
    # both pads in one body against both rotor faces, an elastic rotor
    from brakewear.geometry.files import geometry_dir

    model = BrakeModel(str(geometry_dir() / "floating.toml"), size=8e-3)
    g = model.geometry
    assert model.layout == "full" and g.support.type == "push"
    pad, off = model.meshes["pad"], model.offsets["pad"]
    cs = model.contact_system(1e6, MU)      # the model puts its stops in the system
    assert len(cs.supports) == 4
    res = solve_contact(cs.K, cs.f, cs.fixed, cs.coords, [cs.pair, *cs.supports])
    u = cs.P @ res.u
    n = pad.p.shape[1]
    forces = np.zeros((model.n_nodes, 3))
    pr = cs.pair
    np.add.at(forces, pr.slave, (pr.normal * res.force[0] + res.friction[0]).T)
    for s, lam in zip(cs.supports, res.force[1:]):
        np.add.at(forces, s.slave, (s.normal * lam).T)
    Ks = support_springs(pad, off, g.pad, g.support, model.dofs)
    forces -= (Ks @ u).reshape(-1, 3)
    assert np.array_equal(cs.col, np.arange(model.n_nodes))  # no ties: retained = global
    forces += cs.f.reshape(-1, 3)
    x = model.coordinates()
    F = cs.clamp_force
    tang = end_normal(g.pad, "leading") + end_normal(g.pad, "trailing")
    tang /= np.linalg.norm(tang)
    names = [s.name for s in cs.supports]
    mid = -0.5 * g.rotor.thickness
    for side, sel in (("inboard", x[2, off:off + n] > mid), ("outboard", x[2, off:off + n] < mid)):
        nodes = off + np.flatnonzero(sel)
        fsum, msum = _resultant(forces[nodes], x[:, nodes])
        R = np.hypot(x[0, nodes], x[1, nodes]).max()
        assert np.abs(fsum).max() < 1e-8 * F and np.abs(msum).max() < 1e-8 * F * R, side
        trailing = res.info["normal_force"][1 + names.index(f"abutment trailing ({side})")]
        leading = res.info["normal_force"][1 + names.index(f"abutment leading ({side})")]
        # the trailing stop takes the pad's drag (its tangential component), the
        # leading one stays open
        drag = res.friction[0][:, np.isin(pr.slave, nodes)].sum(axis=1) @ tang
        stop = cs.supports[names.index(f"abutment trailing ({side})")].normal[:, 0] @ tang
        assert leading == 0.0 and trailing * stop == pytest.approx(-drag, rel=1e-3), side


def test_a_pad_apart_from_the_rotor_while_its_stop_touches_starts_at_first_touch():
    """A push-type pad on a rigid rotor with every face node apart (a worn, coned
    rotor between stops): the bearing stop touches, the rotor does not; the first
    solve starts the rotor contact at its closest nodes instead of leaving the pad
    free to move toward the rotor (a singular system)."""
    from brakewear.interfaces import FEInterface

    m = BrakeModel("floating", rotor="rigid", size=8e-3)
    itf = FEInterface(m, 1e6, 0.4)
    r = itf.r
    offset = 5e-6 + 30e-6 * (r - r.min()) / (r.max() - r.min())   # apart everywhere
    sol = itf.solve(offset, None, mu=0.4)
    F = 1e6 * m.geometry.clamp_area
    assert (sol.pressure * itf.area).sum() == pytest.approx(F, rel=1e-8)
    assert sol.active.any() and not sol.active.all()
