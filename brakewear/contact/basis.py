"""Contact solves in the transformed displacement basis of quadratic slave faces.

A quadratic slave face changes its displacement basis (Popp, Wohlmuth, Gee
and Wall) so that every nodal integral is positive,
:class:`~brakewear.mesh.quadratic.SlaveBasis` (``u = T u~``; the surface
geometry in :mod:`brakewear.mesh.quadratic`).  :func:`in_slave_basis` carries a contact problem
(stiffness
``T^T K T``, load ``T^T f``, prescribed values ``T^-1 u``) into the transformed
unknowns, where every slave node -- vertex or mid-edge -- is an ordinary node
of the node-by-node elimination (:mod:`~brakewear.contact.elimination`), and
:func:`consistent_pressure` recovers the pressure field from the nodal
contact forces with the face's mass matrix.
"""
from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np
import scipy.sparse as sp

from ..errors import ContactError

logger = logging.getLogger(__name__)

__all__ = ["check_supports", "in_slave_basis"]


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
