"""Parametric brake meshes: volumes, named facets, orientation, meshio round trip."""
from __future__ import annotations

import numpy as np
import pytest
import skfem as fem

from brakewear.errors import MeshFileError
from brakewear.geometry import load_geometry
from brakewear.mesh import (
    brake_meshes,
    component_materials,
    element_materials,
    read_mesh,
    write_mesh,
)


@pytest.fixture(scope="module")
def geom():
    return load_geometry("default")


@pytest.fixture(scope="module")
def meshes(geom):
    return brake_meshes(geom)


@pytest.fixture(scope="module")
def meshes_p2(geom):
    # a coarse P2 set keeps the test fast
    return brake_meshes(geom, size=5e-3, order=2)


def tet_volumes(m):
    """Signed volumes of the straight (P1) tetrahedra."""
    x = m.p[:, m.t]
    a, b, c = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0], x[:, 3] - x[:, 0]
    return np.einsum("ij,ij->j", a, np.cross(b, c, axis=0)) / 6.0


def volume(m, elements=None):
    """Volume by quadrature; exact for the isoparametric map of a MeshTet2."""
    el = fem.ElementTetP2() if isinstance(m, fem.MeshTet2) else fem.ElementTetP1()
    basis = fem.Basis(m, el, intorder=4, elements=elements)
    return float(basis.dx.sum())


def closed_forms(g):
    r, p, s = g.rotor, g.pad, g.piston
    sector = 0.5 * p.arc_angle * (p.outer_radius ** 2 - p.inner_radius ** 2)
    return {
        "rotor": np.pi * (r.outer_radius ** 2 - r.inner_radius ** 2) * 0.5 * r.thickness,
        "friction_layer": sector * p.friction_thickness,
        "backplate": sector * p.backplate_thickness,
        "piston": 0.25 * np.pi * s.diameter ** 2 * s.length,
    }


def test_default_mesh_size(meshes):
    total = sum(m.nvertices for m in meshes.values())
    counts = {k: (m.nvertices, m.t.shape[1]) for k, m in meshes.items()}
    assert 20_000 <= total <= 60_000, f"default brake has {total} nodes {counts}; want 20k-60k"
    for k, m in meshes.items():
        assert isinstance(m, fem.MeshTet), f"{k}: {type(m).__name__}"


def test_p1_volumes_within_chord_error(geom, meshes):
    ref = closed_forms(geom)
    h, r_ref = geom.mesh.size, 0.5 * (geom.pad.inner_radius + geom.pad.outer_radius)
    # a polygon of n chords has area (1 - dtheta^2/6 + ...) times the circle's
    bounds = {
        "rotor": (geom.mesh.rotor_coarse_factor * h / r_ref) ** 2 / 6 * 1.1,
        "friction_layer": (h / r_ref) ** 2 / 6 * 1.1,
        "backplate": (h / r_ref) ** 2 / 6 * 1.1,
        "piston": (h / (0.5 * geom.piston.diameter)) ** 2 / 6 * 1.5,
    }
    vols = {
        "rotor": tet_volumes(meshes["rotor"]).sum(),
        "friction_layer": tet_volumes(meshes["pad"])[
            meshes["pad"].subdomains["friction_layer"]
        ].sum(),
        "backplate": tet_volumes(meshes["pad"])[meshes["pad"].subdomains["backplate"]].sum(),
        "piston": tet_volumes(meshes["piston"]).sum(),
    }
    for k, v in vols.items():
        rel = (ref[k] - v) / ref[k]
        # P1 chords lie inside the circle: the volume is a little too small
        assert -1e-12 <= rel <= bounds[k], (
            f"{k}: volume {v:.6e} vs {ref[k]:.6e}, rel {rel:.2e}, bound {bounds[k]:.2e}"
        )


def test_p2_volumes_much_closer(geom, meshes_p2):
    ref = closed_forms(geom)
    p1 = brake_meshes(geom, size=5e-3, order=1)
    pairs = {"rotor": ("rotor", None), "friction_layer": ("pad", "friction_layer"),
             "backplate": ("pad", "backplate"), "piston": ("piston", None)}
    for k, (body, sub) in pairs.items():
        m2, m1 = meshes_p2[body], p1[body]
        el2 = None if sub is None else m2.subdomains[sub]
        el1 = None if sub is None else m1.subdomains[sub]
        e2 = abs(volume(m2, el2) - ref[k]) / ref[k]
        e1 = abs(volume(m1, el1) - ref[k]) / ref[k]
        # isoparametric P2: error ~ dtheta^4 (8e-6 on the 25-sided piston), P1 ~ dtheta^2
        assert e2 < 5e-5 and e2 < e1 / 50, f"{k}: P2 rel error {e2:.2e}, P1 {e1:.2e}"


def _jacobians_positive(m):
    if isinstance(m, fem.MeshTet2):
        basis = fem.Basis(m, fem.ElementTetP2(), intorder=4)
        det = basis.mapping.detDF(basis.X)
        return det.min(), det.max()
    v = tet_volumes(m)
    return v.min(), v.max()


@pytest.mark.parametrize("which", ["p1", "p2"])
def test_no_inverted_elements(which, meshes, meshes_p2):
    ms = meshes if which == "p1" else meshes_p2
    for k, m in ms.items():
        lo, hi = _jacobians_positive(m)
        assert lo > 1e-6 * hi, f"{which} {k}: Jacobian range [{lo:.3e}, {hi:.3e}]"


def _nodes(m, name):
    return m.p[:, np.unique(m.facets[:, m.boundaries[name]])]


def test_named_facets_lie_where_they_should(geom, meshes):
    r, p, s = geom.rotor, geom.pad, geom.piston
    top = p.friction_thickness + p.backplate_thickness
    xc, yc = geom.piston_center
    tol = 1e-12
    rot, pad, pis = meshes["rotor"], meshes["pad"], meshes["piston"]
    expected = {
        "rotor": ["friction", "midplane", "rotor_clamp", "outer"],
        "pad": [
            "friction",
            "back",
            "piston_face",
            "abutment",
            "leading",
            "trailing",
            "inner",
            "outer",
        ],
        "piston": ["piston_face", "piston_back", "piston_side"],
    }
    for body, names in expected.items():
        m = meshes[body]
        for nm in names:
            assert len(m.boundaries.get(nm, [])) > 0, (
                f"{body}: facet set {nm!r} is empty or missing"
            )
        # every boundary facet has a name
        named = np.unique(np.concatenate([m.boundaries[nm] for nm in names]))
        unnamed = np.setdiff1d(m.boundary_facets(), named)
        assert unnamed.size == 0, f"{body}: {unnamed.size} boundary facets have no name"

    def rad(x):
        return np.hypot(x[0], x[1])

    checks = [
        ("rotor friction z", _nodes(rot, "friction")[2], 0.0),
        ("rotor midplane z", _nodes(rot, "midplane")[2], -0.5 * r.thickness),
        ("rotor clamp r", rad(_nodes(rot, "rotor_clamp")), r.inner_radius),
        ("rotor outer r", rad(_nodes(rot, "outer")), r.outer_radius),
        ("pad friction z", _nodes(pad, "friction")[2], 0.0),
        ("pad back z", _nodes(pad, "back")[2], top),
        ("pad piston_face z", _nodes(pad, "piston_face")[2], top),
        ("pad inner r", rad(_nodes(pad, "inner")), p.inner_radius),
        ("pad outer r", rad(_nodes(pad, "outer")), p.outer_radius),
        ("pad leading theta", np.arctan2(*_nodes(pad, "leading")[[1, 0]]), p.leading_angle),
        ("pad trailing theta", np.arctan2(*_nodes(pad, "trailing")[[1, 0]]), p.trailing_angle),
        ("piston face z", _nodes(pis, "piston_face")[2], top),
        ("piston back z", _nodes(pis, "piston_back")[2], top + s.length),
        ("piston side r", np.hypot(_nodes(pis, "piston_side")[0] - xc,
                                   _nodes(pis, "piston_side")[1] - yc), 0.5 * s.diameter),
    ]
    for label, vals, want in checks:
        err = np.abs(vals - want).max()
        assert err < 1e-9 * max(1.0, abs(want)) + tol, (
            f"{label}: max |value - {want:.6g}| = {err:.3e}"
        )
    # the leading edge is where rotor points (moving in +theta) arrive: the smaller angle
    assert p.leading_angle < p.trailing_angle
    # abutment = backplate part of both end faces
    ab = _nodes(pad, "abutment")
    assert ab[2].min() >= p.friction_thickness - 1e-12, f"abutment reaches z = {ab[2].min():.4e}"
    ends = np.union1d(pad.boundaries["leading"], pad.boundaries["trailing"])
    assert np.isin(pad.boundaries["abutment"], ends).all()
    # piston_face of the pad: centroids inside the piston footprint
    c = pad.p[:, pad.facets[:, pad.boundaries["piston_face"]]].mean(axis=1)
    d = np.hypot(c[0] - xc, c[1] - yc)
    assert d.max() < 0.5 * s.diameter, (
        f"pad piston_face centroid at {d.max():.4e} from the piston axis"
    )
    area = _area(pad, "piston_face")
    want = np.pi * (0.5 * s.diameter) ** 2
    assert abs(area - want) / want < 0.15, (
        f"pad piston_face area {area:.4e} vs footprint {want:.4e}"
    )


def _area(m, name):
    f = m.facets[:, m.boundaries[name]]
    a, b, c = (m.p[:, f[i]] for i in range(3))
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a, axis=0), axis=0).sum()


def test_friction_areas(geom, meshes):
    p, r = geom.pad, geom.rotor
    got = _area(meshes["pad"], "friction")
    assert abs(got - p.area) / p.area < 1e-3, f"pad friction area {got:.5e} vs {p.area:.5e}"
    ring = np.pi * (r.outer_radius ** 2 - r.inner_radius ** 2)
    got = _area(meshes["rotor"], "friction")
    assert abs(got - ring) / ring < 2e-3, f"rotor friction area {got:.5e} vs {ring:.5e}"


def test_periodic_ring_closed(meshes):
    m = meshes["rotor"]
    key = np.round(m.p.T / 1e-9).astype(np.int64)
    n_unique = np.unique(key, axis=0).shape[0]
    assert n_unique == m.p.shape[1], f"{m.p.shape[1] - n_unique} duplicate rotor nodes"
    # no seam: every boundary facet is on one of the four named faces
    named = sum(len(m.boundaries[k]) for k in ("friction", "midplane", "rotor_clamp", "outer"))
    assert named == len(m.boundary_facets()), (
        f"{len(m.boundary_facets())} boundary facets, {named} named"
    )


def _edge_lengths_at(m, name, theta_lo, theta_hi):
    f = m.facets[:, m.boundaries[name]]
    c = m.p[:, f].mean(axis=1)
    th = np.arctan2(c[1], c[0])
    sel = (th > theta_lo) & (th < theta_hi)
    x = m.p[:, f[:, sel]]
    return np.concatenate(
        [np.linalg.norm(x[:, i] - x[:, j], axis=0) for i, j in ((0, 1), (1, 2), (0, 2))]
    )


def test_rotor_graded_and_comparable_to_pad(geom, meshes):
    p = geom.pad
    pad_h = np.median(_edge_lengths_at(meshes["pad"], "friction", -np.pi, np.pi))
    rot_h = np.median(
        _edge_lengths_at(meshes["rotor"], "friction", p.leading_angle, p.trailing_angle)
    )
    far_h = np.median(_edge_lengths_at(meshes["rotor"], "friction", np.pi - 0.3, np.pi))
    assert 0.67 < rot_h / pad_h < 1.5, (
        f"rotor edge {rot_h:.3e} vs pad edge {pad_h:.3e} under the pad"
    )
    assert far_h > 2.0 * rot_h, f"rotor away from the pad {far_h:.3e} not coarser than {rot_h:.3e}"
    # through the thickness: finest at the friction face
    z = np.unique(np.round(meshes["rotor"].p[2], 12))
    dz = np.diff(z)
    assert dz[-1] < dz[0], f"rotor z cells: {dz[0]:.3e} at midplane, {dz[-1]:.3e} at z = 0"
    assert dz[-1] <= 0.55 * geom.mesh.size, f"first rotor layer {dz[-1]:.3e} m thick"


def test_size_argument_changes_mesh(geom):
    coarse = brake_meshes(geom, size=6e-3)
    fine = brake_meshes(geom, size=3e-3)
    for k in coarse:
        assert fine[k].nvertices > 2 * coarse[k].nvertices, \
            f"{k}: {fine[k].nvertices} nodes at 3 mm vs {coarse[k].nvertices} at 6 mm"
    with pytest.raises(ValueError, match="order"):
        brake_meshes(geom, size=6e-3, order=3)
    with pytest.raises(ValueError, match="size"):
        brake_meshes(geom, size=-1.0)


def test_materials_per_element(geom, meshes):
    cm = component_materials(geom)
    assert set(cm) == {"rotor", "pad", "piston"}
    for body, mapping in cm.items():
        pairs = element_materials(meshes[body], mapping)
        n = sum(len(idx) for idx, _ in pairs)
        assert n == meshes[body].t.shape[1], f"{body}: {n} of {meshes[body].t.shape[1]} elements"
    pad = dict((mat.name, idx) for idx, mat in element_materials(meshes["pad"], cm["pad"]))
    zc = meshes["pad"].p[2, meshes["pad"].t].mean(axis=0)
    assert (zc[pad["pad_resin"]] < geom.pad.friction_thickness).all()
    assert (zc[pad["steel"]] > geom.pad.friction_thickness).all()
    with pytest.raises(ValueError, match="no subdomain 'friction_layer'"):
        element_materials(meshes["rotor"], cm["pad"])


def test_subdomain_volumes(geom, meshes):
    ref = closed_forms(geom)
    pad = meshes["pad"]
    for k in ("friction_layer", "backplate"):
        v = volume(pad, pad.subdomains[k])
        assert abs(v - ref[k]) / ref[k] < 1e-3, f"{k}: {v:.6e} vs {ref[k]:.6e}"


def test_write_read_round_trip(tmp_path, geom, meshes, meshes_p2):
    pad = meshes["pad"]
    z = pad.p[2]
    path = write_mesh(tmp_path / "pad", pad, point_data={"z": z},
                      cell_data={"id": np.arange(pad.t.shape[1])})
    assert path.suffix == ".vtu" and path.exists()
    back = read_mesh(path, required=["friction", "piston_face"])
    assert np.allclose(back.p, pad.p, rtol=0, atol=1e-14 * np.abs(pad.p).max())
    assert np.array_equal(np.sort(back.t, axis=0), np.sort(pad.t, axis=0))
    for k, f in pad.boundaries.items():
        assert np.array_equal(np.sort(back.boundaries[k]), np.sort(f)), f"boundary {k!r} changed"
    for k, e in pad.subdomains.items():
        assert np.array_equal(np.sort(back.subdomains[k]), np.sort(e)), f"subdomain {k!r} changed"
    # MeshTet2: written as its P1 vertices and cells
    m2 = meshes_p2["piston"]
    path2 = write_mesh(tmp_path / "piston2.vtu", m2, point_data={"u": np.zeros(m2.p.shape[1])})
    back2 = read_mesh(path2)
    assert back2.p.shape[1] == m2.nvertices and back2.t.shape == m2.t.shape
    assert set(back2.boundaries) == set(m2.boundaries)


def test_read_tagged_surfaces(tmp_path):
    import meshio

    m = fem.MeshTet.init_tensor(*(np.linspace(0, 1, 3),) * 3)
    bottom = m.facets_satisfying(lambda x: x[2] < 1e-12, boundaries_only=True)
    top = m.facets_satisfying(lambda x: x[2] > 1 - 1e-12, boundaries_only=True)
    tris = m.facets[:, np.concatenate([bottom, top])].T
    extra = np.vstack([m.p.T, [[5.0, 5.0, 5.0]]])  # an unused point (gmsh files have them)
    cells = [("tetra", m.t.T), ("triangle", tris)]
    tags = np.concatenate([np.full(len(bottom), 1), np.full(len(top), 2)])
    mio = meshio.Mesh(extra, cells,
                      cell_data={"gmsh:physical": [np.full(m.t.shape[1], 3), tags]},
                      field_data={"friction": np.array([1, 2]), "back": np.array([2, 2]),
                                  "block": np.array([3, 3])})
    path = tmp_path / "block.msh"
    mio.write(path, file_format="gmsh22", binary=False)
    back = read_mesh(path, required=["friction", "back"])
    assert back.p.shape[1] == m.p.shape[1]
    tol = 1e-12 * np.abs(back.p).max()
    assert np.allclose(back.p[2, back.facets[:, back.boundaries["friction"]]], 0.0, atol=tol)
    assert len(back.boundaries["friction"]) == len(bottom)
    assert np.allclose(back.p[2, back.facets[:, back.boundaries["back"]]], 1.0, rtol=0, atol=tol)
    assert len(back.subdomains["block"]) == m.t.shape[1]
    # triangle cell sets; the VTU writer stores them as cell data (-1 = not in the set)
    mio2 = meshio.Mesh(m.p.T, cells, cell_sets={"friction": [np.array([], dtype=int),
                                                            np.arange(len(bottom))]})
    path2 = tmp_path / "sets.vtu"
    mio2.write(path2)
    got = read_mesh(path2, required=["friction"])
    assert np.array_equal(np.sort(got.boundaries["friction"]), np.sort(bottom)), \
        f"friction facets {np.sort(got.boundaries['friction'])} vs {np.sort(bottom)}"
    with pytest.raises(
        MeshFileError, match=r"rotor_clamp.*groups found: surfaces \['back', 'friction'\]"
    ):
        read_mesh(path, required=["rotor_clamp"])


def test_read_without_tets_fails(tmp_path):
    import meshio

    path = tmp_path / "tris.vtu"
    meshio.Mesh(np.eye(3), [("triangle", np.array([[0, 1, 2]]))]).write(path)
    with pytest.raises(MeshFileError, match="no tetrahedra.*triangle"):
        read_mesh(path)
