"""The transformed displacement basis of a quadratic slave face, and contact solves in it.

On a 6-node triangle the integrals of the vertex shape functions are zero, so
a uniform pressure has no consistent load at the vertices and a nodal
multiplier there has no area to divide by.  A quadratic slave face therefore
changes its displacement basis (Popp, Wohlmuth, Gee and Wall): each vertex
function takes ``alpha`` of every mid-edge function of its face edges and each
mid-edge function keeps ``1 - 2 alpha`` of itself,

    phi~_v = phi_v + alpha sum_{e ~ v} phi_e,    phi~_e = (1 - 2 alpha) phi_e,

a partition of unity spanning the same space whose integrals are all positive
(``alpha = 1/5``: ``2 A / 15`` per triangle at a vertex, ``A / 5`` at a mid-edge
node).  In nodal unknowns ``u = T u~``: a vertex keeps its value, a mid-edge
node ``e`` between vertices ``a`` and ``b`` has
``u_e = (1 - 2 alpha) u~_e + alpha (u~_a + u~_b)``.  A linear field has the same
coefficients in both bases.

:class:`SlaveBasis` holds the face's edge nodes and their two vertices, which
is all ``T`` needs; :func:`in_slave_basis` carries a contact problem (stiffness
``T^T K T``, load ``T^T f``, prescribed values ``T^-1 u``) into the transformed
unknowns, where every slave node -- vertex or mid-edge -- is an ordinary node
of the node-by-node elimination (:mod:`~brakewear.contact.elimination`), and
:func:`consistent_pressure` recovers the pressure field from the nodal
contact forces with the face's mass matrix.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp

from ..errors import ContactError

logger = logging.getLogger(__name__)

__all__ = ["ALPHA", "SlaveBasis", "check_supports", "in_slave_basis"]


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

    def renumbered(self, col: np.ndarray) -> "SlaveBasis":
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


def _combined(pairs, n_dofs: int):
    """``(T, T^-1)`` of every pair's slave basis (DOF level), or None if no pair has one."""
    bases = [pr.basis for pr in pairs if getattr(pr, "basis", None) is not None]
    if not bases:
        return None
    edges = np.concatenate([b.edge for b in bases])
    if np.unique(edges).size != edges.size:
        raise ContactError("two contact pairs transform the same quadratic face node; a face "
                           "may be the slave of one pair only")
    moved = np.zeros(n_dofs // 3, dtype=bool)
    moved[edges] = True
    for pr in pairs:
        if pr.coupling is not None and np.any(moved[pr.coupling.indices]):
            raise ContactError(f"{pr.name}: a master node is a mid-edge node of a quadratic "
                               "slave face; a quadratic face can be the slave of a pair but "
                               "not the master of another")
    eye = sp.identity(n_dofs, format="csr")
    T, Ti = eye.copy(), eye.copy()
    for b in bases:
        T = T + (b.dof_matrix(n_dofs) - eye)
        Ti = Ti + (b.dof_matrix(n_dofs, inverse=True) - eye)
    return T.tocsr(), Ti.tocsr()


def check_supports(Ti: sp.csr_matrix, fixed: np.ndarray) -> None:
    """Refuse a supported DOF of a mid-edge node whose vertices are free in that
    direction: its transformed unknown (row of ``T^-1``) would depend on them."""
    is_fixed = np.zeros(Ti.shape[0], dtype=bool)
    is_fixed[fixed] = True
    rows = Ti[np.asarray(fixed)]
    loose = rows.indices[~is_fixed[rows.indices]]
    if loose.size:
        raise ContactError(f"supported DOF(s) on a mid-edge node of a quadratic contact face "
                           f"whose vertex is free in that direction (first free vertex DOF "
                           f"{loose[0]}): support the whole edge or none of it")


def in_slave_basis(K: sp.spmatrix, f: np.ndarray, fixed: np.ndarray, fixed_values: np.ndarray,
                   pairs: list):
    """A contact problem in the transformed unknowns of its quadratic slave faces.

    Returns ``(K~, f~, values~, pairs~, T)``: ``T^T K T``, ``T^T f``, the
    prescribed values of the transformed unknowns, the pairs without their
    :attr:`basis` (they now describe the transformed unknowns) and ``T``
    (``u = T u~``); or the inputs unchanged and ``T = None`` when no pair has
    a quadratic slave face.  A supported DOF of a mid-edge node needs the same
    DOF of its two vertices supported (its transformed value depends on them).
    """
    N = K.shape[0]
    both = _combined(pairs, N)
    if both is None:
        return K, f, fixed_values, pairs, None
    T, Ti = both
    check_supports(Ti, fixed)
    u = np.zeros(N)
    u[fixed] = fixed_values
    Kt = (T.T @ K.tocsr() @ T).tocsr()
    Kt.sort_indices()
    return (Kt, T.T @ np.asarray(f, dtype=float), (Ti @ u)[fixed],
            [replace(pr, basis=None) for pr in pairs], T)
