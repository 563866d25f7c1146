"""Direct references for the contact benchmark: the KKT system of a contact set, its
factorisation by PARDISO or SuperLU, and a direct active-set solve."""
from __future__ import annotations

import logging
import time

import numpy as np

logger = logging.getLogger(__name__)


__all__ = [
    "kkt_system",
    "symmetric_upper",
    "kkt_solves",
    "direct_active_set",
    "direct_active_set_row",
]


def kkt_system(K, f, fixed, fixed_values, pair, active):
    """The saddle-point system at a fixed active set, Dirichlet DOFs removed.

    Unknowns ``(u_free, lambda)`` (``lambda`` = normal contact force of each
    active slave node, > 0 in compression)::

        [ K_ff   -(C_f^T + G_f) ] [u]   [ f_f - K_fc u_c      ]
        [ -C_f    0             ] [l] = [ g0 + C_c u_c        ]

    ``C`` (one row per active slave node) is the normal gap ``n . (u_s - sum
    W u_m)`` including the coupling to the master nodes, ``G`` the sliding
    friction load per unit normal force (drag on the slave, opposite on its
    masters).  Without friction the matrix is symmetric (indefinite).
    Returns (matrix CSR, rhs, free DOFs, active slave indices).
    """
    import scipy.sparse as sp

    from ..contact.elimination import friction_operators

    N = K.shape[0]
    idx = np.flatnonzero(active)
    s, n = pair.slave[idx], pair.normal[:, idx]
    k = np.arange(idx.size)
    rows, cols, vals = [], [], []
    for i in range(3):
        rows.append(k)
        cols.append(3 * s + i)
        vals.append(n[i])
    if not pair.rigid:
        Wc = pair.coupling[idx].tocoo()
        for i in range(3):
            rows.append(Wc.row)
            cols.append(3 * Wc.col + i)
            vals.append(-Wc.data * n[i, Wc.row])
    C = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(idx.size, N))
    B = C.T.tocsr()
    if pair.frictional:
        G, _ = friction_operators(N, [pair], [np.asarray(active, dtype=bool)])
        B = (B + G).tocsr()
    isfixed = np.zeros(N, dtype=bool)
    isfixed[fixed] = True
    free = np.flatnonzero(~isfixed)
    uc = np.zeros(N)
    uc[fixed] = fixed_values
    K = K.tocsr()
    Kf = K[free][:, free]
    rhs_u = (np.asarray(f, dtype=float) - K @ uc)[free]
    rhs_l = pair.g0[idx] + C @ uc
    M = sp.bmat([[Kf, -B[free]], [-C[:, free], None]], format="csr")
    return M, np.concatenate([rhs_u, rhs_l]), free, idx


def symmetric_upper(M):
    """The upper triangle of a symmetric sparse matrix with every diagonal entry
    stored (explicit zeros on the multiplier block), as PARDISO's symmetric
    matrix types require; CSR with sorted indices."""
    import scipy.sparse as sp

    U = sp.triu(M, format="coo")
    off = U.row != U.col
    n = M.shape[0]
    d = np.zeros(n)
    np.add.at(d, U.row[~off], U.data[~off])
    rows = np.concatenate([U.row[off], np.arange(n)])
    cols = np.concatenate([U.col[off], np.arange(n)])
    vals = np.concatenate([U.data[off], d])
    out = sp.csr_matrix((vals, (rows, cols)), shape=M.shape)  # keeps the explicit zeros
    out.sort_indices()
    return out


def kkt_solves(M, rhs, n_u: int, lam_ref: np.ndarray, row: dict, superlu: bool = True,
                symmetric: bool = False) -> None:
    """Factorise and solve the KKT system with SuperLU and (if installed) PARDISO:
    as a real unsymmetric matrix (type 11) and, for a symmetric system (no
    friction), also as a symmetric indefinite one (type -2, Bunch-Kaufman
    pivoting on the upper triangle: about half the factor)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    scale = max(np.abs(lam_ref).max(), 1e-300)
    best = None
    if superlu:
        t0 = time.perf_counter()
        lu = spla.splu(sp.csc_matrix(M))
        x = lu.solve(rhs)
        row["direct_kkt_superlu_s"] = time.perf_counter() - t0
        del lu
        row["kkt_multiplier_diff_superlu"] = float(np.abs(x[n_u:] - lam_ref).max() / scale)
        best = ("superlu", row["direct_kkt_superlu_s"], row["kkt_multiplier_diff_superlu"])
    try:
        import pypardiso  # optional, benchmark only (MKL PARDISO); not a runtime dependency
    except ImportError:
        pypardiso = None
    if pypardiso is not None:
        solver = pypardiso.PyPardisoSolver()  # mtype 11: real unsymmetric
        t0 = time.perf_counter()
        x = solver.solve(sp.csr_matrix(M), rhs)  # analysis + factorisation + solve
        row["direct_kkt_pardiso_s"] = time.perf_counter() - t0
        solver.free_memory(everything=True)
        row["kkt_multiplier_diff_pardiso"] = float(np.abs(x[n_u:] - lam_ref).max() / scale)
        if best is None or row["direct_kkt_pardiso_s"] < best[1]:
            best = ("pardiso", row["direct_kkt_pardiso_s"], row["kkt_multiplier_diff_pardiso"])
        if symmetric:
            solver = pypardiso.PyPardisoSolver(mtype=-2)  # real symmetric indefinite
            t0 = time.perf_counter()
            U = symmetric_upper(M)
            x = solver.solve(U, rhs)
            row["direct_kkt_pardiso_sym_s"] = time.perf_counter() - t0
            solver.free_memory(everything=True)
            row["kkt_multiplier_diff_pardiso_sym"] = float(np.abs(x[n_u:] - lam_ref).max()
                                                           / scale)
            if row["direct_kkt_pardiso_sym_s"] < best[1]:
                best = ("pardiso-sym", row["direct_kkt_pardiso_sym_s"],
                        row["kkt_multiplier_diff_pardiso_sym"])
    if best is not None:
        row["direct_kkt_solver"], row["direct_kkt_s"], row["kkt_multiplier_diff"] = best


class _KKTSets:
    """The KKT system of one active set after another, solved by ``factorize``
    (a :class:`~brakewear.contact.active_set.SetProblem` for the shared driver)."""

    def __init__(self, K, f, fixed, fixed_values, pair, gap_tol, symmetric, factorize):
        self.args = (K, f, fixed, fixed_values, pair)
        self.pair, self.gap_tol, self.symmetric, self.factorize = pair, gap_tol, symmetric, \
            factorize
        self.uc = np.zeros(K.shape[0])
        self.uc[fixed] = fixed_values
        self.t_solve = self.t_assembly = 0.0

    def solve(self, active, tol, rtol0) -> None:
        t0 = time.perf_counter()
        M, rhs, free, idx = kkt_system(*self.args, active)
        M = symmetric_upper(M) if self.symmetric else M
        t1 = time.perf_counter()
        x = self.factorize(M, rhs)
        self.u = self.uc.copy()
        self.u[free] = x[:free.size]
        self.lam = np.zeros(self.pair.slave.size)
        self.lam[idx] = x[free.size:]
        self.t_solve += time.perf_counter() - t1
        self.t_assembly += t1 - t0

    def margins(self, active, band):
        from ..contact.active_set import Margins
        t0 = time.perf_counter()
        gaps = np.where(active, 0.0, self.pair.gaps(self.u))
        m = Margins(self.lam, band * max(np.abs(self.lam).max(), 1e-300), -gaps, self.gap_tol)
        self.t_solve += time.perf_counter() - t0
        return m


def _pardiso(symmetric: bool):
    """PARDISO's analysis, factorisation and solve of each system, or None."""
    try:
        import pypardiso
    except ImportError:
        return None
    # one wrapper for all sets: its construction finds the MKL library (0.1 s), no PARDISO work
    solver = pypardiso.PyPardisoSolver(mtype=-2 if symmetric else 11)

    def factorize(M, rhs):
        x = solver.solve(M, rhs)
        solver.free_memory(everything=True)
        return x
    return factorize


def direct_active_set(K, f, fixed, fixed_values, pair, gap_tol: float, symmetric: bool,
                      release_tol: float = 1e-6, max_iter: int = 30,
                      factorize=None) -> dict | None:
    """A direct active-set solve: the shared driver's primal-dual rule
    (:class:`~brakewear.contact.active_set.ActiveSetDriver` with the
    :data:`~brakewear.contact.active_set.EXACT` policy, as ``solve_contact``
    with ``linear="direct"``) with every set's KKT system (:func:`kkt_system`)
    solved by ``factorize(M, rhs)``: by default MKL PARDISO (symmetric
    indefinite where ``symmetric``, else real unsymmetric), from the same
    start (the nodes with ``g0 <= gap_tol``).

    What a direct solver does with a cold contact problem, the like-for-like
    of a cold ``solve_contact``.  Returns ``time_s`` (the analysis,
    factorisation and solve of every set plus the gaps and the update; the
    KKT assemblies apart in ``assembly_s``, since :func:`kkt_system` slices
    ``K`` anew for every set where a direct code would do it once: leaving
    them out favours the direct solve), ``iterations``, the final ``active``
    set and its ``force`` (multipliers per slave node), or ``None`` without
    pypardiso (and no ``factorize``).  Raises
    :class:`~brakewear.errors.ActiveSetError` if the set does not settle in
    ``max_iter``.  A given ``factorize`` gets the full matrix.
    """
    from dataclasses import replace

    from ..contact.active_set import EXACT, ActiveSetDriver
    if factorize is None:
        factorize = _pardiso(symmetric)
        if factorize is None:
            return None
    else:
        symmetric = False
    problem = _KKTSets(K, f, fixed, fixed_values, pair, gap_tol, symmetric, factorize)
    driver = ActiveSetDriver(replace(EXACT, max_iter=max_iter, release_tol=release_tol), 0.0,
                             exact=True, name="direct active-set solve")
    active = driver.run(problem, pair.g0 <= gap_tol)
    return {"time_s": problem.t_solve, "assembly_s": problem.t_assembly,
            "iterations": driver.solves, "active": active, "force": problem.lam}


def direct_active_set_row(row: dict, K, f, fixed, fixed_values, pair, gap_tol: float,
                           symmetric: bool, res) -> None:
    """``direct_active_set_s`` and its checks against ``solve_contact``'s result ``res``."""
    out = direct_active_set(K, f, fixed, fixed_values, pair, gap_tol, symmetric)
    if out is None:
        row["direct_active_set_s"] = None
        return
    lam = res.force[0]
    row["direct_active_set_s"] = out["time_s"]
    row["direct_active_set_assembly_s"] = out["assembly_s"]
    row["direct_active_set_iterations"] = out["iterations"]
    row["direct_active_set_same_set"] = bool(np.array_equal(out["active"], res.active[0]))
    row["direct_active_set_force_diff"] = float(np.abs(out["force"] - lam).max()
                                                / max(np.abs(lam).max(), 1e-300))


