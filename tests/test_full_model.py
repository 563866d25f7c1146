"""The full brake model: both pads, the whole rotor, the caliper's loads.

Where the half model's assumption holds (equal pistons on both sides, a rotor
symmetric about its mid-plane) the full model must give the half model's
answer; where it does not (fingers) it must differ the way the load path says.
Every pad must be in force and moment balance.
"""
from dataclasses import replace

import numpy as np
import pytest
import skfem as fem

from brakewear import Numerics, WearLaw
from brakewear.errors import SceneError
from brakewear.fem.footprint import annulus, footprint_load
from brakewear.geometry import CaliperGeometry, FingerGeometry, load_geometry
from brakewear.interfaces import FEInterface
from brakewear.mesh.brake import pad_mesh, rotor_mesh
from brakewear.mesh.mirror import mirrored_pads
from brakewear.mesh.surface import face_nodes
from brakewear.mesh.triangle import subdivided_rule, tri6
from brakewear.model import BrakeModel
from brakewear.static import pad_balance, solve_contact, solve_tied, static_summary
from brakewear.wear import Run, wear_history

SIZE = 6e-3


@pytest.fixture(scope="module")
def rim():
    g = load_geometry()
    return replace(g, piston=replace(g.piston, rim_inner_diameter=0.030))


@pytest.fixture(scope="module")
def floating(rim):
    fingers = tuple(FingerGeometry(0.020, 0.127, np.radians(a)) for a in (-12.0, 12.0))
    return replace(rim, caliper=CaliperGeometry("floating", fingers))


def _volume(mesh):
    e = fem.ElementTetP2() if isinstance(mesh, fem.MeshTet2) else fem.ElementTetP1()
    return fem.Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(fem.Basis(mesh, e))


@pytest.mark.parametrize("order", [1, 2])
def test_mirrored_pads_are_two_pads(rim, order):
    pad = pad_mesh(rim, size=SIZE, order=order)
    both = mirrored_pads(pad, -0.5 * rim.rotor.thickness)
    assert _volume(both) == pytest.approx(2 * _volume(pad), rel=1e-12)
    for name in pad.boundaries:
        assert both.boundaries[name].size == 2 * pad.boundaries[name].size
    t = rim.rotor.thickness
    out = face_nodes(both, "friction_out")
    assert np.allclose(both.p[2, out], -t, rtol=0, atol=1e-12 * t)
    assert face_nodes(both, "friction").size == 2 * face_nodes(pad, "friction").size


def test_rotor_full_thickness_faces(rim):
    m = rotor_mesh(rim, size=SIZE, full=True)
    t = rim.rotor.thickness
    assert m.p[2].min() == pytest.approx(-t) and m.p[2].max() == pytest.approx(0.0)
    assert "midplane" not in m.boundaries
    assert m.boundaries["friction"].size == 2 * m.boundaries["friction_in"].size


def test_subdivided_rule_integrates_quadratic_shape_functions_exactly():
    # int N_i dA / A: 0 at the vertices, 1/3 at the edges of the P2 triangle
    for level in (0, 2):
        lam, w = subdivided_rule(level)
        assert w.sum() == pytest.approx(1.0, rel=1e-14)
        assert np.allclose(tri6(lam) @ w, [0, 0, 0, 1 / 3, 1 / 3, 1 / 3], rtol=0, atol=1e-14)


@pytest.mark.parametrize("order", [1, 2])
def test_footprint_load_resultant_and_centre_are_mesh_independent(rim, order):
    c = rim.piston_center
    centres = []
    for size in (6e-3, 3e-3):
        pad = pad_mesh(rim, size=size, order=order)
        f = footprint_load(pad, "back", annulus(c, 0.015, 0.020), 1000.0).reshape(-1, 3)
        assert f.sum(axis=0) == pytest.approx([0.0, 0.0, -1000.0], abs=1e-9 * 1000.0)
        centres.append((f[:, 2] @ pad.p[0] / f[:, 2].sum(), f[:, 2] @ pad.p[1] / f[:, 2].sum()))
    # the annulus' centre to a small share of the element size on either mesh
    for cx, cy in centres:
        assert np.hypot(cx - c[0], cy - c[1]) < 0.02 * 3e-3


def test_footprint_outside_the_face_is_refused(rim):
    pad = pad_mesh(rim, size=SIZE)
    with pytest.raises(ValueError, match="does not overlap"):
        footprint_load(pad, "back", annulus((1.0, 1.0), 0.0, 0.01), 1.0)


def _face_pressures(model, res, face):
    """``(x, y) -> pressure`` of a face's nodes, sorted by position (comparable across
    layouts: the full model's outboard pad is the mirror image of the inboard one)."""
    pad = model.meshes["pad"]
    name = "friction" if not model.full else f"friction_{face}"
    mask = np.isin(res.interface_nodes, face_nodes(pad, name))
    xy = np.round(pad.p[:2, res.interface_nodes[mask]], 9)
    order = np.lexsort(xy)
    return xy[:, order], res.interface_pressure[mask][order]


@pytest.mark.parametrize("footprint", ["disc", "rim"])
@pytest.mark.parametrize("mu", [0.0, 0.4])
def test_full_model_equals_half_model_where_the_half_holds(rim, footprint, mu):
    """The same footprint gives the same nodal loads in both layouts (one quadrature
    of the exact footprint), so where the half model's assumption holds it is the
    full model's answer node by node, for the default brake's disc as for a rim."""
    g = rim if footprint == "rim" else load_geometry()
    half = BrakeModel(g, size=SIZE, layout="half")
    full = BrakeModel(g, size=SIZE, layout="full")
    assert BrakeModel(g, size=SIZE).layout == "half"          # auto: the assumption holds
    rh = solve_contact(half, 1e6, mu=mu, tol=1e-12)
    rf = solve_contact(full, 1e6, mu=mu, tol=1e-12)
    xh, ph = _face_pressures(half, rh, "in")
    for face in ("in", "out"):
        xf, pf = _face_pressures(full, rf, face)
        np.testing.assert_array_equal(xf, xh)
        err = np.abs(pf - ph).max() / ph.max()
        assert err < 1e-7, f"{footprint}, mu {mu}, face {face}: half and full differ by {err:.2e}"


def test_one_footprint_gives_one_nodal_load_in_both_layouts():
    """The inboard pad's clamp load of the half model is the full model's, to round-off."""
    half = BrakeModel("default", size=SIZE, layout="half")
    full = BrakeModel("default", size=SIZE, layout="full")
    n = half.meshes["pad"].p.shape[1]
    fh, ff = half.loads(1e6), full.loads(1e6)
    oh, of = 3 * half.offsets["pad"], 3 * full.offsets["pad"]
    # the mirrored pad mesh keeps the inboard pad's nodes first, in their order
    np.testing.assert_array_equal(full.meshes["pad"].p[:, :n], half.meshes["pad"].p)
    np.testing.assert_allclose(ff[of:of + 3 * n], fh[oh:oh + 3 * n], rtol=0,
                               atol=1e-12 * np.abs(fh).max())


def test_fingers_move_the_outboard_pressure_outward(floating):
    m = BrakeModel(floating, size=SIZE)
    assert m.layout == "full"                                    # auto: fingers break symmetry
    res = solve_contact(m, 1e6, mu=0.4)
    s = static_summary(m, res)
    F = 1e6 * floating.clamp_area
    for face in ("in", "out"):
        assert s["faces"][face]["normal_force_N"] == pytest.approx(F, rel=1e-8)
    r_in = s["faces"]["in"]["centre_of_pressure_r_m"]
    r_out = s["faces"]["out"]["centre_of_pressure_r_m"]
    # fingers at 127 mm, piston at 116.5 mm: the outboard centre moves out by millimetres
    assert r_out - r_in > 0.003
    bal = pad_balance(m, res, 1e6)
    for face in ("in", "out"):
        assert bal[face]["force"] < 1e-8 and bal[face]["moment"] < 1e-8
    assert bal["caliper"]["force"] < 1e-12
    # the pins carry the moment of the finger force's offset: F (x_fingers - x_piston)
    x_f = 0.127 * np.cos(np.radians(12.0))
    assert bal["caliper"]["pin_moment_Nm"][1] == pytest.approx(F * (x_f - 0.1165), rel=0.02)


@pytest.mark.parametrize("solve", ["tied", "contact"])
def test_each_pad_is_in_balance(rim, solve):
    m = BrakeModel(rim, size=SIZE, layout="full")
    res = solve_tied(m, 1e6) if solve == "tied" else solve_contact(m, 1e6, mu=0.4)
    bal = pad_balance(m, res, 1e6)
    for face in ("in", "out"):
        assert bal[face]["force"] < 1e-8 and bal[face]["moment"] < 1e-8


def test_full_model_wears_both_pads_as_the_half_model(rim):
    law = WearLaw(5e-15)
    vols = {}
    for layout in ("half", "full"):
        m = BrakeModel(rim, size=SIZE, layout=layout)
        itf = FEInterface(m, 1e6, 0.4)
        for s in wear_history(  # noqa: B007  (the last step)
            Run(
                m,
                1e6,
                55.0,
                3600.0,
                law,
                WearLaw(5e-16),
                0.4,
                numerics=Numerics(scheme="implicit", update="gap", steps=4),
                interface=itf,
            )
        ):
            pass
        out = (np.isin(itf.pad_nodes, face_nodes(m.meshes["pad"], "friction_out")) if m.full
               else np.zeros(itf.pad_nodes.size, dtype=bool))
        vols[layout] = [(s.pad_wear * itf.area)[~out].sum(), (s.pad_wear * itf.area)[out].sum()]
        # each rotor face keeps its own rings: the rotor's worn volume is the pads' share
        assert s.rotor_wear.max() > 0
    assert vols["full"][0] == pytest.approx(vols["half"][0], rel=1e-3)
    assert vols["full"][1] == pytest.approx(vols["half"][0], rel=1e-3)


def test_layouts_refused_by_name(rim):
    with pytest.raises(SceneError, match="layout = 'sideways'"):
        BrakeModel(rim, size=SIZE, layout="sideways")
    with pytest.raises(SceneError, match="rigid"):
        BrakeModel(rim, size=SIZE, layout="full", rotor="rigid")


def test_a_full_scene_runs_and_pictures_both_faces(tmp_path):
    """A floating-caliper scene (auto: the full model) end to end: both pads wear,
    the outboard one further out (the fingers), one figure per face."""
    import meshio

    from brakewear.output.runs import run_scene
    from brakewear.scene import Scene
    from brakewear.scene.spec import InterfaceSpec

    g = load_geometry("floating")
    g = replace(g, mesh=replace(g.mesh, size=8e-3, friction_layers=2, backplate_layers=2,
                                rotor_layers=2, rotor_size=12e-3))
    scene = Scene(geometry=g, duration=300.0, interface=InterfaceSpec(mu=0.4))
    summary = run_scene(scene, tmp_path)
    assert summary["final"]["pad_wear_max_m"] > 0
    for name in ("pad_wear_in.png", "pad_wear_out.png", "pad_pressure_in.png",
                 "pad_pressure_out.png"):
        assert (tmp_path / name).stat().st_size > 10_000
    model = scene.build_model()
    assert model.layout == "full"
    pad = model.meshes["pad"]
    w = meshio.read(sorted(tmp_path.glob("pad_*.vtu"))[-1]).point_data["pad_wear"]
    r = np.hypot(pad.p[0], pad.p[1])
    centre = {side: (w * r)[face_nodes(pad, f"friction_{side}")].sum()
              / w[face_nodes(pad, f"friction_{side}")].sum() for side in ("in", "out")}
    assert centre["out"] > centre["in"] + 2e-3


def test_meshed_piston_and_fixed_calipers_with_two_pistons_per_side():
    g = load_geometry("floating")
    # the meshed piston on the inboard pad, the fingers on the outboard one
    m = BrakeModel(g, size=8e-3, piston="body")
    s = static_summary(m, solve_contact(m, 1e6, mu=0.4))["faces"]
    F = 1e6 * g.clamp_area
    assert s["in"]["normal_force_N"] == pytest.approx(F, rel=1e-8)
    assert s["out"]["normal_force_N"] == pytest.approx(F, rel=1e-8)
    # a fixed caliper with two opposed 40 mm pistons per side, +-12 deg
    p1 = replace(g.piston, diameter=0.040, rim_inner_diameter=0.036, bore_diameter=0.040,
                 radius=0.119, angle=np.radians(-12.0))
    fixed = replace(g, caliper=CaliperGeometry("fixed"), piston=p1,
                    extra_pistons=(replace(p1, angle=np.radians(12.0)),))
    assert fixed.clamp_area == pytest.approx(2 * np.pi * 0.020 ** 2)
    m = BrakeModel(fixed, size=8e-3)
    res = solve_contact(m, 1e6, mu=0.4)
    s = static_summary(m, res)["faces"]
    for face in ("in", "out"):
        assert s[face]["normal_force_N"] == pytest.approx(1e6 * fixed.clamp_area, rel=1e-8)
    bal = pad_balance(m, res, 1e6)
    assert max(bal["in"].values()) < 1e-8 and max(bal["out"].values()) < 1e-8


def test_geometry_update_and_thermal_coupling_on_both_faces(rim):
    """Where the half model holds, the full model's geometry update and heating
    give the half model's answer on both faces."""
    from brakewear.thermal import ThermalModel

    law, rlaw = WearLaw(5e-15), WearLaw(5e-16)
    out = {}
    for layout in ("half", "full"):
        m = BrakeModel(rim, size=SIZE, layout=layout)
        for s in wear_history(  # noqa: B007  (the last step)
            Run(
                m,
                1e6,
                55.0,
                72000.0,
                law,
                rlaw,
                0.4,
                numerics=Numerics(scheme="implicit", update="geometry", steps=3),
            )
        ):
            pass
        m = BrakeModel(rim, size=SIZE, layout=layout)
        th = ThermalModel(m)
        for _ in wear_history(
            Run(
                m,
                1e6,
                55.0,
                30.0,
                law,
                rlaw,
                0.4,
                thermal=th,
                interface=FEInterface(m, 1e6, 0.4),
                numerics=Numerics(scheme="implicit", update="gap", steps=3),
            )
        ):
            pass
        pad = m.meshes["pad"]
        faces = ("friction_in", "friction_out") if m.full else ("friction",)
        out[layout] = {"wear": s.pad_wear.max(), "p": s.pressure.max(),
                       "T": [th.T["pad"][face_nodes(pad, f)].max() for f in faces]}
    h, f = out["half"], out["full"]
    assert f["wear"] == pytest.approx(h["wear"], rel=1e-3)
    assert f["p"] == pytest.approx(h["p"], rel=1e-3)
    rise = h["T"][0] - 293.15
    for T in f["T"]:
        assert abs(T - h["T"][0]) < 0.02 * rise


def test_the_full_rotor_mesh_is_its_own_mirror_image(rim):
    """Both halves of the full ring are meshed alike: each tetrahedron's mirror
    image through the mid-plane is a tetrahedron of the mesh (so, with the
    mirrored pads, a load and its mirror image give mirrored answers)."""
    m = rotor_mesh(rim, size=8e-3, full=True)
    t = rim.rotor.thickness
    key = np.round(m.p / (1e-9 * t)).astype(np.int64)
    mirrored = key.copy()
    mirrored[2] = np.round((-t - m.p[2]) / (1e-9 * t)).astype(np.int64)
    index = {tuple(k): i for i, k in enumerate(key.T)}
    image = np.array([index[tuple(k)] for k in mirrored.T])      # KeyError: not a node
    tets = {tuple(sorted(c)) for c in m.t.T}
    assert {tuple(sorted(image[c])) for c in m.t.T} == tets


def _face_contact(itf, pressure, mask):
    """(contact fraction by area, radial centre of pressure (m)) of one face."""
    a, p, r = itf.area[mask], pressure[mask], itf.r[mask]
    return a[p > 0].sum() / a.sum(), (p * a * r).sum() / (p * a).sum()


def test_opposite_coning_mirrors_the_coverage_of_the_two_faces(rim):
    """A rotor coned by +c (rim dished toward the outboard side: the gap opens at
    the outer radius on the inboard face, at the inner radius on the outboard
    face) is the mirror image of one coned by -c: with equal pistons on both
    sides, the inboard face under +c has the contact of the outboard face
    under -c, and the other way round.  Pads and rotor are meshed as mirror
    images, so the two contact problems are the same problem with the nodes
    numbered differently: the active sets match exactly and the centres of
    pressure to the contact solve's tolerance."""
    from brakewear.cleaning.corrosion import outboard_nodes
    from brakewear.scene import Scene
    from brakewear.scene.spec import InterfaceSpec

    c, tol = 30e-6, 1e-10
    contact = {}
    for sign in (1, -1):
        scene = Scene(geometry=rim, layout="full", mesh_size=8e-3,
                      interface=InterfaceSpec(mu=0.4, coning=sign * c))
        model = scene.build_model()
        itf = FEInterface(model, 1e6, 0.4, tol)
        gap = scene.initial_gap(itf.x)
        out = outboard_nodes(itf.x, rim.rotor.thickness)
        p = itf.solve(gap, None).pressure
        contact[sign] = {"in": _face_contact(itf, p, ~out), "out": _face_contact(itf, p, out)}
        if sign == 1:     # the number is the per-face table {inboard = c, outboard = -c}
            table = Scene(geometry=rim, layout="full", mesh_size=8e-3,
                          interface=InterfaceSpec(mu=0.4, coning={"inboard": c,
                                                                  "outboard": -c}))
            assert np.array_equal(table.initial_gap(itf.x), gap)
            # the inboard gap opens toward the outer radius, the outboard one inward
            r_in, r_out = itf.r[~out], itf.r[out]
            assert gap[~out][r_in.argmax()] > 0.9 * c * (r_in.max() - r_in.min()) / (
                rim.pad.outer_radius - rim.pad.inner_radius)
            assert gap[out][r_out.argmin()] == pytest.approx(gap[~out][r_in.argmax()],
                                                             rel=1e-12)
    band = rim.pad.outer_radius - rim.pad.inner_radius
    for face, other in (("in", "out"), ("out", "in")):
        frac, r_cp = contact[1][face]
        frac_m, r_cp_m = contact[-1][other]
        assert frac == pytest.approx(frac_m, rel=1e-12)
        assert r_cp == pytest.approx(r_cp_m, rel=100 * tol)
    # and the coning matters: the faces of one rotor bear at opposite edges
    assert contact[1]["out"][1] - contact[1]["in"][1] > 0.3 * band
