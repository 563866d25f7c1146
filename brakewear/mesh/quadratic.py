"""Surface geometry of quadratic (P2) faces: the transformed basis, its quadrature, nodal areas.

On a 6-node triangle the integrals of the vertex shape functions are zero, so
a uniform pressure has no consistent load at the vertices and a nodal value
there has no area to divide by.  A quadratic face therefore changes its
displacement basis (Popp, Wohlmuth, Gee and Wall, SIAM J. Sci. Comput. 34,
2012): each vertex function takes ``alpha`` of every mid-edge function of its
face edges and each mid-edge function keeps ``1 - 2 alpha`` of itself,

    phi~_v = phi_v + alpha sum_{e ~ v} phi_e,    phi~_e = (1 - 2 alpha) phi_e,

a partition of unity spanning the same space whose integrals are all positive
(``alpha = 1/5``: ``2 A / 15`` per triangle at a vertex, ``A / 5`` at a mid-edge
node).  In nodal unknowns ``u = T u~``: a vertex keeps its value, a mid-edge
node ``e`` between vertices ``a`` and ``b`` has
``u_e = (1 - 2 alpha) u~_e + alpha (u~_a + u~_b)``.  A linear field has the same
coefficients in both bases.

Here is what contact (:mod:`brakewear.contact.quadratic`), heat
(:mod:`brakewear.thermal.quadratic`) and the interfaces need of such a face,
with no solver behind it: :class:`SlaveBasis` (``T``), :func:`face_quadrature`
(points, weights, transformed and dual functions per facet) and
:func:`quadratic_face_areas` (the integrals of the transformed functions per
node: the areas a nodal pressure is defined on).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp
import skfem as fem

from ..errors import ContactError, MeshError
from .surface import FACE_EDGES, quadratic_faces
from .triangle import subdivided_rule, tri6

logger = logging.getLogger(__name__)

__all__ = ["ALPHA", "SlaveBasis", "transformed", "face_quadrature", "face_numbering",
           "quadratic_face_areas", "slave_basis"]


#: the vertex share of each mid-edge function (Popp et al.'s choice for 6-node triangles)
ALPHA = 0.2


@dataclass(frozen=True)
class SlaveBasis:
    """The transformed basis of a quadratic face: ``u = T u~`` (see the module).

    Attributes
    ----------
    edge : ndarray
        (ne,) global node number of each mid-edge node of the face.
    ends : ndarray
        (2, ne) global node numbers of its two vertices.
    alpha : float
        The vertex share (:data:`ALPHA`).
    """

    edge: np.ndarray
    ends: np.ndarray
    alpha: float = ALPHA

    def __post_init__(self):
        if not 0.0 < self.alpha < 0.5:
            raise ContactError(f"alpha = {self.alpha!r}; need 0 < alpha < 1/2")
        if self.ends.shape != (2, self.edge.size):
            raise ContactError(f"ends has shape {self.ends.shape}; need (2, {self.edge.size})")

    def renumbered(self, col: np.ndarray) -> SlaveBasis:
        """The same basis in another node numbering (``col[old] = new``, all kept)."""
        new = replace(self, edge=col[self.edge], ends=col[self.ends])
        if np.any(new.edge < 0) or np.any(new.ends < 0):
            raise ContactError("a node of a quadratic slave face was eliminated (tied or "
                               "removed); the face needs all its nodes")
        return new

    def node_matrix(self, n_nodes: int, inverse: bool = False) -> sp.csr_matrix:
        """``T`` (or ``T^-1``) on nodes, ``n_nodes`` x ``n_nodes``."""
        a = self.alpha
        d, o = (1.0 / (1.0 - 2.0 * a), -a / (1.0 - 2.0 * a)) if inverse else (1.0 - 2.0 * a, a)
        if self.edge.size and max(self.edge.max(), self.ends.max()) >= n_nodes:
            raise ContactError(f"the face's nodes reach {max(self.edge.max(), self.ends.max())}; "
                               f"the system has {n_nodes} nodes")
        keep = np.ones(n_nodes, dtype=bool)
        keep[self.edge] = False
        ident = np.flatnonzero(keep)
        rows = np.concatenate([ident, self.edge, self.edge, self.edge])
        cols = np.concatenate([ident, self.edge, self.ends[0], self.ends[1]])
        vals = np.concatenate([np.ones(ident.size), np.full(self.edge.size, d),
                               np.full(2 * self.edge.size, o)])
        return sp.csr_matrix((vals, (rows, cols)), shape=(n_nodes, n_nodes))

    def dof_matrix(self, n_dofs: int, inverse: bool = False) -> sp.csr_matrix:
        """``T`` (or ``T^-1``) on vector DOFs ``3 node + i``."""
        return sp.kron(self.node_matrix(n_dofs // 3, inverse), sp.identity(3),
                       format="csr")


def _tri6_derivatives(lam: np.ndarray) -> np.ndarray:
    """d N / d(xi, eta) (2, 6, nq) with ``lam = (1 - xi - eta, xi, eta)``."""
    l0, l1, l2 = lam
    z = np.zeros_like(l0)
    dxi = np.stack([1 - 4 * l0, 4 * l1 - 1, z, 4 * (l0 - l1), 4 * l2, -4 * l2])
    deta = np.stack([1 - 4 * l0, z, 4 * l2 - 1, -4 * l1, 4 * l1, 4 * (l0 - l2)])
    return np.stack([dxi, deta])


def transformed(N: np.ndarray, alpha: float = ALPHA) -> np.ndarray:
    """The transformed functions ``phi~`` (6, ...) from the standard ones (6, ...)."""
    out = np.empty_like(N)
    for v in range(3):
        out[v] = N[v] + alpha * sum(N[3 + k] for k, ab in enumerate(FACE_EDGES) if v in ab)
    out[3:] = (1.0 - 2.0 * alpha) * N[3:]
    return out


def face_quadrature(mesh: fem.Mesh, facets, level: int = 1, alpha: float = ALPHA) -> dict:
    """Quadrature of quadratic facets and their transformed and dual functions.

    Returns a dict: ``nodes`` (6, nf), ``x`` (3, nf, nq) points, ``w`` (nf, nq)
    weights (area), ``lam`` (3, nq) barycentric points, ``phi`` (6, nq)
    transformed functions, ``psi`` (6, nf, nq) dual functions and ``D`` (6, nf)
    the element integrals of ``phi~``.
    """
    nodes = quadratic_faces(mesh, facets)
    X = mesh.p[:, nodes]                                          # (3, 6, nf)
    lam, wr = subdivided_rule(level)
    N = tri6(lam)
    dN = _tri6_derivatives(lam)                                   # (2, 6, nq)
    x = np.einsum("akf,kq->afq", X, N)
    t = np.einsum("akf,dkq->dafq", X, dN)                         # tangents (2, 3, nf, nq)
    jac = np.linalg.norm(np.cross(t[0], t[1], axis=0), axis=0)    # (nf, nq), 2 x area scale
    w = 0.5 * jac * wr
    phi = transformed(N, alpha)
    M = np.einsum("iq,jq,fq->fij", phi, phi, w)
    D = M.sum(axis=2)                                             # (nf, 6)
    if np.any(D <= 0):
        raise MeshError(f"a quadratic facet has a non-positive basis integral "
                         f"({D.min():.3g}): the face is too distorted for alpha = {alpha}")
    A = D[:, :, None] * np.linalg.inv(M)                          # psi = A phi~ per facet
    psi = np.einsum("fij,jq->ifq", A, phi)
    return {"nodes": nodes, "x": x, "w": w, "lam": lam, "phi": phi, "psi": psi, "D": D.T}


def face_numbering(nodes: np.ndarray):
    """``(nodes, local)``: the sorted nodes of facets ``nodes`` (6, nf) and each
    facet node's place among them (6, nf)."""
    slave = np.unique(nodes)
    col = -np.ones(int(nodes.max()) + 1, dtype=np.int64)
    col[slave] = np.arange(slave.size)
    return slave, col[nodes]


def _basis(nodes: np.ndarray, offset: int, alpha: float) -> SlaveBasis:
    """The face's :class:`SlaveBasis` in global numbering (each mid-edge node once)."""
    edge = nodes[3:].ravel()
    ends = np.vstack(
        [nodes[[a for a, _ in FACE_EDGES]].ravel(), nodes[[b for _, b in FACE_EDGES]].ravel()]
    )
    edge, first = np.unique(edge, return_index=True)
    return SlaveBasis(edge + offset, ends[:, first] + offset, alpha)


def quadratic_face_areas(mesh: fem.Mesh, facets, alpha: float = ALPHA):
    """``(nodes, D)``: the face's nodes (vertices and mid-edge nodes, sorted) and
    the integrals of their transformed functions (m^2, all positive, summing
    to the face's area)."""
    q = face_quadrature(mesh, facets, level=0, alpha=alpha)
    slave, local = face_numbering(q["nodes"])
    return slave, np.bincount(local.ravel(), weights=q["D"].ravel(), minlength=slave.size)


def slave_basis(nodes: np.ndarray, offset: int, alpha: float = ALPHA) -> SlaveBasis:
    """The :class:`SlaveBasis` of facets ``nodes`` (6, nf),
    in global numbers (``offset`` = the slave body's first global node)."""
    return _basis(nodes, offset, alpha)
