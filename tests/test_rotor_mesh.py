"""The hat and vented rotor meshes: volumes and facet areas against closed forms,
orientation, conformity, P2 geometry, the theta grid at the vanes, bad input."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import skfem as fem

from brakewear.caliper.geometry import HatGeometry, VentGeometry
from brakewear.geometry import load_geometry
from brakewear.mesh import rotor_mesh
from brakewear.mesh.rotor import full_rotor_mesh, rotor_volume, vane_edges
from brakewear.mesh.topology import ensure_topology

SIZE = 6e-3
HAT = HatGeometry(height=0.045, wall_radius=0.087, wall_thickness=0.006, flange_thickness=0.007,
                  bore_radius=0.033, bolt_circle_radius=0.057)
VENTS = VentGeometry(cheek_thickness=0.007, vane_count=37, vane_width=0.008)


def _rotor(g, **kw):
    return replace(g, rotor=replace(g.rotor, **kw))


@pytest.fixture(scope="module")
def geoms():
    g = load_geometry("default")
    return {"hat": _rotor(g, mount="hat", hat=HAT), "vents": _rotor(g, vents=VENTS),
            "hat+vents": _rotor(g, mount="hat", hat=HAT, vents=VENTS),
            # a wall that reaches under the ring: no neck
            "hat under ring": _rotor(g, mount="hat", hat=replace(HAT, wall_radius=0.093))}


@pytest.fixture(scope="module")
def meshes(geoms):
    return {(k, o): rotor_mesh(g, size=SIZE, order=o, full=True) for k, g in geoms.items()
            for o in (1, 2)}


def _basis(m, intorder=4):
    el = fem.ElementTetP2() if isinstance(m, fem.MeshTet2) else fem.ElementTetP1()
    return fem.Basis(m, el, intorder=intorder)


def _area(m, name):
    el = fem.ElementTetP2() if isinstance(m, fem.MeshTet2) else fem.ElementTetP1()
    return float(fem.FacetBasis(m, el, facets=m.boundaries[name], intorder=4).dx.sum())


def _vane_area(geom):
    ri, ro, a = geom.rotor.inner_radius, geom.rotor.outer_radius, 0.5 * geom.rotor.vents.vane_width

    def chord(R):
        return a * np.sqrt(R ** 2 - a ** 2) + R ** 2 * np.arcsin(a / R)
    return chord(ro) - chord(ri)


@pytest.mark.parametrize("key", ["hat", "vents", "hat+vents", "hat under ring"])
def test_volume_against_the_union_of_the_blocks(geoms, meshes, key):
    exact = rotor_volume(geoms[key])
    e1 = abs(_basis(meshes[key, 1]).dx.sum() / exact - 1)
    e2 = abs(_basis(meshes[key, 2]).dx.sum() / exact - 1)
    # P1: chords of the circles (relative error ~ dtheta^2 / 12 over the coarse arc)
    assert e1 < 1e-2, f"{key}: P1 volume off by {e1:.2e}"
    # P2: the isoparametric map represents the circles to second order
    assert e2 < 2e-5 and e2 < 1e-2 * e1, f"{key}: P2 volume off by {e2:.2e} (P1 {e1:.2e})"


def test_closed_form_volume_by_hand(geoms):
    g = geoms["hat"]
    t, ro = g.rotor.thickness, g.rotor.outer_radius
    ring = np.pi * (ro ** 2 - 0.084 ** 2) * t  # the neck continues the ring to the wall's inside
    wall = np.pi * (0.090 ** 2 - 0.084 ** 2) * (0.045 - 0.007)
    flange = np.pi * (0.090 ** 2 - 0.033 ** 2) * 0.007
    assert rotor_volume(g) == pytest.approx(ring + wall + flange, rel=1e-12)


@pytest.mark.parametrize("key", ["hat", "hat+vents"])
def test_friction_and_clamp_areas(geoms, meshes, key):
    g, m = geoms[key], meshes[key, 2]
    ring = np.pi * (g.rotor.outer_radius ** 2 - g.rotor.inner_radius ** 2)
    for name in ("friction_in", "friction_out"):
        assert _area(m, name) == pytest.approx(ring, rel=1e-5), name
    assert _area(m, "friction") == pytest.approx(2 * ring, rel=1e-5)
    clamp = np.pi * (HAT.bolt_circle_radius ** 2 - HAT.bore_radius ** 2)
    assert _area(m, "rotor_clamp") == pytest.approx(clamp, rel=1e-5)
    ro, t = g.rotor.outer_radius, g.rotor.thickness
    outer = 2 * np.pi * ro * t
    if g.rotor.vents is not None:  # the cheeks' rims and the vanes' ends (arcs of the circle)
        c, a = VENTS.cheek_thickness, 0.5 * VENTS.vane_width
        outer = 2 * np.pi * ro * 2 * c + VENTS.vane_count * 2 * ro * np.arcsin(a / ro) * (t - 2 * c)
    assert _area(m, "outer") == pytest.approx(outer, rel=1e-5)
    assert "midplane" not in m.boundaries


def test_vent_channel_walls(geoms, meshes):
    g, m = geoms["vents"], meshes["vents", 2]
    ri, ro, t = g.rotor.inner_radius, g.rotor.outer_radius, g.rotor.thickness
    a, n, c = 0.5 * VENTS.vane_width, VENTS.vane_count, VENTS.cheek_thickness
    cheeks = 2 * (np.pi * (ro ** 2 - ri ** 2) - n * _vane_area(g))
    sides = 2 * n * (np.sqrt(ro ** 2 - a ** 2) - np.sqrt(ri ** 2 - a ** 2)) * (t - 2 * c)
    assert _area(m, "vents") == pytest.approx(cheeks + sides, rel=1e-6)
    # no hat: the ring is held at its inner radius (cheeks and vane ends)
    inner = 2 * np.pi * ri * 2 * c + n * 2 * ri * np.arcsin(a / ri) * (t - 2 * c)
    assert _area(m, "rotor_clamp") == pytest.approx(inner, rel=1e-5)


@pytest.mark.parametrize("key", ["hat", "hat+vents"])
@pytest.mark.parametrize("order", [1, 2])
def test_positive_jacobians(meshes, key, order):
    m = meshes[key, order]
    b = _basis(m)
    det = b.mapping.detDF(b.X)
    assert det.min() > 0.0, f"{key} P{order}: {(det <= 0).sum()} non-positive Jacobians"
    # straight-sided check of the vertex tetrahedra, too
    x = m.p[:, m.t[:4]]
    v = np.einsum("ij,ij->j", x[:, 1] - x[:, 0], np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 0],
                                                          axis=0))
    assert v.min() > 0.0


def _inside(geom, X):
    """Point in the rotor (physical coordinates), from the closed-form section."""
    ro_, h = geom.rotor, geom.rotor.hat
    t, ri, ro = ro_.thickness, ro_.inner_radius, ro_.outer_radius
    r, z = np.hypot(X[0], X[1]), X[2]
    wi, wo = h.wall_radius - 0.5 * h.wall_thickness, h.wall_radius + 0.5 * h.wall_thickness
    ring = (r > ri) & (r < ro) & (z > -t) & (z < 0)
    if ro_.vents is not None:
        c = ro_.vents.cheek_thickness
        centres, _ = vane_edges(geom)
        ang = np.arctan2(X[1], X[0])[:, None] - centres[None]
        vane = ((np.abs(r[:, None] * np.sin(ang)) < 0.5 * ro_.vents.vane_width)
                & (np.cos(ang) > 0)).any(axis=1)
        ring &= ~((z > -t + c) & (z < -c)) | vane
    neck_top = -t + ro_.vents.cheek_thickness if ro_.vents is not None else 0.0
    neck = (r > min(ri, wi)) & (r < ro) & (z > -t) & (z < neck_top)
    wall = (r > wi) & (r < wo) & (z < -t) & (z > -t - h.height)
    flange = (r > h.bore_radius) & (r < wo) & (z > -t - h.height) & (z < -t - h.height
                                                                     + h.flange_thickness)
    return ring | neck | wall | flange


@pytest.mark.parametrize("key", ["hat", "hat+vents", "hat under ring"])
def test_conforming_every_boundary_facet_is_on_the_surface(geoms, meshes, key):
    """No hanging nodes: a facet left without its second tetrahedron inside the
    body would have material on both sides; every boundary facet must have the
    rotor on its inner side only."""
    m = meshes[key, 1]
    ensure_topology(m)
    bf = np.nonzero(m.f2t[1] == -1)[0]
    x = m.p[:, m.facets[:, bf]]
    mid = x.mean(axis=1)
    # a P1 facet on a cylinder is a chord: move its midpoint back onto the circle
    mid[:2] *= np.hypot(x[0], x[1]).mean(axis=0) / np.hypot(mid[0], mid[1])
    n = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0], axis=0)
    n /= np.linalg.norm(n, axis=0)
    # orient outward: away from the centroid of the owning tetrahedron
    cen = m.p[:, m.t[:, m.f2t[0, bf]]].mean(axis=1)
    n *= np.sign(np.einsum("ij,ij->j", n, mid - cen))
    eps = 2e-4  # below every feature of the section
    assert _inside(geoms[key], mid - eps * n).all()
    out = _inside(geoms[key], mid + eps * n)
    assert not out.any(), f"{key}: {out.sum()} boundary facets with material on both sides"
    # and every facet is shared by at most two tetrahedra with matching vertices
    assert np.unique(m.facets, axis=1).shape[1] == m.facets.shape[1]


def test_theta_grid_carries_every_vane_edge(geoms, meshes):
    g, m = geoms["vents"], meshes["vents", 1]
    centres, _ = vane_edges(g)
    w = VENTS.vane_width
    for r in (g.rotor.inner_radius, g.rotor.outer_radius):
        on_r = np.abs(np.hypot(m.p[0], m.p[1]) - r) < 1e-9
        ang = np.arctan2(m.p[1, on_r], m.p[0, on_r])
        for sgn in (-1.0, 1.0):
            target = centres + sgn * np.arcsin(0.5 * w / r)
            d = np.abs(np.angle(np.exp(1j * (ang[:, None] - target[None])))).min(axis=0)
            assert d.max() < 1e-9, f"vane edge missing at r = {r}"


def test_full_false_and_bad_hats_are_refused(geoms):
    with pytest.raises(ValueError, match="full=True"):
        rotor_mesh(geoms["hat"], size=SIZE)
    g = geoms["hat"]
    with pytest.raises(ValueError, match="does not meet the ring"):
        full_rotor_mesh(_rotor(g, hat=replace(HAT, wall_radius=0.080)), size=SIZE)
    with pytest.raises(ValueError, match="bolt_circle_radius"):
        full_rotor_mesh(_rotor(g, hat=replace(HAT, bolt_circle_radius=0.095)), size=SIZE)
    with pytest.raises(ValueError, match="rotor.hat is missing"):
        full_rotor_mesh(_rotor(g, hat=None), size=SIZE)
    with pytest.raises(ValueError, match="vane_width"):
        full_rotor_mesh(_rotor(g, vents=replace(VENTS, vane_width=0.02)), size=SIZE)
    with pytest.raises(ValueError, match="cheek_thickness"):
        full_rotor_mesh(_rotor(g, vents=replace(VENTS, cheek_thickness=0.013)), size=SIZE)


def test_plain_ring_unchanged(geoms):
    g = load_geometry("default")
    m = rotor_mesh(g, size=SIZE, full=True)
    assert set(m.boundaries) == {"friction_in", "friction_out", "friction", "rotor_clamp", "outer"}


def test_half_vented_ring_for_a_symmetric_model(geoms):
    """Without a hat a vented ring may be halved at its mid-plane (rotor_mesh's
    names); the half has half the volume, the vanes' mid-sections as midplane."""
    g = geoms["vents"]
    m = rotor_mesh(g, size=SIZE, order=2)
    assert set(m.boundaries) == {"friction", "midplane", "rotor_clamp", "outer", "vents"}
    assert _basis(m).dx.sum() == pytest.approx(0.5 * rotor_volume(g), rel=2e-5)
    assert _area(m, "midplane") == pytest.approx(VENTS.vane_count * _vane_area(g), rel=1e-5)
    ring = np.pi * (g.rotor.outer_radius ** 2 - g.rotor.inner_radius ** 2)
    assert _area(m, "friction") == pytest.approx(ring, rel=1e-5)
    with pytest.raises(ValueError, match="no mid-plane of symmetry"):
        full_rotor_mesh(geoms["hat+vents"], size=SIZE, half=True)


def test_packaged_hat_rotor_has_no_zero_width_cells():
    # floating.toml puts the hat wall's outer surface exactly at the ring's inner
    # radius (87 + 6/2 = 90 mm): round-off must not leave a cell of zero width there
    from brakewear.geometry import load_geometry
    from brakewear.motion.brake import element_volumes

    g = load_geometry("floating")
    m = rotor_mesh(g, size=8e-3, full=True)
    v = element_volumes(m)
    assert v.min() > 1e-3 * np.median(v)


def test_rotor_shapes_study(tmp_path):
    """studies/rotor_shapes.py (docs/geometry.md's figure) on a coarse mesh, without
    the picture: its closed forms are the ones worked out by hand above, and the
    meshes' volumes meet them."""
    from studyload import load_study

    res = load_study("rotor_shapes").main(size_mm=8.0, data=str(tmp_path), figure=False)
    g = load_geometry("floating")
    t, ri, ro = 0.024, 0.090, 0.150
    wall = np.pi * (0.090 ** 2 - 0.084 ** 2) * (0.042 - 0.007)
    flange = np.pi * (0.090 ** 2 - 0.033 ** 2) * 0.007
    vents = _rotor(g, vents=VentGeometry(0.008, 37, 0.006))
    hand = {"hat": np.pi * (ro ** 2 - 0.084 ** 2) * t + wall + flange,
            # the neck over the wall is the outboard cheek only; the channels less the vanes
            "vented": (np.pi * (ro ** 2 - ri ** 2) * t + np.pi * (ri ** 2 - 0.084 ** 2) * 0.008
                       + wall + flange
                       - (np.pi * (ro ** 2 - ri ** 2) - 37 * _vane_area(vents)) * (t - 0.016))}
    for name, row in res["rotors"].items():
        assert row["closed_form_m3"]["total"] == pytest.approx(hand[name], rel=1e-12)
        assert row["rotor_volume_m3"] == pytest.approx(hand[name], rel=1e-12)
        assert abs(row["orders"]["P1"]["rel_diff"]) < 1e-2, name
        assert abs(row["orders"]["P2"]["rel_diff"]) < 2e-5, name
        assert row["orders"]["P2"]["dofs"] > row["orders"]["P1"]["dofs"]
    assert (tmp_path / "rotor_mounts.json").exists()
