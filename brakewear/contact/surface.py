"""Surface geometry of contact: projection of points on facets, segment (mortar) coupling, ties.

Slave nodes (for the pad-rotor interface, the pad's friction-face nodes) are
projected onto master facets (the rotor's friction face).  The projection
gives, per slave node, the master facet, the barycentric weights of the
projected point, the signed normal gap and the master's outward normal.  A
*tie* glues slave nodes to the master surface: every slave DOF equals the
master displacement interpolated at its projection (``u = P u_r``).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import skfem as fem
from scipy.spatial import cKDTree

from ..errors import ContactError, ContactSearchError
from ..mesh.surface import facet_normals

logger = logging.getLogger(__name__)

__all__ = ["Projection", "project_nodes", "tie_prolongation"]


@dataclass
class Projection:
    """Projection of slave points on a master surface (arrays over slave points)."""

    facet: np.ndarray   # (n,) index into mesh.facets of the master facet
    nodes: np.ndarray   # (3, n) master vertex indices of that facet
    weights: np.ndarray  # (3, n) barycentric weights of the projected point
    gap: np.ndarray     # (n,) signed normal distance, > 0 outside the master body
    normal: np.ndarray  # (3, n) master outward unit normal
    distance: np.ndarray  # (n,) distance from the point to the facet (0 if it projects inside)



def project_nodes(points: np.ndarray, mesh: fem.Mesh, facets, search_radius: float | None = None,
                  candidates: int = 12, tol: float = 1e-9) -> Projection:
    """Project ``points`` (3, n) onto the master facets of ``mesh``.

    Candidates are the ``candidates`` facets with the nearest centroids; the
    chosen facet is the one whose closest point is nearest (a point that
    projects inside a facet has distance 0 in-plane).  Raises
    :class:`ContactSearchError` naming the first point that is farther than
    ``search_radius`` from every candidate.
    """
    if isinstance(facets, str):
        facets = mesh.boundaries[facets]
    facets = np.asarray(facets)
    points = np.asarray(points, dtype=float)
    f = mesh.facets[:, facets]
    p = mesh.p
    A, Bv, Cv = p[:, f[0]], p[:, f[1]], p[:, f[2]]
    tree = cKDTree(((A + Bv + Cv) / 3.0).T)
    k = min(candidates, facets.size)
    _, cand = tree.query(points.T, k=k)
    cand = cand.reshape(points.shape[1], k)
    a, b, c = A[:, cand], Bv[:, cand], Cv[:, cand]  # (3, n, k)
    x = points[:, :, None]
    e0, e1, d = b - a, c - a, x - a
    d00 = np.einsum("inj,inj->nj", e0, e0)
    d01 = np.einsum("inj,inj->nj", e0, e1)
    d11 = np.einsum("inj,inj->nj", e1, e1)
    d20 = np.einsum("inj,inj->nj", d, e0)
    d21 = np.einsum("inj,inj->nj", d, e1)
    den = d00 * d11 - d01 * d01
    v = (d11 * d20 - d01 * d21) / den
    w = (d00 * d21 - d01 * d20) / den
    u = 1.0 - v - w
    bary = np.stack([u, v, w])
    # clamp to the triangle for the in-plane distance (a simple, robust
    # approximation of the closest point: renormalised clipped weights)
    cl = np.clip(bary, 0.0, None)
    cl /= cl.sum(axis=0, keepdims=True)
    q = cl[0] * a + cl[1] * b + cl[2] * c
    nrm = np.cross(e0, e1, axis=0)
    nrm /= np.linalg.norm(nrm, axis=0)
    h = np.einsum("inj,inj->nj", d, nrm)
    inplane = np.linalg.norm(x - h * nrm - q, axis=0)
    inside = bary.min(axis=0) >= -tol
    score = np.where(inside, 0.0, inplane) + 1e-12 * np.abs(h)
    best = np.argmin(score, axis=1)
    rows = np.arange(points.shape[1])
    sel = cand[rows, best]
    weights = np.where(inside[rows, best], bary[:, rows, best], cl[:, rows, best])
    normal = facet_normals(mesh, facets[sel])
    proj = (weights[0] * A[:, sel] + weights[1] * Bv[:, sel] + weights[2] * Cv[:, sel])
    gap = np.einsum("ij,ij->j", points - proj, normal)
    dist = inplane[rows, best]
    if search_radius is not None:
        far = np.nonzero(np.hypot(dist, gap) > search_radius)[0]
        if far.size:
            i = far[0]
            raise ContactSearchError(
                f"{far.size} slave point(s) have no master facet within the search radius "
                f"{search_radius:.3g}; first: point {i} at {points[:, i]}, distance "
                f"{np.hypot(dist[i], gap[i]):.3g}")
    return Projection(facets[sel], f[:, sel], weights, gap, normal, dist)


def tie_prolongation(n_nodes: int, slave: np.ndarray, master_nodes: np.ndarray,
                     weights: np.ndarray) -> tuple[sp.csr_matrix, np.ndarray]:
    """Node-level prolongation of a tie: ``u_node = P u_retained``.

    ``slave`` (n,) are eliminated nodes (global numbering); ``master_nodes``
    (k, n) and ``weights`` (k, n) express each slave as a combination of
    master nodes (k = 3 on a linear face, 6 on a quadratic one), which must
    not be slaves themselves.  Returns ``P``
    (n_nodes x n_retained) and the retained node indices.  The vector
    prolongation for DOFs ``3 s + i`` is ``kron(P, I3)``.
    """
    slave = np.asarray(slave)
    is_slave = np.zeros(n_nodes, dtype=bool)
    is_slave[slave] = True
    if np.any(is_slave[master_nodes]):
        raise ContactError("tie_prolongation: a master node is also a slave node; "
                           "ties must not be chained")
    retained = np.nonzero(~is_slave)[0]
    col = -np.ones(n_nodes, dtype=np.int64)
    col[retained] = np.arange(retained.size)
    rows = np.concatenate([retained, np.repeat(slave, master_nodes.shape[0])])
    cols = np.concatenate([np.arange(retained.size), col[master_nodes.T.ravel()]])
    vals = np.concatenate([np.ones(retained.size), weights.T.ravel()])
    P = sp.csr_matrix((vals, (rows, cols)), shape=(n_nodes, retained.size))
    return P, retained


def mortar_coupling(slave_mesh: fem.Mesh, slave_facets, slave: np.ndarray,
                    master_mesh: fem.Mesh, master_facets, n_master_nodes: int,
                    level: int = 2, search_radius: float | None = None):
    """Segment-weighted coupling: ``W[s, m] = int phi_s psi_m dA / int phi_s dA``.

    ``phi_s`` are the slave surface's linear shape functions, ``psi_m`` the
    master's, evaluated at the projections of ``4**level`` points per slave
    facet (centroids of a regular subdivision).  With this coupling a uniform
    contact pressure maps to the consistent nodal loads of the master mesh,
    which is what one-point projection misses on non-matching meshes.
    Returns (W (n_slave x n_master_nodes), weak gap (n_slave,), area (n_slave,)).
    """
    if isinstance(slave_facets, str):
        slave_facets = slave_mesh.boundaries[slave_facets]
    # barycentric centroids of the subdivision of the reference triangle
    m = 2 ** level
    pts = []
    for i in range(m):
        for j in range(m - i):
            pts.append(((i + 1 / 3) / m, (j + 1 / 3) / m))          # upward triangles
            if i + j < m - 1:
                pts.append(((i + 2 / 3) / m, (j + 2 / 3) / m))      # downward triangles
    lam = np.array([[1 - a - b, a, b] for a, b in pts]).T          # (3, nq), equal weights
    nq = lam.shape[1]
    f = slave_mesh.facets[:, slave_facets]
    X = slave_mesh.p[:, f]                                          # (3 coords, 3 verts, nf)
    area = 0.5 * np.linalg.norm(np.cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0], axis=0), axis=0)
    xq = np.einsum("avf,vq->afq", X, lam).reshape(3, -1)            # (3, nf * nq)
    pr = project_nodes(xq, master_mesh, master_facets, search_radius=search_radius)
    wq = np.repeat(area / nq, nq).reshape(-1, nq).ravel()           # weight of each point
    col = -np.ones(slave_mesh.nvertices, dtype=np.int64)
    col[slave] = np.arange(slave.size)
    rows, cols, vals = [], [], []
    gap_num = np.zeros(slave.size)
    den = np.zeros(slave.size)
    phi = lam[:, None, :].repeat(f.shape[1], axis=1).reshape(3, -1)
    fv = np.repeat(f, nq, axis=1)                                   # slave vertex per point
    for a in range(3):
        sa = col[fv[a]]
        wa = wq * phi[a]
        np.add.at(den, sa, wa)
        np.add.at(gap_num, sa, wa * pr.gap)
        for b in range(3):
            rows.append(sa)
            cols.append(pr.nodes[b])
            vals.append(wa * pr.weights[b])
    W = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(slave.size, n_master_nodes))
    W = sp.diags(1.0 / den) @ W
    return W.tocsr(), gap_num / den, den
