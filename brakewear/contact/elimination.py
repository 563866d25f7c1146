"""The eliminated system of one active set: frames, prolongation, friction, per-set operators.

Each active contact constraint (the slave's normal displacement equals the
master's interpolated one minus the gap) is a multi-point constraint,
eliminated by ``u = P x + c`` with the slave's DOFs rotated into its normal
frame; the reduced operator ``P^T K P`` stays symmetric positive definite for
pyamg.  Sliding friction along a known direction enters as a thin product.
"""
from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp

from ..errors import ContactError
from ..solvers.patched import PatchedMatrix

logger = logging.getLogger(__name__)

__all__ = ["friction_operators", "body_labels", "check_disjoint"]


def _local_frames(n: np.ndarray):
    """For each normal: the DOF slot that becomes the eliminated (dummy) one
    (the dominant axis) and the tangential directions of the other two slots."""
    k = np.argmax(np.abs(n), axis=0)
    slots = np.array([[1, 2], [0, 2], [0, 1]])[k]  # (ns, 2) retained global axes
    T = np.zeros((2, 3, n.shape[1]))
    for a in range(2):
        e = np.zeros_like(n)
        e[slots[:, a], np.arange(n.shape[1])] = 1.0
        T[a] = e - n * np.einsum("ij,ij->j", e, n)  # e_j minus its normal part
    return k, slots, T


def _active_frames(pairs, active):
    """Per pair with active nodes: the pair, its mask, the active slave nodes, their
    normals and local frames (:func:`_local_frames`)."""
    for pr, act in zip(pairs, active):
        s = pr.slave[act]
        if s.size:
            n = pr.normal[:, act]
            yield (pr, act, s, n, *_local_frames(n))


def _prolongation(N: int, pairs, active):
    """``u = P x + c`` for the active constraints; also the dummy DOFs."""
    elim = []
    rows, cols, vals = [], [], []
    c = np.zeros(N)
    for pr, act, s, n, k, slots, T in _active_frames(pairs, active):
        elim.append(3 * s + k)
        for a in range(2):
            for i in range(3):
                rows.append(3 * s + i)
                cols.append(3 * s + slots[:, a])
                vals.append(T[a, i])
        if not pr.rigid:
            Wc = pr.coupling[np.nonzero(act)[0]].tocoo()
            sr, mr, w = s[Wc.row], Wc.col, Wc.data
            nr = n[:, Wc.row]
            for i in range(3):
                for j in range(3):
                    v = nr[i] * w * nr[j]
                    nz = v != 0
                    rows.append((3 * sr + i)[nz])
                    cols.append((3 * mr + j)[nz])
                    vals.append(v[nz])
        for i in range(3):
            c[3 * s + i] = -pr.g0[act] * n[i]
    elim = np.concatenate(elim) if elim else np.zeros(0, dtype=np.int64)
    slave_dofs = np.concatenate([3 * pr.slave[act][:, None] + np.arange(3)
                                 for pr, act in zip(pairs, active)]).ravel() \
        if any(a.any() for a in active) else np.zeros(0, dtype=np.int64)
    keep = np.ones(N, dtype=bool)
    keep[slave_dofs] = False
    idx = np.nonzero(keep)[0]
    rows.append(idx)
    cols.append(idx)
    vals.append(np.ones(idx.size))
    P = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(N, N))
    return P, c, elim


def check_disjoint(pairs) -> None:
    """Refuse pairs that share a slave node: a node has one normal constraint."""
    nodes = np.concatenate([pr.slave for pr in pairs]) if pairs else np.zeros(0, dtype=int)
    uniq, counts = np.unique(nodes, return_counts=True)
    if np.any(counts > 1):
        n = int(uniq[counts > 1][0])
        names = [pr.name for pr in pairs if np.isin(n, pr.slave)]
        raise ContactError(f"node {n} is a slave node of more than one contact pair "
                           f"({', '.join(names)}); a node may be constrained by one pair only")


def friction_operators(N: int, pairs, active):
    """``G`` (N x n_act): nodal friction load per unit normal force of each active
    slave node (drag on the slave, opposite on its master nodes); ``S`` (n_act x N):
    the normal component at each active slave node."""
    gr, gc, gv, sr, sc, sv = [], [], [], [], [], []
    col0 = 0
    for pr, act in zip(pairs, active):
        idx = np.nonzero(act)[0]
        k = np.arange(idx.size) + col0
        col0 += idx.size
        s = pr.slave[idx]
        for i in range(3):
            sr.append(k)
            sc.append(3 * s + i)
            sv.append(pr.normal[i, idx])
        if not pr.frictional:
            continue
        t = pr.traction()[:, idx]
        for i in range(3):
            gr.append(3 * s + i)
            gc.append(k)
            gv.append(t[i])
            if not pr.rigid:
                Wc = pr.coupling[idx].tocoo()
                gr.append(3 * Wc.col + i)
                gc.append(k[Wc.row])
                gv.append(-Wc.data * t[i, Wc.row])
    G = sp.csr_matrix((np.concatenate(gv), (np.concatenate(gr), np.concatenate(gc))),
                      shape=(N, col0))
    S = sp.csr_matrix((np.concatenate(sv), (np.concatenate(sr), np.concatenate(sc))),
                      shape=(col0, N))
    return G, S


def _reduce_delta(K: sp.csr_matrix, P: sp.csr_matrix) -> sp.csr_matrix:
    """``P^T K P - K`` for a ``P`` that is the identity but in a few rows, without big products.

    With ``D = P - I`` (nonzero only in the constrained rows) and symmetric
    ``K``: ``P^T K P - K = K D + (K D)^T + D^T K D``; every product involves
    only the rows of the constrained DOFs (``K[:, rows] = K[rows]^T``).
    """
    D = (P - sp.identity(K.shape[0], format="csr")).tocsr()
    D.eliminate_zeros()
    rows = np.flatnonzero(np.diff(D.indptr))
    Dr = D[rows]
    Kr = K[rows]
    KD = (Kr.T @ Dr).tocsr()
    DKD = (Dr.T @ (Kr[:, rows] @ Dr)).tocsr()
    return (KD + KD.T + DKD).tocsr()


def _mask_fixed(M: sp.spmatrix, is_fixed: np.ndarray,
                keep_diagonal: bool = False) -> sp.csr_matrix:
    """``M`` without the rows and columns of supported DOFs (CSR, structure
    filtered); with ``keep_diagonal`` their stored diagonal entries stay."""
    M = M.tocsr()
    row = np.repeat(np.arange(M.shape[0]), np.diff(M.indptr))
    keep = ~is_fixed[row] & ~is_fixed[M.indices]
    if keep_diagonal:
        keep |= row == M.indices
    indptr = np.zeros(M.shape[0] + 1, dtype=M.indptr.dtype)
    np.cumsum(np.bincount(row[keep], minlength=M.shape[0]), out=indptr[1:])
    return sp.csr_matrix((M.data[keep], M.indices[keep], indptr), shape=M.shape)


def _mask_fixed_rows(M: sp.spmatrix, is_fixed: np.ndarray) -> sp.csr_matrix:
    """``M`` without the rows of supported DOFs."""
    return (sp.diags((~is_fixed).astype(float)) @ M.tocsr()).tocsr()


def _dirichlet_base(K: sp.csr_matrix, is_fixed: np.ndarray) -> sp.csr_matrix:
    """``K`` with the rows and columns of supported DOFs zeroed, their diagonal kept
    (one filtering pass; a stored diagonal entry is kept as it is)."""
    K = K.tocsr()
    if not K.has_canonical_format:
        K = K.copy()
        K.sum_duplicates()
    return _mask_fixed(K, is_fixed, keep_diagonal=True)


def _set_delta(K, P, elim, is_fixed, diagK):
    """``P^T K P - K`` with the eliminated normal DOFs as decoupled dummies
    (``K``'s diagonal); rows and columns of supported DOFs kept (masked by the caller)."""
    delta = _reduce_delta(K, P)
    if elim.size:
        N = K.shape[0]
        delta = delta + sp.csr_matrix((diagK[elim], (elim, elim)), shape=(N, N))
    return delta


class _SetOperators(PatchedMatrix):
    """``Kd + dK`` for every active set of one solve on a single sparsity pattern
    (:class:`~brakewear.solvers.PatchedMatrix`).

    The pattern is the union of ``Kd``'s and of the structural pattern ``Z``
    of the difference with *every* slave node active (absolute values
    multiplied, so no cancellation drops an entry) and the slave DOFs'
    diagonal (the dummy rows), which contains the difference of any active
    set.  A new set restores the previous set's entries to ``Kd`` and adds
    its own -- work in the size of the difference, where ``Kd + dK`` is a
    pass over the whole matrix (at 490k DOFs, 21M entries: 0.4-0.6 s per
    set).  ``Z`` also gives the coarse levels' patterns
    (:meth:`~brakewear.solvers.AMGSolver.level_buffers`).
    """

    def __init__(self, K, Kd, pairs, is_fixed):
        N = K.shape[0]
        P, _, _ = _prolongation(N, pairs, [np.ones(pr.slave.size, dtype=bool) for pr in pairs])
        D = abs(P - sp.identity(N, format="csr")).tocsr()
        D.eliminate_zeros()
        rows = np.flatnonzero(np.diff(D.indptr))
        Dr, Kr = D[rows], abs(K[rows])
        KD = (Kr.T @ Dr).tocsr()
        dofs = np.unique(np.concatenate([3 * pr.slave[:, None] + np.arange(3) for pr in pairs]
                                        ).ravel())
        Z = KD + KD.T + Dr.T @ (Kr[:, rows] @ Dr) + sp.csr_matrix(
            (np.ones(dofs.size), (dofs, dofs)), shape=(N, N))
        self.Z = _mask_fixed(Z, is_fixed)
        self.Z.eliminate_zeros()
        super().__init__(Kd, self.Z)


def _contact_system(K, Kd, f, pairs, active, P, c, elim, is_fixed, u_fixed, frictional,
                    diagK=None, fine: _SetOperators | None = None):
    """The eliminated system of one active set, supports applied.

    Returns ``A`` (SPD: ``P^T K P`` with a unit-scaled dummy row per eliminated
    normal DOF, supported rows/columns replaced by their diagonal), ``E`` (the
    sliding-friction term, the operator being ``A - E``; None without
    friction), the right-hand side and ``dK = A - Kd``, the small masked
    difference: only the rows of the contact nodes are recomputed.  With
    ``fine`` (:class:`_SetOperators`), ``A`` is formed in its buffer.
    """
    N = K.shape[0]
    diagK = K.diagonal() if diagK is None else diagK
    delta = _set_delta(K, P, elim, is_fixed, diagK)
    dK = _mask_fixed(delta, is_fixed)
    A = (Kd + dK).tocsr() if fine is None else fine.matrix(dK)
    b = P.T @ (f - K @ c)
    E = None
    if frictional:
        # sliding friction mu * lambda along a known direction is linear in u:
        # f_fr = G S (K u - f), S = normal rows of active slaves, G = drag loads
        # kept as the product of its two thin factors (n x n_act, n_act x n): the
        # product itself would have as many nonzeros as K
        G, S = friction_operators(N, pairs, active)
        PG = (P.T @ G).tocsr()
        SKP = ((S @ K) @ P).tocsr()
        b = b + PG @ (S @ (K @ c - f))
        E = (_mask_fixed_rows(PG, is_fixed), _mask_fixed_rows(SKP.T, is_fixed).T.tocsr())
    b[elim] = 0.0
    if np.any(u_fixed):  # prescribed values to the right-hand side
        Au = K @ u_fixed + delta @ u_fixed
        if E is not None:
            Au = Au - PG @ (SKP @ u_fixed)
        b = b - Au
    b[is_fixed] = diagK[is_fixed] * u_fixed[is_fixed]
    return A, E, b, dK


def _reduced_start(u: np.ndarray, pairs, active) -> np.ndarray:
    """The reduced unknowns ``x`` of ``active``'s system that give ``u`` as closely
    as its constraints allow: the warm start after an active-set change.

    Reusing the last set's ``x`` instead would read a released node's dummy
    (0) as its normal displacement -- a jump of the pad's whole approach at
    every released node -- and a new contact node's axis components as its
    tangential coordinates (490k brake, cold solve: 66 linear iterations in
    11 sets that way, 58 in 10 with this start; the last sets begin 3-400x
    closer to their solution).  Here an open node takes ``u``; a contact node's
    two retained slots take the coordinates along its tangential directions
    ``T[a]`` (``u_s + alpha n`` with zero dominant component) and its dummy 0.
    """
    x = np.array(u, dtype=float)
    for _, _, s, n, k, slots, _ in _active_frames(pairs, active):
        idx = np.arange(s.size)
        us = u.reshape(-1, 3)[s]  # (ns, 3)
        alpha = -us[idx, k] / n[k, idx]
        for a in range(2):
            x[3 * s + slots[:, a]] = us[idx, slots[:, a]] + alpha * n[slots[:, a], idx]
        x[3 * s + k] = 0.0
    return x


def body_labels(K: sp.csr_matrix) -> np.ndarray | None:
    """Body label per node: the connected components of ``K``'s node graph
    (contact couples bodies only through the constraints); None for one body."""
    from scipy.sparse.csgraph import connected_components

    K = K.tocsr()
    first = K[::3]  # a node's x row couples to every node its y and z rows do
    graph = sp.csr_matrix((np.ones(first.nnz, dtype=np.int8), first.indices // 3,
                           first.indptr), shape=(K.shape[0] // 3, K.shape[0] // 3))
    n, labels = connected_components(graph, directed=False)
    return labels if n > 1 else None


def _reduced_modes(coords, pairs, active, fixed):
    from ..solvers.amg import rigid_body_modes

    return rigid_body_modes(coords, fixed)
