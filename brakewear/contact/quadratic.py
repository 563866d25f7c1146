"""Contact of quadratic (P2) faces: dual mortar coupling in the transformed basis.

Why this formulation.  On a 6-node triangle the vertex shape functions
integrate to zero, so node-to-surface contact with lumped nodal areas has no
area at the vertices and nodal multipliers there take either sign; the
patch test fails.  Of the remedies, the one that keeps brakewear's active-set
solver as it is -- every active slave node's normal DOF eliminated on its own,
the reduced operator SPD for AMG -- is the dual mortar method with the
quadratic basis transformation of Popp, Wohlmuth, Gee and Wall (SIAM J. Sci.
Comput. 34, 2012):

1. the slave face's displacement basis is transformed so that every nodal
   integral is positive (:mod:`~brakewear.contact.basis`, ``alpha = 1/5``);
2. the pressure is a *dual* multiplier ``p_h = sum_j p_j psi_j``, built per
   slave triangle from the transformed functions so that
   ``int psi_j phi~_k dA = delta_jk D_j``, ``D_j = int phi~_j dA > 0``;
3. the weak gap of node ``j``, ``int psi_j g dA``, then involves the slave's
   own unknown only: ``D_j (g0_j + n_j . (u~_j - sum_m W_jm u_m))`` with
   ``W_jm = int psi_j N_m dA / D_j`` over the master's shape functions ``N_m``
   (linear or quadratic) at the projections of the quadrature points, and
   ``g0_j = int psi_j g0 dA / D_j``.

That is exactly the form of a :class:`~brakewear.contact.ContactPair` (area
``D_j``, coupling ``W``, gap ``g0``), so the node-wise elimination, friction
and the compliant (wear) solve apply unchanged in the transformed unknowns;
the nodal contact force is ``D_j p_j``.  The coupling reproduces constants
(``W`` rows sum to one, ``sum_j D_j W_jm = int N_m``): a uniform pressure loads
the master with its consistent nodal forces, and the weak gap is exact for
a gap that is quadratic on each slave triangle.  A mortar method with
piecewise-linear multipliers on the subdivided faces (positive weights too)
would give a non-diagonal ``D``, which the node-wise elimination cannot take.

Integrals use a 7-point degree-5 rule on each of the ``4**level``
sub-triangles of a slave triangle (exact for the mass matrix of a flat face;
the sub-triangles resolve the master's element edges on non-matching meshes).
Curved (isoparametric) faces are integrated with their own Jacobian; the
master is searched by its vertex triangles and evaluated with its own shape
functions.
"""
from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp
import skfem as fem

from ..mesh.quadratic import ALPHA, face_numbering, face_quadrature
from ..mesh.surface import is_quadratic, quadratic_faces
from ..mesh.triangle import tri6
from .surface import Projection, project_nodes

logger = logging.getLogger(__name__)

__all__ = ["face_values", "dual_surface_pair", "dual_rigid_pair"]


def _assemble(q: dict, local: np.ndarray, ns: int, cols: np.ndarray, vals: np.ndarray,
              n_cols: int) -> sp.csr_matrix:
    """``sum_q psi_j(q) w(q) vals_b(q)`` into (ns, n_cols) at ``cols_b(q)``: rows are
    the slave nodes ``j`` of each point's facet, ``cols``/``vals`` (k, nf, nq)."""
    out = sp.csr_matrix((ns, n_cols))
    pw = q["psi"] * q["w"]                                        # (6, nf, nq)
    for j in range(6):
        r = np.broadcast_to(local[j][:, None], pw.shape[1:])
        rows = np.broadcast_to(r, vals.shape).ravel()
        out = out + sp.csr_matrix(((pw[j] * vals).ravel(), (rows, cols.ravel())),
                                  shape=(ns, n_cols))
    return out.tocsr()


def face_values(master_mesh: fem.Mesh, master_facets, pr: Projection
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Master nodes (k, n), shape-function values (k, n) and the master point (3, n)
    under projected points ``pr`` (:class:`~brakewear.contact.Projection`):
    k = 3 for a linear master, 6 for a quadratic one (its own curved geometry).
    A tie of a quadratic face interpolates with these."""
    if not is_quadratic(master_mesh):
        x = np.einsum("kn,akn->an", pr.weights, master_mesh.p[:, pr.nodes])
        return pr.nodes, pr.weights, x
    if isinstance(master_facets, str):
        master_facets = master_mesh.boundaries[master_facets]
    facets = np.asarray(master_facets)
    where = np.full(master_mesh.facets.shape[1], -1, dtype=np.int64)
    where[facets] = np.arange(facets.size)
    nodes = quadratic_faces(master_mesh, facets)[:, where[pr.facet]]
    N = tri6(pr.weights)
    return nodes, N, np.einsum("kn,akn->an", N, master_mesh.p[:, nodes])


def _projected(points: np.ndarray, mesh: fem.Mesh, facets, search_radius,
               chunk: int = 40_000) -> Projection:
    """:func:`~brakewear.contact.project_nodes` in chunks of points (its candidate
    arrays grow with points x candidates)."""
    parts = [project_nodes(points[:, i:i + chunk], mesh, facets, search_radius=search_radius)
             for i in range(0, points.shape[1], chunk)]
    if len(parts) == 1:
        return parts[0]
    return Projection(*(np.concatenate([getattr(pt, k) for pt in parts], axis=-1)
                        for k in ("facet", "nodes", "weights", "gap", "normal", "distance")))


def dual_surface_pair(slave_mesh: fem.Mesh, slave_facets, master_mesh: fem.Mesh, master_facets,
                      n_master_nodes: int, level: int = 2, search_radius: float | None = None,
                      alpha: float = ALPHA) -> dict:
    """The dual mortar pair of a quadratic slave face against a meshed master (see the module).

    Returns a dict in the meshes' own numbering: ``slave`` (face nodes, sorted),
    ``area`` (``D_j``), ``g0`` (weak gap), ``W`` (ns x ``n_master_nodes``), ``normal``
    (the master's normal under each slave node) and ``nodes`` (6, nf).
    """
    q = face_quadrature(slave_mesh, slave_facets, level, alpha)
    slave, local = face_numbering(q["nodes"])
    ns = slave.size
    nf, nq = q["w"].shape
    pr = _projected(q["x"].reshape(3, -1), master_mesh, master_facets, search_radius)
    mnodes, mvals, xm = face_values(master_mesh, master_facets, pr)
    k = mnodes.shape[0]
    gap = np.einsum("an,an->n", pr.normal, q["x"].reshape(3, -1) - xm).reshape(1, nf, nq)
    D = np.bincount(local.ravel(), weights=q["D"].ravel(), minlength=ns)
    W = _assemble(q, local, ns, mnodes.reshape(k, nf, nq), mvals.reshape(k, nf, nq),
                  n_master_nodes)
    g0 = _assemble(q, local, ns, np.zeros((1, nf, nq), dtype=np.int64), gap, 1)
    normal = project_nodes(slave_mesh.p[:, slave], master_mesh, master_facets,
                           search_radius=search_radius).normal
    return {"slave": slave, "area": D, "g0": g0.toarray().ravel() / D,
            "W": (sp.diags(1.0 / D) @ W).tocsr(), "normal": normal, "nodes": q["nodes"]}


def dual_rigid_pair(slave_mesh: fem.Mesh, slave_facets, height, side: int, level: int = 1,
                    alpha: float = ALPHA) -> dict:
    """The dual mortar pair of a quadratic slave face against the rigid surface
    ``z = height(x, y)`` (gaps along z, ``side`` as in
    :func:`~brakewear.contact.pair_to_rigid`); the dict of :func:`dual_surface_pair`
    without ``W``."""
    q = face_quadrature(slave_mesh, slave_facets, level, alpha)
    slave, local = face_numbering(q["nodes"])
    ns = slave.size
    x = q["x"]
    gap = side * (x[2] - np.asarray(height(x[0], x[1]), dtype=float))
    D = np.bincount(local.ravel(), weights=q["D"].ravel(), minlength=ns)
    g0 = _assemble(q, local, ns, np.zeros((1,) + gap.shape, dtype=np.int64), gap[None], 1)
    normal = np.zeros((3, ns))
    normal[2] = side
    return {"slave": slave, "area": D, "g0": g0.toarray().ravel() / D, "normal": normal,
            "nodes": q["nodes"]}
