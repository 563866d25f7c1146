"""The pad mesh of a real pad: backplate larger than the lining, chamfers, a radial slot,
the piston rim.  Volumes and face areas against closed forms, positive Jacobians, P1 and P2."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import skfem as fem

from brakewear.geometry import load_geometry
from brakewear.mesh import pad_mesh

SIZE = 5e-3


@pytest.fixture(scope="module")
def geom():
    return load_geometry("floating")


@pytest.fixture(scope="module", params=[1, 2], ids=["P1", "P2"])
def mesh(request, geom):
    return pad_mesh(geom, size=SIZE, order=request.param)


def _element(m):
    return fem.ElementTetP2() if isinstance(m, fem.MeshTet2) else fem.ElementTetP1()


def _volume(m, sub):
    b = fem.Basis(m, _element(m), elements=m.subdomains[sub], intorder=4)
    return float(b.dx.sum())


def _area(m, name):
    b = fem.FacetBasis(m, _element(m), facets=m.boundaries[name], intorder=4)
    return float(b.dx.sum())


def _rel(m):
    """Tolerance of a volume or area: P1 chords cut the curved faces by O((h/r)^2)."""
    return 0.5 * (SIZE / 0.095) ** 2 if isinstance(m, fem.MeshTet1) else 1e-6


def _slot_area(pad):
    """Area of the slot's footprint in the lining: |distance to the centre line| < w/2."""
    a = 0.5 * pad.slot_width
    F = lambda r: 0.5 * r * r * math.asin(a / r) + 0.5 * a * math.sqrt(r * r - a * a)  # noqa: E731
    return 2.0 * (F(pad.outer_radius) - F(pad.inner_radius))


def _chamfer_area(pad, length, depth):
    """Area of a chamfer face z = depth (1 - (theta - end) / Theta), Theta = length / r_mean."""
    th = length / (0.5 * (pad.inner_radius + pad.outer_radius))
    g = depth / th
    G = lambda r: 0.5 * (r * math.sqrt(r * r + g * g) + g * g * math.asinh(r / g))  # noqa: E731
    return th * (G(pad.outer_radius) - G(pad.inner_radius))


def test_lining_and_backplate_volumes(geom, mesh):
    pad = geom.pad
    dr2 = pad.outer_radius ** 2 - pad.inner_radius ** 2
    r_mean = 0.5 * (pad.inner_radius + pad.outer_radius)
    wedges = sum(0.25 * d * (L / r_mean) * dr2 for L, d in (pad.leading_chamfer,
                                                           pad.trailing_chamfer))
    lining = 0.5 * pad.arc_angle * dr2 * pad.friction_thickness - wedges \
        - _slot_area(pad) * pad.friction_thickness
    bri, bro = pad.backplate_radii
    backplate = 0.5 * pad.arc_angle * (bro ** 2 - bri ** 2) * pad.backplate_thickness
    v = _volume(mesh, "friction_layer")
    assert v == pytest.approx(lining, rel=_rel(mesh)), f"lining {v} vs {lining}"
    v = _volume(mesh, "backplate")
    assert v == pytest.approx(backplate, rel=_rel(mesh)), f"backplate {v} vs {backplate}"


def test_friction_chamfer_and_slot_areas(geom, mesh):
    pad = geom.pad
    r_mean = 0.5 * (pad.inner_radius + pad.outer_radius)
    (ll, dl), (lt, dt) = pad.leading_chamfer, pad.trailing_chamfer
    dr2 = pad.outer_radius ** 2 - pad.inner_radius ** 2
    flat = 0.5 * (pad.arc_angle - (ll + lt) / r_mean) * dr2 - _slot_area(pad)
    lead, trail = _chamfer_area(pad, ll, dl), _chamfer_area(pad, lt, dt)
    assert _area(mesh, "leading_chamfer") == pytest.approx(lead, rel=_rel(mesh))
    assert _area(mesh, "trailing_chamfer") == pytest.approx(trail, rel=_rel(mesh))
    assert _area(mesh, "friction") == pytest.approx(flat + lead + trail, rel=_rel(mesh))
    a = 0.5 * pad.slot_width      # two plane walls and the floor (the backplate's front)
    walls = 2 * pad.friction_thickness * (math.sqrt(pad.outer_radius ** 2 - a * a)
                                          - math.sqrt(pad.inner_radius ** 2 - a * a))
    assert _area(mesh, "slot") == pytest.approx(walls + _slot_area(pad), rel=_rel(mesh))


def test_jacobians_positive_with_a_deep_chamfer(geom):
    pad = dataclasses.replace(geom.pad, leading_chamfer=(20e-3, 10e-3), slot_width=0.0)
    g = dataclasses.replace(geom, pad=pad)
    for order in (1, 2):
        m = pad_mesh(g, size=SIZE, order=order)
        b = fem.Basis(m, _element(m), intorder=4)
        det = m.mapping().detDF(b.X)
        assert det.min() > 0.0, f"order {order}: min det J = {det.min()}"
        # the chamfer shrinks the end elements to 0.5 / 10.5 of their height, no more
        assert det.min() > 0.02 * np.median(det), f"order {order}: {det.min()} vs {np.median(det)}"


def test_names_cover_the_boundary(geom, mesh):
    pad = geom.pad
    B = mesh.boundaries
    bf = np.flatnonzero(mesh.f2t[1] == -1)
    named = np.unique(np.concatenate(list(B.values())))
    assert np.array_equal(named, bf), "a boundary facet has no name"
    X = lambda name: mesh.p[:, mesh.facets[:, B[name]]].mean(axis=1)  # noqa: E731
    tf = pad.friction_thickness
    assert np.array_equal(np.union1d(B["abutment_leading"], B["abutment_trailing"]),
                          np.sort(B["abutment"]))
    for name in ("abutment_leading", "abutment_trailing"):
        assert (X(name)[2] > tf).all()
    assert np.isin(B["leading_chamfer"], B["friction"]).all()
    assert np.isin(B["trailing_chamfer"], B["friction"]).all()
    assert not np.isin(B["slot"], B["friction"]).any()
    # the piston rim: back facets between the rim's inner and outer circle
    xc, yc = geom.piston_center
    d = np.hypot(X("piston_face")[0] - xc, X("piston_face")[1] - yc)
    assert len(d) and (d >= 0.5 * geom.piston.rim_inner_diameter).all() \
        and (d < 0.5 * geom.piston.diameter).all()
    # the backplate's exposed front face beyond the lining is part of inner/outer
    z = X("inner")[2]
    assert np.isclose(z, tf, rtol=1e-9).any()


def test_partial_slot_depth(geom):
    pad = dataclasses.replace(geom.pad, slot_depth=4e-3, leading_chamfer=(0.0, 0.0),
                              trailing_chamfer=(0.0, 0.0))
    m = pad_mesh(dataclasses.replace(geom, pad=pad), size=SIZE, order=2)
    dr2 = pad.outer_radius ** 2 - pad.inner_radius ** 2
    lining = 0.5 * pad.arc_angle * dr2 * pad.friction_thickness - _slot_area(pad) * 4e-3
    assert _volume(m, "friction_layer") == pytest.approx(lining, rel=1e-6)
    floor = m.p[:, m.facets[:, m.boundaries["slot"]]].mean(axis=1)[2].max()
    assert floor == pytest.approx(4e-3, rel=1e-9)


def test_the_idealised_pad_has_no_new_faces():
    m = pad_mesh(load_geometry(), size=SIZE)
    for name in ("leading_chamfer", "trailing_chamfer", "slot"):
        assert name not in m.boundaries
    assert len(m.boundaries["abutment_leading"]) == len(m.boundaries["abutment_trailing"]) > 0


def test_pad_shape_study(tmp_path):
    """studies/pad_shape.py (docs/geometry.md's figure) on a coarse mesh, without the picture."""
    from studyload import load_study

    res = load_study("pad_shape").main(size_mm=5.0, out=str(tmp_path), data=str(tmp_path),
                                       figure=False)
    for key in ("lining_volume", "backplate_volume", "friction_area"):
        assert abs(res["orders"]["P2"][key]["rel_diff"]) < 1e-6, res["orders"]["P2"][key]
        assert abs(res["orders"]["P1"][key]["rel_diff"]) < 0.5 * (5 / 95) ** 2
    assert (tmp_path / "floating_pad.json").exists()


@pytest.mark.parametrize("suffix", [".msh", ".vtu"])
def test_floating_pad_round_trips_through_a_mesh_file(tmp_path, geom, suffix):
    from brakewear.mesh import read_mesh, write_mesh

    m = pad_mesh(geom, size=2 * SIZE)
    back = read_mesh(write_mesh(tmp_path / f"pad{suffix}", m))
    assert sorted(back.boundaries) == sorted(m.boundaries)
    for name in ("slot", "leading_chamfer", "abutment_trailing"):
        assert len(back.boundaries[name]) == len(m.boundaries[name]) > 0, name
