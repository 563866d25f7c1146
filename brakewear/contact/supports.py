"""The pad's support in the caliper bracket: abutments, radial rails and anti-rattle spring.

A bracket holds each pad in its plane at the two ends of its backplate.  The
rotor turns in +theta, so friction drags the pad toward its trailing end,
and the design decides which end takes that drag:

* ``"push"``: the trailing abutment bears.  A rigid stop beyond the trailing
  end face, no clearance (``u_theta <= 0`` there); the leading end has the
  clearance ``c`` to its stop on the -theta side (``u_theta >= -c``);
* ``"pull"``: the leading hook bears (``u_theta <= 0`` at the leading end
  face); the trailing end has its stop after the clearance
  (``u_theta <= c``);
* ``"bilateral"``: both end faces held in their plane (the model's Dirichlet
  support); nothing here.

``u_theta`` is the displacement along the tangential unit vector normal to
each end face (a radial plane at the pad's leading or trailing angle).  Each
stop is a unilateral contact against a rigid plane
(:class:`~brakewear.contact.ContactPair` without coupling): its normal is the
tangential unit vector pointing from the stop toward the pad, its gap the
clearance (or 0) and its nodes those of the backplate part of the end face
(facets ``abutment_leading`` / ``abutment_trailing``, or ``abutment`` on
``leading`` / ``trailing`` where a mesh does not name them), with their
tributary areas.

Two springs to ground complete the bracket, as a sparse stiffness to add to
``K`` (:func:`support_springs`): the *rails* the backplate ends rest on (a
stiffness ``rail_stiffness`` per end face along the pad's radial direction,
its centre line) and the *anti-rattle spring* (``spring_stiffness`` along the
pad's tangential direction, spread over both end faces of its backplate).
Each is spread over its face's nodes in proportion to their areas.  They
keep the system positive definite where no abutment bears (no friction, a
clearance not closed) and take out the in-plane rigid modes.

A mesh may hold one pad or both (one body: the inboard pad at ``z > 0``, the
outboard one mirrored below the rotor, ``z < 0``): each pad (told apart by
the sign of ``z`` of its backplate) gets its own stops and springs.  Both
pads span the same angles, so their end faces have the same normals.
"""
from __future__ import annotations

import dataclasses
import logging
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
import skfem as fem

from ..errors import ContactError, GeometryError, MeshError
from ..mesh.surface import is_quadratic, quadratic_faces, surface_nodes, tributary_areas
from .pairs import ContactPair

if TYPE_CHECKING:
    from ..caliper.geometry import SupportGeometry
    from ..geometry.parts import PadGeometry

logger = logging.getLogger(__name__)

__all__ = ["SUPPORT_ENDS", "abutment_faces", "abutment_pairs", "support_springs",
           "end_normal", "with_supports", "support_forces", "spring_faces"]

#: the two end faces of a pad
SUPPORT_ENDS = ("leading", "trailing")


def _check_support(support: SupportGeometry) -> None:
    if support.type not in ("bilateral", "push", "pull"):
        raise GeometryError(f"support.type = {support.type!r}; allowed: 'bilateral', 'push', "
                            "'pull'")
    for key in ("clearance", "rail_stiffness", "spring_stiffness"):
        v = getattr(support, key)
        if not (np.isfinite(v) and v >= 0):
            unit = "m" if key == "clearance" else "N/m"
            raise GeometryError(f"support.{key} = {v!r} {unit}; need a finite value >= 0")


def end_normal(pad_geometry: PadGeometry, end: str) -> np.ndarray:
    """The tangential unit vector (3,) normal to the pad's ``end`` face (a radial
    plane), pointing in +theta (toward the trailing end)."""
    if end not in SUPPORT_ENDS:
        raise ContactError(f"end = {end!r}; allowed: {', '.join(SUPPORT_ENDS)}")
    a = pad_geometry.leading_angle if end == "leading" else pad_geometry.trailing_angle
    return np.array([-np.sin(a), np.cos(a), 0.0])


def abutment_faces(mesh: fem.Mesh, end: str) -> dict:
    """The facets of the backplate part of the ``end`` face, per pad:
    ``{"inboard": facets, "outboard": facets}`` (only the pads the mesh holds;
    a facet belongs to the inboard pad when its centroid lies at ``z > 0``)."""
    if end not in SUPPORT_ENDS:
        raise ContactError(f"end = {end!r}; allowed: {', '.join(SUPPORT_ENDS)}")
    b = mesh.boundaries or {}
    name = f"abutment_{end}"
    if name in b:
        facets = np.asarray(b[name])
    elif "abutment" in b and end in b:
        facets = np.intersect1d(b["abutment"], b[end])
    else:
        raise MeshError(f"the pad mesh names no facets {name!r} (nor 'abutment' and {end!r}); "
                        f"its facets: {', '.join(sorted(b))}")
    if facets.size == 0:
        raise MeshError(f"the pad mesh's {name} facets are empty: no backplate end face")
    zc = mesh.p[2, mesh.facets[:, facets]].mean(axis=0)
    out = {"inboard": facets[zc > 0], "outboard": facets[zc < 0]}
    return {k: v for k, v in out.items() if v.size}


def face_weights(mesh: fem.Mesh, facets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Nodes of ``facets`` and the integral of each node's shape function over
    them (m^2; a linear face: tributary areas; a quadratic one: its mid-edge
    nodes carry a third of each flat triangle, its vertices nothing)."""
    if not is_quadratic(mesh):
        nodes = surface_nodes(mesh, facets)
        return nodes, tributary_areas(mesh, facets, nodes)
    q = quadratic_faces(mesh, facets)
    p = mesh.p
    area = 0.5 * np.linalg.norm(np.cross(p[:, q[1]] - p[:, q[0]], p[:, q[2]] - p[:, q[0]],
                                         axis=0), axis=0)
    nodes, inv = np.unique(q, return_inverse=True)
    inv = inv.reshape(q.shape)
    w = np.zeros(nodes.size)
    for a in range(3, 6):
        np.add.at(w, inv[a], area / 3.0)
    return nodes, w


def _stop(mesh, facets, offset, normal, g0, name) -> ContactPair:
    """A unilateral stop: the nodes of ``facets`` against a rigid plane parallel
    to them at gap ``g0``, along ``normal`` (stop -> pad)."""
    if is_quadratic(mesh):
        from ..mesh.quadratic import quadratic_face_areas, slave_basis

        nodes, area = quadratic_face_areas(mesh, facets)
        basis = slave_basis(quadratic_faces(mesh, facets), offset)
    else:
        nodes = surface_nodes(mesh, facets)
        area, basis = tributary_areas(mesh, facets, nodes), None
    n = nodes.size
    # a plane parallel to the face: the same gap at every node (and the same weak
    # gap on a quadratic face, whose transformed functions are a partition of unity)
    return ContactPair(nodes + offset, area, np.repeat(normal[:, None], n, axis=1),
                       np.full(n, float(g0)), None, 0.0, None, name, basis=basis)


def abutment_pairs(mesh: fem.Mesh, offset: int, pad_geometry: PadGeometry,
                   support: SupportGeometry) -> list[ContactPair]:
    """The abutment stops of every pad in ``mesh`` (its first global node ``offset``)
    as unilateral contact pairs against rigid planes (see the module).

    Push: the trailing stop (gap 0, ``u_theta <= 0``) and the leading one (gap
    = clearance, ``u_theta >= -clearance``).  Pull: the leading hook (gap 0,
    ``u_theta <= 0``) and the trailing stop (gap = clearance, ``u_theta <=
    clearance``).  Bilateral: no pair (the model's Dirichlet support).  Pairs
    are named ``"abutment <end> (<inboard|outboard>)"``, the bearing end first.
    """
    _check_support(support)
    if support.type == "bilateral":
        return []
    bearing = support.bearing_end
    pairs = []
    for end in (bearing, "leading" if bearing == "trailing" else "trailing"):
        e = end_normal(pad_geometry, end)
        # the direction the stop pushes the pad: push's leading stop pushes toward
        # +theta, every other stop toward -theta
        normal = e if (support.type == "push" and end == "leading") else -e
        g0 = 0.0 if end == bearing else support.clearance
        for side, facets in abutment_faces(mesh, end).items():
            pairs.append(_stop(mesh, facets, offset, normal, g0, f"abutment {end} ({side})"))
    return pairs


def support_springs(mesh: fem.Mesh, offset: int, pad_geometry: PadGeometry,
                    support: SupportGeometry, n_dofs: int) -> sp.csr_matrix:
    """The rails and the anti-rattle spring of every pad in ``mesh`` as a sparse
    symmetric stiffness (``n_dofs`` x ``n_dofs``, DOF ``3 node + i`` with the
    mesh's nodes from ``offset``), to add to ``K``; zero for a bilateral
    support.

    Per pad: ``rail_stiffness`` per end face along the radial direction of the
    pad's centre line, ``spring_stiffness`` along its tangential direction
    over both end faces together, each spread over the nodes by area.
    """
    _check_support(support)
    if n_dofs < 3 * (offset + mesh.p.shape[1]):
        raise ContactError(f"n_dofs = {n_dofs}; the pad mesh's nodes reach DOF "
                           f"{3 * (offset + mesh.p.shape[1]) - 1}")
    if support.type == "bilateral":
        return sp.csr_matrix((n_dofs, n_dofs))
    radial, tangential, pads = spring_faces(mesh, pad_geometry)
    nodes, k, d = [], [], []
    for ends in pads:
        for facets in ends:   # a rail per end face
            n, w = face_weights(mesh, facets)
            nodes.append(n)
            k.append(support.rail_stiffness * w / w.sum())
            d.append(np.repeat(radial[:, None], n.size, axis=1))
        n, w = face_weights(mesh, np.concatenate(ends))   # the spring over both
        nodes.append(n)
        k.append(support.spring_stiffness * w / w.sum())
        d.append(np.repeat(tangential[:, None], n.size, axis=1))
    return _node_springs(np.concatenate(nodes) + offset, np.concatenate(k),
                         np.hstack(d), n_dofs)


def spring_faces(mesh: fem.Mesh, pad_geometry: PadGeometry):
    """``(radial, tangential, pads)``: the unit vectors of the pad's centre line and
    its tangent (the rails' and the clip's directions), and per pad of ``mesh`` the
    facets of its end faces (a list of one array per end)."""
    c = pad_geometry.center_angle
    radial = np.array([np.cos(c), np.sin(c), 0.0])
    tangential = np.array([-np.sin(c), np.cos(c), 0.0])
    faces = {end: abutment_faces(mesh, end) for end in SUPPORT_ENDS}
    pads = [[faces[end][side] for end in SUPPORT_ENDS if side in faces[end]]
            for side in sorted(set(faces["leading"]) | set(faces["trailing"]))]
    return radial, tangential, pads


def _node_springs(nodes: np.ndarray, k: np.ndarray, d: np.ndarray,
                  n_dofs: int) -> sp.csr_matrix:
    """Springs to ground ``k_j d_j d_j^T`` on the DOFs of ``nodes`` (duplicates summed)."""
    i, j = np.meshgrid(np.arange(3), np.arange(3), indexing="ij")
    rows = 3 * nodes[:, None, None] + i[None]
    cols = 3 * nodes[:, None, None] + j[None]
    vals = k[:, None, None] * d.T[:, :, None] * d.T[:, None, :]
    return sp.csr_matrix((vals.ravel(), (rows.ravel(), cols.ravel())),
                         shape=(n_dofs, n_dofs))


def with_supports(system, mesh: fem.Mesh, offset: int, pad_geometry: PadGeometry,
                  support: SupportGeometry):
    """A contact system (:class:`~brakewear.contact.ContactSystem`) with its pads held
    by ``support`` instead of the bilateral support.

    ``system`` is in its retained numbering (``P``: retained -> all DOFs,
    ``col``: node -> retained node); ``mesh`` is the pad mesh whose first
    global node is ``offset``.  The copy has the springs added to ``K``
    (``P^T K_s P``), the abutment nodes' in-plane DOFs released from
    ``fixed`` and the stops appended to ``supports``.  A bilateral support
    returns ``system`` itself.
    """
    _check_support(support)
    if support.type == "bilateral":
        return system
    col, P = np.asarray(system.col), system.P
    Ks = support_springs(mesh, offset, pad_geometry, support, P.shape[0])
    pairs = []
    for pr in abutment_pairs(mesh, offset, pad_geometry, support):
        if np.any(col[pr.slave] < 0):
            raise ContactError(f"{pr.name}: an abutment node is tied (eliminated); the pad's "
                               "end faces must keep their nodes")
        basis = None if pr.basis is None else pr.basis.renumbered(col)
        pairs.append(dataclasses.replace(pr, slave=col[pr.slave], basis=basis))
    ends = [f for end in SUPPORT_ENDS for f in abutment_faces(mesh, end).values()]
    # every node of the end faces (vertices and mid-edge nodes): what the bilateral
    # support held in the plane
    nodes = col[face_weights(mesh, np.concatenate(ends))[0] + offset]
    held = (3 * nodes[:, None] + np.arange(2)).ravel()
    return dataclasses.replace(system, K=(system.K + P.T @ Ks @ P).tocsr(),
                               fixed=np.setdiff1d(system.fixed, held),
                               supports=[*getattr(system, "supports", []), *pairs])


def support_forces(system, stop_forces: list, u: np.ndarray, mesh: fem.Mesh, offset: int,
                   pad_geometry: PadGeometry, support: SupportGeometry) -> np.ndarray | None:
    """Nodal forces (the pad mesh's DOFs, ``3 node + i``) of a solved system's
    abutment stops (``stop_forces``: one multiplier array per pair of
    ``system.supports``) and of the rails and springs at the displacement ``u``
    (all DOFs); None for a bilateral support (its reactions are Dirichlet's)."""
    if support.type == "bilateral":
        return None
    n_nodes = u.size // 3
    F = np.zeros((n_nodes, 3))
    node = np.flatnonzero(np.asarray(system.col) >= 0)        # retained -> global node
    for s, lam in zip(system.supports, stop_forces):
        np.add.at(F, node[s.slave], (s.normal * lam).T)
    F -= (support_springs(mesh, offset, pad_geometry, support, u.size) @ u).reshape(-1, 3)
    return F[offset:offset + mesh.p.shape[1]].ravel()
