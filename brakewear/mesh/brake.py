"""Parametric tetrahedral meshes of brake components, with named surfaces and materials.

Every component (rotor ring, pad sector, piston) is a structured block of
hexahedra in *parametric* coordinates -- (r, theta, z) for the ring and the
pad, a mapped square for the piston disc -- split into six tetrahedra each
(:mod:`brakewear.mesh.structured`).  Grading is a matter of choosing the
coordinate arrays.  P2 meshes place their edge nodes with the same map, so
curved surfaces are represented exactly to second order (isoparametric).
"""
from __future__ import annotations

import logging
from typing import TYPE_CHECKING

import numpy as np
import skfem as fem

from ..errors import MeshError
from .grids import _body_size, _check_size_order, _n_cells, _ring_theta
from .pad_block import sector_pad_mesh
from .rotor import full_rotor_mesh
from .structured import _oriented, cylindrical, graded, mapped_mesh, structured_tets
from .topology import _with_boundaries, _with_subdomains

if TYPE_CHECKING:  # imported for annotations only: geometry sits above mesh
    from ..geometry import BrakeGeometry
    from ..materials import Material

logger = logging.getLogger(__name__)

__all__ = [
    "rotor_mesh",
    "pad_mesh",
    "piston_mesh",
    "brake_meshes",
    "component_materials",
    "element_materials",
]


def rotor_mesh(geom: BrakeGeometry, size: float | None = None, order: int | None = None,
               full: bool = False) -> fem.Mesh:
    """The inboard half of the rotor friction ring, a closed (periodic) ring
    (``full``: the whole thickness).

    ``z`` runs from ``-thickness/2`` (midplane) to ``0`` (friction face);
    with ``full`` from ``-thickness`` (outboard friction face) to ``0``, the
    grading mirrored about the mid-plane.  In
    theta the elements have the in-plane ``size`` (at the pad mid radius) over
    the pad arc plus ``geom.mesh.rotor_margin`` on both sides and grow to
    ``rotor_coarse_factor * size`` elsewhere; through the thickness they are
    ``size / 2`` thick at ``z = 0`` and grow by ``rotor_z_ratio``
    (``mesh.rotor_layers`` layers with that grading if set).  A hat rotor
    (``rotor.mount = "hat"``) or a vented ring is meshed whole, hat, cheeks
    and vanes, by :func:`brakewear.mesh.rotor.full_rotor_mesh` (a hat rotor
    needs ``full``; a vented ring without one may be halved).

    Parameters
    ----------
    geom : BrakeGeometry
        The checked brake geometry (SI units).
    size, order
        Override ``geom.mesh.size`` (m) and ``geom.mesh.order``; a body's own
        ``mesh.rotor_size`` / ``mesh.pad_size`` takes precedence over both
        sizes.

    Returns
    -------
    skfem.MeshTet or skfem.MeshTet2
        Facets ``friction`` (z = 0), ``midplane`` (z = -t/2), ``rotor_clamp``
        (inner radius) and ``outer``; subdomain ``rotor`` (all elements).
        With ``full``: ``friction_in`` (z = 0), ``friction_out`` (z = -t),
        ``friction`` (both), ``rotor_clamp`` and ``outer``, no ``midplane``.
    """
    ms, ro_ = geom.mesh, geom.rotor
    h, order = _check_size_order(_body_size(geom, size, "rotor"),
                                 ms.order if order is None else order)
    if ro_.mount == "hat" or ro_.vents is not None:
        if not full and ro_.mount == "hat":
            raise MeshError("rotor_mesh: a rotor with mount = 'hat' is meshed whole; "
                            "call with full=True")
        return full_rotor_mesh(geom, size, order, half=not full)
    ri, ro, half = ro_.inner_radius, ro_.outer_radius, 0.5 * ro_.thickness
    r = np.linspace(ri, ro, max(2, int(np.ceil((ro - ri) / h))) + 1)
    th = _ring_theta(geom, h)
    nz = ms.rotor_layers or _n_cells(half, 0.5 * h, ms.rotor_z_ratio)
    z = graded(-half, 0.0, nz, ms.rotor_z_ratio if nz > 1 else 1.0, "b")
    if full:     # the outboard half the mirror image of the inboard one, node for node
        z = np.concatenate([-2 * half - z[::-1], z[1:]])
    p, t = structured_tets(r, th, z, periodic_y=True, mirror_below=nz if full else None)
    m = mapped_mesh(p, t, cylindrical, order=order, period=np.array([0.0, 2 * np.pi, 0.0]))
    tol = 1e-9 * ro
    rmid = 0.5 * (ri + ro)

    bottom = -2 * half if full else -half

    def side(X):
        return (np.abs(X[2]) > tol) & (np.abs(X[2] - bottom) > tol)

    faces = {
        "rotor_clamp": lambda X: side(X) & (np.hypot(X[0], X[1]) < rmid),
        "outer": lambda X: side(X) & (np.hypot(X[0], X[1]) > rmid),
    }
    if full:
        faces.update({"friction": lambda X: ~side(X), "friction_in": lambda X: np.abs(X[2]) < tol,
                      "friction_out": lambda X: np.abs(X[2] - bottom) < tol})
    else:
        faces.update({"friction": lambda X: np.abs(X[2]) < tol,
                      "midplane": lambda X: np.abs(X[2] - bottom) < tol})
    m = _with_boundaries(m, faces)
    m = _with_subdomains(m, {"rotor": np.arange(m.t.shape[1])})
    logger.debug("rotor mesh: %d nodes, %d elements (order %d)", m.p.shape[1], m.t.shape[1], order)
    return m


def pad_mesh(geom: BrakeGeometry, size: float | None = None, order: int | None = None) -> fem.Mesh:
    """The pad: an annular-sector lining on ``0 < z < friction_thickness``, the
    backplate above it up to ``z = friction_thickness + backplate_thickness``.

    The lining spans the pad radii, the backplate the backplate radii
    (``pad.backplate_radii``); the lining may have leading/trailing chamfers
    (its friction face rises linearly to the chamfer depth at the pad end)
    and a radial slot of constant width on the centre line
    (:mod:`brakewear.mesh.pad_block`).  The rotor turns in +theta, so a rotor point
    enters under the pad at the smaller angle: ``leading`` is the end face at
    ``center - arc/2`` and ``trailing`` the one at ``center + arc/2``.

    Through the thickness: ``mesh.friction_layers`` layers in the friction
    layer, graded by ``pad_z_ratio`` toward the friction face (default: the
    fewest whose first layer is at most ``size / 2`` thick), and
    ``mesh.backplate_layers`` uniform layers in the backplate (default
    ``ceil(backplate_thickness / size)``).

    Parameters are those of :func:`rotor_mesh`.

    Returns
    -------
    skfem.MeshTet or skfem.MeshTet2
        Subdomains ``friction_layer`` and ``backplate``; facets ``friction``
        (the lining's face toward the rotor, chamfers included), ``back`` (top
        face), ``piston_face`` (back facets whose centroid lies inside the
        piston footprint: the rim annulus or the disc), ``leading``,
        ``trailing`` (whole end faces), ``abutment_leading``,
        ``abutment_trailing`` (backplate part of each end face), ``abutment``
        (both), ``leading_chamfer``, ``trailing_chamfer`` (the chamfer faces)
        and ``slot`` (walls and floor of the slot), these three only where
        the pad has them, ``inner`` and ``outer`` (the curved faces and, where the
        backplate is larger than the lining, its exposed front face).
    """
    ms = geom.mesh
    h, order = _check_size_order(_body_size(geom, size, "pad"),
                                 ms.order if order is None else order)
    tf, tb = geom.pad.friction_thickness, geom.pad.backplate_thickness
    nzf = ms.friction_layers or _n_cells(tf, 0.5 * h, ms.pad_z_ratio)
    zf = graded(0.0, tf, nzf, ms.pad_z_ratio if nzf > 1 else 1.0, "a")
    zb = np.linspace(tf, tf + tb, (ms.backplate_layers or max(1, int(np.ceil(tb / h)))) + 1)
    m = sector_pad_mesh(geom, h, order, zf, zb)
    logger.debug("pad mesh: %d nodes, %d elements (order %d)", m.p.shape[1], m.t.shape[1], order)
    return m


def _disc_triangles(R: float, h: float) -> tuple[np.ndarray, np.ndarray]:
    """A triangulated disc of radius ``R``: concentric rings of nodes about
    ``h`` apart (alternate rings turned by half a step), Delaunay-connected."""
    from scipy.spatial import Delaunay

    nr = max(2, int(np.ceil(R / h)))
    pts = [np.zeros((2, 1))]
    for k, rk in enumerate(np.linspace(0.0, R, nr + 1)[1:], start=1):
        n = max(6, int(round(2 * np.pi * rk / h)))
        ang = (np.arange(n) + 0.5 * (k % 2)) * 2 * np.pi / n
        pts.append(rk * np.vstack([np.cos(ang), np.sin(ang)]))
    p = np.hstack(pts)
    tri = Delaunay(p.T).simplices.T
    return p, tri


def _extrude(p2: np.ndarray, tri: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Extrude triangles through the layers ``z`` into prisms of three tetrahedra.

    Each prism is split by the global vertex order (every quadrilateral side
    gets the diagonal from its lower-numbered bottom vertex to its
    higher-numbered top vertex), so neighbouring prisms always agree.
    """
    n2 = p2.shape[1]
    nz = len(z)
    p = np.vstack([np.tile(p2, nz), np.repeat(z, n2)])
    v = np.sort(tri, axis=0)
    tets = []
    for k in range(nz - 1):
        b0, b1, b2 = v + k * n2
        t0, t1, t2 = v + (k + 1) * n2
        tets += [np.vstack([b0, b1, b2, t2]), np.vstack([b0, b1, t1, t2]),
                 np.vstack([b0, t0, t1, t2])]
    return p, np.hstack(tets)


def piston_mesh(
    geom: BrakeGeometry, size: float | None = None, order: int | None = None
) -> fem.Mesh:
    """The piston: a solid cylinder standing on the back of the pad.

    Concentric-ring triangulation of the footprint disc, extruded in z from
    the back of the pad (``z = friction_thickness + backplate_thickness``)
    over ``piston.length``.  For ``order=2`` the edge nodes on the cylinder
    wall are moved onto the circle.

    Returns
    -------
    skfem.MeshTet or skfem.MeshTet2
        Facets ``piston_face`` (bottom, on the backplate), ``piston_back``
        (top, hydraulic side) and ``piston_side``; subdomain ``piston``.
    """
    ms, pis = geom.mesh, geom.piston
    h, order = _check_size_order(ms.size if size is None else size,
                                 ms.order if order is None else order)
    R = 0.5 * pis.diameter
    z0 = geom.pad.thickness
    z1 = z0 + pis.length
    xc, yc = geom.piston_center
    p2, tri = _disc_triangles(R, h)
    z = np.linspace(z0, z1, max(2, int(np.ceil(pis.length / (1.5 * h)))) + 1)
    p, t = _extrude(p2, tri, z)
    on_wall = np.abs(np.hypot(p[0], p[1]) - R) < 1e-9 * R
    p = p + np.array([[xc], [yc], [0.0]])
    t = _oriented(p, t)
    if order == 1:
        m = fem.MeshTet(p, t)
    else:
        m1 = fem.MeshTet(p, t)
        e0, e1 = m1.edges
        mid = 0.5 * (p[:, e0] + p[:, e1])
        wall = on_wall[e0] & on_wall[e1]
        d = mid[:2, wall] - np.array([[xc], [yc]])
        mid[:2, wall] = np.array([[xc], [yc]]) + R * d / np.hypot(d[0], d[1])
        m = fem.MeshTet2(np.hstack([p, mid]), t)
    tol = 1e-9 * z1
    m = _with_boundaries(m, {
        "piston_face": lambda X: np.abs(X[2] - z0) < tol,
        "piston_back": lambda X: np.abs(X[2] - z1) < tol,
        "piston_side": lambda X: (np.abs(X[2] - z0) > tol) & (np.abs(X[2] - z1) > tol),
    })
    m = _with_subdomains(m, {"piston": np.arange(m.t.shape[1])})
    logger.debug("piston mesh: %d nodes, %d elements (order %d)", m.p.shape[1], m.t.shape[1], order)
    return m


def brake_meshes(
    geom: BrakeGeometry, size: float | None = None, order: int | None = None
) -> dict[str, fem.Mesh]:
    """Meshes of the three bodies of a brake geometry.

    The bodies are separate meshes that do not match at their interfaces;
    contact and ties are made by projection elsewhere.  Coordinates: rotor
    axis = z, friction interface at z = 0, rotor below (z < 0), pad and
    piston above; the pad is centred on ``pad.center_angle``.

    Parameters
    ----------
    geom : BrakeGeometry
        A checked geometry (see :func:`brakewear.geometry.load_geometry`).
    size : float, optional
        In-plane element size at the friction interface (m); default
        ``geom.mesh.size``.
    order : int, optional
        1 (P1 ``MeshTet``) or 2 (isoparametric ``MeshTet2``); default
        ``geom.mesh.order``.

    Returns
    -------
    dict of str to skfem.Mesh
        Keys ``"rotor"``, ``"pad"``, ``"piston"``; see :func:`rotor_mesh`,
        :func:`pad_mesh`, :func:`piston_mesh` for the named facets and
        subdomains.
    """
    out = {"rotor": rotor_mesh(geom, size, order), "pad": pad_mesh(geom, size, order),
           "piston": piston_mesh(geom, size, order)}
    logger.info("brake meshes: %s", ", ".join(
        f"{k} {m.p.shape[1]} nodes / {m.t.shape[1]} tets" for k, m in out.items()))
    return out


def component_materials(geom: BrakeGeometry) -> dict[str, dict[str, Material]]:
    """Material of every subdomain of every mesh of :func:`brake_meshes`.

    Returns
    -------
    dict
        ``{"rotor": {"rotor": ...}, "pad": {"friction_layer": ...,
        "backplate": ...}, "piston": {"piston": ...}}``.
    """
    return {
        "rotor": {"rotor": geom.rotor.material},
        "pad": {"friction_layer": geom.pad.friction_material,
                "backplate": geom.pad.backplate_material},
        "piston": {"piston": geom.piston.material},
    }


def element_materials(mesh: fem.Mesh, mapping: dict) -> list[tuple[np.ndarray, Material]]:
    """Pair the subdomains of ``mesh`` with materials.

    Parameters
    ----------
    mesh : skfem.Mesh
        A mesh with the subdomains named in ``mapping``.
    mapping : dict of str to Material
        Subdomain name -> material (one entry of :func:`component_materials`).

    Returns
    -------
    list of (ndarray, Material)
        Element indices and their material, one pair per subdomain.

    Raises
    ------
    MeshError
        A subdomain is missing from the mesh, or the subdomains do not cover
        every element exactly once.
    """
    subs = mesh.subdomains or {}
    missing = [k for k in mapping if k not in subs]
    if missing:
        raise MeshError(f"element_materials: mesh has no subdomain {missing[0]!r}; "
                        f"its subdomains: {sorted(subs) or 'none'}")
    out = [(np.asarray(subs[k], dtype=np.int64), mat) for k, mat in mapping.items()]
    count = np.zeros(mesh.t.shape[1], dtype=np.int64)
    for idx, _ in out:
        np.add.at(count, idx, 1)
    if (count != 1).any():
        raise MeshError(
            f"element_materials: subdomains {sorted(mapping)} leave {(count == 0).sum()} "
            f"elements without a material and give {(count > 1).sum()} elements two or more")
    return out
