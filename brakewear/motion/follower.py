"""The band of nodes beneath a worn face, and how it follows the face.

:class:`SurfaceFollower` is built once on the reference (unworn) mesh of a
body: every node within a depth ``D`` below a face gets the shape functions
of the point of the face above it, weighted ``1 - d/D``, so that moving the
face by worn depths moves the band by a linear fall-off to ``D``
(:mod:`brakewear.motion.brake`).  P1 faces take the flat facets' barycentric
coordinates; P2 faces the curved facets' (isoparametric) coordinates and
the face's transformed basis (:mod:`brakewear.contact.basis`).
"""
from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp
import skfem as fem

from ..contact.surface import project_nodes
from ..errors import MotionError
from ..mesh.quadratic import slave_basis
from ..mesh.surface import face_nodes, facet_normals, is_quadratic, quadratic_faces
from ..mesh.triangle import tri6

logger = logging.getLogger(__name__)

__all__ = ["SurfaceFollower"]


class SurfaceFollower:
    """Moves one worn surface and the band of nodes beneath it.

    Built once on the reference (unworn) mesh: each node at depth ``d < D``
    below the surface (measured along the surface normal, laterally inside
    the surface) gets the weights ``(1 - d/D) * b`` on the surface nodes of
    the facet it projects on (``b`` its barycentric coordinates).  On the
    structured brake meshes a node lies exactly under a surface node, so
    ``b`` is one on that node and the motion is per column.

    Parameters
    ----------
    mesh
        The reference mesh (P1 tetrahedra).
    facets
        Name (or facet indices) of the worn surface.
    depth
        Target band depth ``D`` (m).  With ``snap`` it is raised to the
        nearest node depth at or below it, so that the band ends on a node
        layer and the elements beyond it do not move at all.
    snap
        See ``depth``.
    """

    def __init__(self, mesh: fem.Mesh, facets, depth: float, snap: bool = True):
        if not isinstance(mesh, (fem.MeshTet1, fem.MeshTet2)):
            raise MotionError(f"SurfaceFollower needs a MeshTet (P1 or P2); got "
                            f"{type(mesh).__name__}")
        depth = float(depth)
        if not (np.isfinite(depth) and depth > 0):
            raise MotionError(f"depth = {depth!r} m is not allowed; need a finite band depth > 0")
        fac = mesh.boundaries[facets] if isinstance(facets, str) else np.asarray(facets)
        quad = is_quadratic(mesh)
        self.nodes = face_nodes(mesh, fac)
        ns, n_all = self.nodes.size, mesh.p.shape[1]
        p = mesh.p
        # the nodes of each facet (P2: the vertices, then the mid-edge nodes)
        f6 = quadratic_faces(mesh, fac) if quad else mesh.facets[:, fac]
        f = mesh.facets[:, fac]
        area = 0.5 * np.linalg.norm(np.cross(p[:, f[1]] - p[:, f[0]], p[:, f[2]] - p[:, f[0]],
                                             axis=0), axis=0)
        # outward nodal normals: area-weighted facet normals
        nf = facet_normals(mesh, fac) * area
        acc = np.zeros((3, n_all))
        for a in range(f6.shape[0]):
            for i in range(3):
                np.add.at(acc[i], f6[a], nf[i])
        n = acc[:, self.nodes]
        self.normals = n / np.linalg.norm(n, axis=0)
        # on a quadratic face the depths are coefficients of its transformed basis
        # (the wear loop's, brakewear.contact.basis): their nodal values are T h
        self.basis = None
        if quad:
            T = slave_basis(f6, 0).node_matrix(n_all)
            self.basis = T[self.nodes][:, self.nodes].tocsr()
        # depth and lateral position of every node over the surface
        scale = float(np.ptp(p, axis=1).max())
        tol = 1e-9 * scale
        # in chunks: the candidate search holds (3, n, 12) arrays
        parts = [project_nodes(p[:, i:i + 50_000], mesh, fac) for i in range(0, n_all, 50_000)]
        d = -np.concatenate([q.gap for q in parts])
        dist = np.concatenate([q.distance for q in parts])
        # a quadratic face's curved edges bulge past their chords (by c^2 / 8R): its
        # mid-edge nodes there, and the nodes beneath them, are under it too
        lateral = tol if not quad else 0.1 * float(np.linalg.norm(
            p[:, f[1]] - p[:, f[0]], axis=0).max())
        under = (dist <= lateral) & (d >= -tol)
        # the band ends on a layer of vertices (on P2 not between two)
        vertex = np.arange(n_all) < mesh.nvertices
        depths = np.unique(np.round(d[under & vertex] / tol)) * tol
        if snap:
            deeper = depths[depths >= depth - tol]
            if deeper.size == 0:
                raise MotionError(f"depth = {depth:.6g} m is not allowed: the body is only "
                                 f"{depths.max():.6g} m deep under this surface")
            depth = float(d[under & vertex][np.argmin(np.abs(d[under & vertex] - deeper[0]))])
        self.depth = depth
        inband = np.nonzero(under & (d < depth - tol))[0]
        self.F = self._weights(mesh, fac, parts, d, inband, quad)
        self.band_nodes = inband
        self.scale = scale
        logger.debug("follower: %d surface nodes, band depth %.4g m, %d nodes in the band",
                     ns, depth, inband.size)

    def _weights(self, mesh, fac, parts, d, inband, quad: bool) -> sp.csr_matrix:
        """``F`` (all nodes x surface nodes): ``(1 - d/D)`` times the shape
        functions of the facet each band node projects on, at its point."""
        n_all = mesh.p.shape[1]
        w = np.clip(1.0 - np.clip(d[inband], 0.0, None) / self.depth, 0.0, 1.0)
        b = np.hstack([q.weights for q in parts])[:, inband]
        b[np.abs(b) < 1e-12] = 0.0  # a node under a vertex follows that vertex alone
        b /= b.sum(axis=0, keepdims=True)
        if quad:
            facet = np.concatenate([q.facet for q in parts])[inband]
            nodes = quadratic_faces(mesh, facet)
            b = tri6(_curved_point(mesh.p[:, nodes], mesh.p[:, inband], b))
        else:
            nodes = np.hstack([q.nodes for q in parts])[:, inband]
        b[np.abs(b) < 1e-12] = 0.0
        col = -np.ones(n_all, dtype=np.int64)
        col[self.nodes] = np.arange(self.nodes.size)
        cols = col[nodes]
        if np.any(cols < 0):  # pragma: no cover - facets' nodes are surface nodes
            raise RuntimeError("follower: a projection landed on a non-surface node")
        rows = np.repeat(inband[None, :], nodes.shape[0], axis=0)
        F = sp.csr_matrix(((b * w).ravel(), (rows.ravel(), cols.ravel())),
                          shape=(n_all, self.nodes.size))
        F.eliminate_zeros()
        return F

    def displacement(self, h: np.ndarray) -> np.ndarray:
        """Nodal displacement (3, all nodes) for worn depths ``h`` (face-node
        order; on a quadratic face the coefficients of its transformed basis)."""
        if self.basis is not None:
            h = self.basis @ h
        s = -(self.normals * h[None, :])            # inward, by h
        return np.vstack([self.F @ s[i] for i in range(3)])


def _curved_point(X: np.ndarray, x: np.ndarray, lam: np.ndarray, iterations: int = 8
                  ) -> np.ndarray:
    """Barycentric coordinates (3, k) of the points of the curved 6-node facets
    ``X`` (3, 6, k) nearest to ``x`` (3, k), from the flat facets' ``lam``
    (Gauss-Newton on the isoparametric map; a point under a node gets that
    node's coordinates, so it follows that node alone)."""
    lam = lam.copy()
    for _ in range(iterations):
        l0, l1, l2 = lam
        z = np.zeros_like(l0)
        dN = np.stack([np.stack([1 - 4 * l0, 4 * l1 - 1, z, 4 * (l0 - l1), 4 * l2, -4 * l2]),
                       np.stack([1 - 4 * l0, z, 4 * l2 - 1, -4 * l1, 4 * l1, 4 * (l0 - l2)])])
        J = np.einsum("ank,dnk->kad", X, dN)                       # (k, 3, 2)
        r = x - np.einsum("ank,nk->ak", X, tri6(lam))
        step = np.linalg.solve(np.einsum("kad,kae->kde", J, J),
                               np.einsum("kad,ak->kd", J, r)[..., None])[..., 0]
        lam = lam + np.stack([-step.sum(axis=1), step[:, 0], step[:, 1]])
    lam = np.clip(lam, 0.0, None)
    return lam / lam.sum(axis=0, keepdims=True)
