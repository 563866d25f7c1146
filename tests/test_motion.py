"""Geometry update of worn surfaces (brakewear.motion.brake)."""
import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import skfem as fem

from brakewear.contact.surface import mortar_coupling
from brakewear.errors import MeshError
from brakewear.fem import assemble_stiffness, stiffness_update
from brakewear.mesh.surface import surface_nodes, tributary_areas
from brakewear.model import BrakeModel
from brakewear.motion.brake import (
    BrakeMotion,
    MeshQualityError,
    SurfaceFollower,
    check_quality,
    element_quality,
    element_volumes,
    surface_element_height,
)
from brakewear.static import solve_contact

COARSE = 6e-3  # m: a coarse brake, a second to build and assemble


def _model(size=COARSE, assemble=True, **kw):
    m = BrakeModel(size=size, **kw)
    if assemble:
        for b in m.bodies:
            m.stiffness(b)
    return m


def _face(m, body):
    mesh = m.meshes[body]
    return mesh.p[:, surface_nodes(mesh, "friction")]


def _taper(m, depth):
    """Pad wear rising linearly from 0 at the leading edge to ``depth`` at the trailing one."""
    x = _face(m, "pad")
    th = np.arctan2(x[1], x[0])
    return depth * (th - th.min()) / np.ptp(th)


def _radial(m, depth):
    """Rotor wear ``depth`` over the pad track, rising linearly with the radius."""
    x = _face(m, "rotor")
    g = m.geometry.pad
    r = np.hypot(x[0], x[1])
    s = (r - g.inner_radius) / (g.outer_radius - g.inner_radius)
    return np.where((s >= 0) & (s <= 1), depth * (0.5 + 0.5 * s), 0.0)


def _rel(A, B):
    A, B = sp.csr_matrix(A), sp.csr_matrix(B)
    return spla.norm(A - B) / spla.norm(B)


# ------------------------------------------------------------- measures --

def test_element_quality_regular_flat_and_inverted():
    p = np.array([[1.0, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]]).T
    t = np.array([[0, 1, 2, 3]]).T
    m = fem.MeshTet(p, t)
    if element_volumes(m)[0] < 0:
        m = fem.MeshTet(p, t[[0, 2, 1, 3]])
    assert element_quality(m)[0] == pytest.approx(1.0, rel=1e-12)
    flat = fem.MeshTet(m.p * np.array([[1.0], [1.0], [1e-3]]), m.t, validate=False)
    assert 0 < element_quality(flat)[0] < 0.02
    inv = fem.MeshTet(m.p * np.array([[1.0], [1.0], [-1.0]]), m.t, validate=False)
    assert element_quality(inv)[0] == pytest.approx(-1.0, rel=1e-12)
    with pytest.raises(MeshQualityError, match=r"step 7: cube element 0 .*inverted"):
        check_quality(inv, "cube", step=7)
    with pytest.raises(ValueError, match="min_quality"):
        check_quality(m, min_quality=1.5)


def test_surface_element_height_is_first_layer_thickness():
    m = _model(assemble=False)
    pad = m.meshes["pad"]
    h = surface_element_height(pad, "friction")
    z = np.unique(np.round(pad.p[2], 12))
    assert h.shape == surface_nodes(pad, "friction").shape
    # Kuhn tetrahedra on the face reach exactly one layer up
    np.testing.assert_allclose(h, z[1], rtol=1e-9)
    with pytest.raises(MeshError, match="nope"):
        surface_element_height(pad, "nope")


# -------------------------------------------------- stiffness updates --

def test_subset_assembly_adds_up_to_full():
    m = _model(assemble=False)
    pad, mats = m.meshes["pad"], m.materials["pad"]
    K, pat = assemble_stiffness(pad, mats)
    half = np.arange(0, pad.nelements, 2)
    rest = np.arange(1, pad.nelements, 2)
    Ka, _ = assemble_stiffness(pad, mats, pattern=pat, elements=half)
    Kb, _ = assemble_stiffness(pad, mats, pattern=pat, elements=rest)
    assert _rel(Ka + Kb, K) < 1e-14
    with pytest.raises(ValueError, match="out of range"):
        assemble_stiffness(pad, mats, pattern=pat, elements=np.array([pad.nelements]))


def test_stiffness_update_checks_its_input():
    m = _model(assemble=False)
    pad = m.meshes["pad"]
    K, pat = assemble_stiffness(pad, m.materials["pad"])
    other = m.meshes["rotor"]
    with pytest.raises(ValueError, match="same elements"):
        stiffness_update(K, pat, pad, other, m.materials["pad"], np.array([0]))
    with pytest.raises(ValueError, match="3x3-block"):
        stiffness_update(K.tocsr(), pat, pad, pad, m.materials["pad"], np.array([0]))


@pytest.mark.parametrize("kind", ["uniform", "taper"])
def test_partial_reassembly_equals_full(kind):
    m = _model()
    mo = BrakeMotion(m)
    tf = m.geometry.pad.friction_thickness
    hp = np.full(mo.pad_wear.size, 0.3 * tf) if kind == "uniform" else _taper(m, 0.3 * tf)
    hr = _radial(m, 0.5e-3)
    # two successive steps: the second updates an already updated matrix
    for step, s in enumerate((0.5, 1.0), start=1):
        st = mo.apply(s * hp, s * hr, step=step)
        for b in m.bodies:
            K, pattern = mo.model.assembled(b)
            Kf, _ = assemble_stiffness(mo.model.meshes[b], m.materials[b], pattern=pattern)
            err = _rel(K, Kf)
            assert err < 1e-12, f"{b} step {step}: partial vs full reassembly {err:.2e}"
    # only the band moved: the backplate's elements and the rotor's deep layers are kept
    assert 0 < st["pad"]["moved_elements"] < st["pad"]["elements"]
    assert 0 < st["rotor"]["moved_elements"] < 0.5 * st["rotor"]["elements"]


# ---------------------------------------------------------- the motion --

def test_worn_volume_equals_depth_times_area():
    m = _model(assemble=False)
    mo = BrakeMotion(m)
    V0 = {b: element_volumes(m.meshes[b]).sum() for b in m.bodies}
    area = {b: tributary_areas(m.meshes[b], "friction") for b in m.bodies}
    hp, hr = _taper(m, 2e-3) + 1e-4, _radial(m, 3e-4)
    mo.apply(hp, hr)
    for b, h in (("pad", hp), ("rotor", hr)):
        dV = V0[b] - element_volumes(mo.model.meshes[b]).sum()
        expect = float((h * area[b]).sum())
        # the faces move along z over a fixed triangulation and the side
        # faces are vertical: the swept volume is int h dA = sum h A exactly
        assert dV == pytest.approx(expect, rel=1e-9), f"{b}: {dV:.6e} vs {expect:.6e}"
        assert mo.worn_volume()[b] == pytest.approx(expect, rel=1e-12)


def test_face_moves_by_wear_along_normal_and_backplate_stays():
    m = _model(assemble=False)
    ref = {b: m.meshes[b].p.copy() for b in m.bodies}
    old_pad = m.meshes["pad"]
    mo = BrakeMotion(m)
    tf = m.geometry.pad.friction_thickness
    hp, hr = _taper(m, 0.5 * tf), _radial(m, 1e-3)
    mo.apply(hp, hr, step=3)
    pad, rot = mo.model.meshes["pad"], mo.model.meshes["rotor"]
    assert pad is not old_pad, "the worn geometry must be a new mesh object"
    assert m.meshes["pad"] is old_pad, "the model passed in must not change"
    np.testing.assert_array_equal(old_pad.p, ref["pad"])  # the old mesh is untouched
    # pad face recedes away from the rotor (+z), rotor face into the rotor (-z)
    sp_, sr = surface_nodes(pad, "friction"), surface_nodes(rot, "friction")
    # differences of coordinates: round-off relative to the coordinates' size
    tol_p, tol_r = (1e-13 * np.abs(ref[b][2]).max() for b in ("pad", "rotor"))
    np.testing.assert_allclose(pad.p[2, sp_] - ref["pad"][2, sp_], hp, rtol=0, atol=tol_p)
    np.testing.assert_allclose(rot.p[2, sr] - ref["rotor"][2, sr], -hr, rtol=0, atol=tol_r)
    np.testing.assert_array_equal(pad.p[:2], ref["pad"][:2])
    np.testing.assert_array_equal(rot.p[:2], ref["rotor"][:2])
    # backplate nodes (z >= friction thickness) and the rotor below the band: not a bit moved
    back = ref["pad"][2] >= tf * (1 - 1e-12)
    assert back.sum() > 0
    np.testing.assert_array_equal(pad.p[:, back], ref["pad"][:, back])
    deep = ref["rotor"][2] <= -mo.depths["rotor"] * (1 - 1e-12)
    np.testing.assert_array_equal(rot.p[:, deep], ref["rotor"][:, deep])
    # every node in between follows its column linearly
    # (structured numbering: z runs fastest, so node s + k is k layers above face node s)
    for k in range(1, int(np.count_nonzero(np.unique(ref["pad"][2]) < tf))):
        nodes = sp_ + k
        np.testing.assert_array_equal(ref["pad"][:2, nodes], ref["pad"][:2, sp_])
        z = ref["pad"][2, nodes]
        np.testing.assert_allclose(pad.p[2, nodes] - z, (1 - z / tf) * hp, rtol=0, atol=tol_p)
    # subdomains, facets and topology come along
    assert set(pad.subdomains) == {"friction_layer", "backplate"}
    np.testing.assert_array_equal(pad.boundaries["friction"], old_pad.boundaries["friction"])
    np.testing.assert_array_equal(pad.t, old_pad.t)


@pytest.mark.parametrize("kind", ["uniform", "taper"])
def test_pad_worn_to_half_friction_layer_keeps_quality(kind):
    """The must-show: the default brake's pad worn to half its friction layer
    (uniformly, and tapered leading -> trailing) has no inverted element and
    its quality stays above 0.3 (0.56 new; measured 0.376 / 0.374)."""
    m = _model(size=None, assemble=False)
    mo = BrakeMotion(m)
    tf = m.geometry.pad.friction_thickness
    hp = np.full(mo.pad_wear.size, 0.5 * tf) if kind == "uniform" else _taper(m, 0.5 * tf)
    q0 = element_quality(m.meshes["pad"]).min()
    # in 10 steps, as a wear loop would
    for k in range(1, 11):
        st = mo.apply(k / 10 * hp, step=k)
    q = element_quality(mo.model.meshes["pad"])
    assert q.min() > 0.3, f"{kind}: min quality {q.min():.3f} (new pad {q0:.3f})"
    assert st["pad"]["min_quality"] == pytest.approx(q.min())
    pad_now = mo.model.meshes["pad"]
    assert np.abs(pad_now.p[2, surface_nodes(pad_now, "friction")]
                  - hp).max() < 1e-13 * m.geometry.pad.thickness   # coordinate round-off
    # the first layer is half as thick where the pad is worn by half
    # (tapered: a face tetrahedron reaches up a neighbouring column, worn a little differently)
    h1 = surface_element_height(mo.model.meshes["pad"], "friction")
    z1 = np.unique(np.round(mo.reference["pad"][2], 12))[1]
    np.testing.assert_allclose(h1, z1 * (1 - hp / tf), rtol=1e-9 if kind == "uniform" else 0.05)


def test_excessive_wear_is_refused_naming_the_step():
    m = _model()
    mo = BrakeMotion(m)
    tf = m.geometry.pad.friction_thickness
    good = np.full(mo.pad_wear.size, 0.2 * tf)
    mo.apply(good, step=1)
    before = (mo.model.meshes["pad"], mo.model.assembled("pad")[0].data.copy())
    worn_through = good.copy()
    worn_through[5] = 1.1 * tf  # deeper than the friction layer
    with pytest.raises(MeshQualityError, match=r"step 42: pad element \d+ .*inverted.*"
                                               r"worn through the band") as err:
        mo.apply(worn_through, step=42)
    e = err.value
    assert e.step == 42 and e.body == "pad" and e.quality < 0 and e.element >= 0
    # nothing changed: the model is still in the last accepted geometry
    assert mo.model.meshes["pad"] is before[0]
    np.testing.assert_array_equal(mo.model.assembled("pad")[0].data, before[1])
    np.testing.assert_array_equal(mo.pad_wear, good)


def test_bad_input_is_refused_before_anything_moves():
    m = _model(assemble=False)
    mo = BrakeMotion(m)
    n, nr = mo.pad_wear.size, mo.rotor_wear.size
    pad0 = m.meshes["pad"]
    with pytest.raises(ValueError, match=rf"pad_wear has shape \({n - 1},\); need \({n},\)"):
        mo.apply(np.zeros(n - 1))
    with pytest.raises(ValueError, match=r"pad_wear\[3\] = -1e-05 m .* must be >= 0"):
        h = np.zeros(n)
        h[3] = -1e-5
        mo.apply(h)
    with pytest.raises(ValueError, match=r"rotor_wear\[0\] = nan .* finite"):
        mo.apply(np.zeros(n), np.full(nr, np.nan))
    with pytest.raises(ValueError, match=r"pad_wear\[1\] = inf"):
        mo.apply(np.array([0.0, np.inf] + [0.0] * (n - 2)))
    with pytest.raises(ValueError, match="reassembly = 'some'"):
        mo.apply(np.zeros(n), reassembly="some")
    with pytest.raises(ValueError, match="pad_depth"):
        BrakeMotion(m, pad_depth=1.0)
    with pytest.raises(ValueError, match="rotor_depth"):
        BrakeMotion(m, rotor_depth=-1e-3)
    with pytest.raises(ValueError, match="min_quality"):
        BrakeMotion(m, min_quality=0.0)
    assert mo.model.meshes["pad"] is pad0


def test_rigid_rotor_moves_pad_only():
    m = _model(rotor="rigid", assemble=False)
    mo = BrakeMotion(m)
    assert set(mo.followers) == {"pad"}
    with pytest.raises(ValueError, match="rigid rotor"):
        mo.apply(np.zeros(mo.pad_wear.size), np.ones(3))
    mo.apply(np.full(mo.pad_wear.size, 1e-3))
    cs = mo.model.contact_system(1e6)
    np.testing.assert_allclose(cs.pair.g0, 1e-3, rtol=0, atol=1e-10 * COARSE)


def test_follower_snaps_band_to_a_node_layer():
    m = _model(size=None, assemble=False)
    rot = m.meshes["rotor"]
    z = np.unique(np.round(rot.p[2], 12))[::-1]          # 0, -1.29, -2.98 mm, ...
    f = SurfaceFollower(rot, "friction", depth=2.0e-3)
    assert f.depth == pytest.approx(-z[2], rel=1e-9)
    assert not np.isin(np.nonzero(rot.p[2] <= z[2] + 1e-12)[0], f.band_nodes).any()
    with pytest.raises(ValueError, match="only .* deep"):
        SurfaceFollower(rot, "friction", depth=0.05)


# -------------------------------------------- the contact of the worn brake --

def _self_coupling(pad):
    """Segment weights of the (worn) pad face on itself: ``int phi_s phi_a / int phi_s``,
    integrated the way the contact pair integrates its weak gap."""
    slave = surface_nodes(pad, "friction")
    W, _, _ = mortar_coupling(pad, "friction", slave, pad, "friction", pad.nvertices)
    return W[:, slave]


def _rotor_face_coupling(m, cs):
    face = surface_nodes(m.meshes["rotor"], "friction")
    return cs.pair.coupling[:, cs.col[face + m.offsets["rotor"]]]


@pytest.mark.parametrize("method", ["segment", "node"])
def test_worn_gap_uniform_wear(method):
    m = _model()
    size = COARSE
    g_ref = m.contact_system(1e6, method=method).pair.g0
    mo = BrakeMotion(m)
    hp, hr = np.full(mo.pad_wear.size, 1.2e-3), np.full(mo.rotor_wear.size, 3e-4)
    mo.apply(hp, hr, step=1)
    cs = mo.model.contact_system(1e6, method=method)
    np.testing.assert_allclose(cs.pair.g0, g_ref + hp + 3e-4, rtol=0, atol=1e-10 * size)


def test_worn_gap_tapered_pad_flat_rotor():
    """Non-uniform pad wear: nodal gaps (node-to-surface) are h_pad + h_rot
    exactly; the segment method's weak gaps are the tributary-weighted mean
    of h_pad (the pad face's own mortar coupling) plus h_rot."""
    m = _model()
    size = COARSE
    g_node = m.contact_system(1e6, method="node").pair.g0
    g_seg = m.contact_system(1e6).pair.g0
    mo = BrakeMotion(m)
    hp = _taper(m, 2e-3)
    hr = np.full(mo.rotor_wear.size, 2e-4)
    mo.apply(hp, hr, step=1)
    Wself = _self_coupling(mo.model.meshes["pad"])
    np.testing.assert_allclose(mo.model.contact_system(1e6, method="node").pair.g0,
                               g_node + hp + 2e-4, rtol=0, atol=1e-10 * size)
    np.testing.assert_allclose(mo.model.contact_system(1e6).pair.g0,
                               g_seg + Wself @ hp + 2e-4, rtol=0, atol=1e-10 * size)


def test_worn_gap_radial_rotor_wear():
    """Rotor wear varying with r tilts the rotor facets: the normal gap is the
    vertical one times cos(tilt) = 1 - slope^2 / 2 (slope 0.007 here): the
    gap-offset formula g0 + W_self h_pad + W h_rot holds to that."""
    m = _model()
    cs0 = m.contact_system(1e6)
    W = _rotor_face_coupling(m, cs0)
    mo = BrakeMotion(m)
    x = _face(m, "rotor")
    r = np.hypot(x[0], x[1])
    hp, hr = _taper(m, 1e-3), 4e-4 * (r - r.min()) / np.ptp(r)
    mo.apply(hp, hr, step=1)
    Wself = _self_coupling(mo.model.meshes["pad"])
    expect = cs0.pair.g0 + Wself @ hp + W @ hr
    g0 = mo.model.contact_system(1e6).pair.g0
    err = np.abs(g0 - expect).max()
    slope = hr.max() / np.ptp(r)
    # 1 - cos(tilt) = slope^2 / 2 of the gap (measured 2.9e-8 m against 6.2e-8 m)
    assert err < slope ** 2 * g0.max(), f"gap error {err:.2e} m"


def test_worn_brake_solves_contact():
    """After the update the model still solves: same clamp force carried."""
    m = _model()
    mo = BrakeMotion(m)
    mo.apply(_taper(m, 1e-3), _radial(m, 2e-4), step=1)
    res = solve_contact(mo.model, 1e6)
    assert res.normal_force == pytest.approx(res.clamp_force, rel=1e-6)
    # the trailing edge is worn most, so it carries least
    x = mo.model.meshes["pad"].p[:, res.interface_nodes]
    th = np.arctan2(x[1], x[0])
    lead = res.interface_force[2][th < np.quantile(th, 0.2)].sum()
    trail = res.interface_force[2][th > np.quantile(th, 0.8)].sum()
    assert lead > trail


def test_piston_body_tie_survives_the_update():
    """The backplate does not move, so the piston stays tied to it exactly."""
    m = _model(piston="body", assemble=False)
    ties0 = m.ties(interface=False)
    piston0 = m.meshes["piston"]
    mo = BrakeMotion(m)
    mo.apply(_taper(m, 2e-3), _radial(m, 2e-4), step=1)
    ties1 = mo.model.ties(interface=False)
    for (s0, n0, w0), (s1, n1, w1) in zip(ties0, ties1):
        np.testing.assert_array_equal(s0, s1)
        np.testing.assert_array_equal(n0, n1)
        np.testing.assert_allclose(w1, w0, rtol=0, atol=1e-14)
    assert mo.model.meshes["piston"] is piston0 and "piston" not in mo.followers


def test_a_quadratic_face_moves_by_its_worn_coefficients():
    """P2: the depths are coefficients of the face's transformed basis; the face
    moves by their nodal values (curved edges included), so the weak gap of the
    moved geometry grows by exactly the coefficients, and the worn volume is
    ``area @ h``."""
    from brakewear import BrakeModel, FEInterface

    model = BrakeModel(size=1.2e-2, order=2)
    fe = FEInterface(model, 1e6, 0.4)
    motion = BrakeMotion(model)
    h = 2e-6 * (fe.r - fe.r.min()) / np.ptp(fe.r) * (1.0 + 0.3 * np.sin(9 * fe.x[1] / fe.r))
    motion.apply(h, np.zeros(fe.rotor_area.size))
    moved = fe.rebuilt(motion.model)
    assert np.abs((moved.g0 - fe.g0) - h).max() < 1e-12 * h.max()
    assert motion.worn_volume()["pad"] == pytest.approx(float(fe.area @ h), rel=1e-12)
    # the backplate stays, the band beneath the face follows
    fol = motion.followers["pad"]
    assert fol.depth == pytest.approx(model.geometry.pad.friction_thickness, rel=1e-9)
    assert fol.band_nodes.size > fol.nodes.size
