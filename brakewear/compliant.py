"""Contact through a compliant interface layer: the implicit (backward Euler) wear step.

An implicit Archard step of length ``dt`` wears each pad node by
``dh_i = dt k v_i p_i`` with the pressure ``p_i`` at the *end* of the step.
The new gap must close over the worn depth, so the interface behaves as a
layer of compliance ``eps_i = dt k v_i`` (m/Pa) between pad and rotor: a
spring of stiffness ``kappa_i = A_i / eps_i`` (N/m) at each contact node,
active while it is compressed.  Solving that contact problem *is* the
backward Euler step: it is unconditionally stable (the wear ODE's stiff
short-wavelength modes are damped, not amplified), so a step can be as long
as accuracy allows, where explicit Euler is bound to ``dt c_i s_i/A_i < 2``.

The compliance is physical (the step's wear), not a penalty parameter: the
solution is the exact backward Euler step, and the spring force is the
contact pressure.  With ``eps -> 0`` it becomes the rigid (Lagrange) contact
of :func:`brakewear.contact.solve_contact`.

The system ``(K + C_A^T kappa C_A) u = f - C_A^T kappa g0_A`` stays SPD
without friction (AMG-preconditioned CG); sliding friction ``mu p`` along a
known direction is linear in ``u`` and enters the operator (flexible GMRES
with the same hierarchy).
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from .contact import ActiveSetError, ContactLostError, ContactPair

logger = logging.getLogger(__name__)

__all__ = ["constraint_rows", "solve_compliant_contact", "compliant_preconditioner",
           "CompliantResult"]


@dataclass
class CompliantResult:
    """Contact through compliant springs: displacements and the nodal contact state."""

    u: np.ndarray
    pressure: np.ndarray   # (ns,) Pa, spring force / tributary area, 0 where open
    force: np.ndarray      # (ns,) N, normal force at each slave node
    gap: np.ndarray        # (ns,) m, g0 + C u (negative: the layer is compressed)
    active: np.ndarray     # (ns,) bool
    info: dict = field(default_factory=dict)


def constraint_rows(pair: ContactPair, n_dofs: int) -> sp.csr_matrix:
    """``C`` (n_slave x n_dofs) with ``gap = g0 + C u``: the normal component of the
    slave's displacement relative to the master point under it."""
    n, s = pair.normal, pair.slave
    ns = s.size
    rows = [np.repeat(np.arange(ns), 3)]
    cols = [(3 * s[:, None] + np.arange(3)).ravel()]
    vals = [n.T.ravel()]
    if not pair.rigid:
        W = pair.coupling.tocoo()
        for j in range(3):
            rows.append(W.row)
            cols.append(3 * W.col + j)
            vals.append(-W.data * n[j, W.row])
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(ns, n_dofs))


def _drag_loads(pair: ContactPair, n_dofs: int) -> sp.csr_matrix:
    """``G`` (n_dofs x n_slave): nodal friction load per newton of normal force."""
    ns, s = pair.slave.size, pair.slave
    t = pair.mu * pair.drag
    rows = [(3 * s[:, None] + np.arange(3)).ravel()]
    cols = [np.repeat(np.arange(ns), 3)]
    vals = [t.T.ravel()]
    if not pair.rigid:
        W = pair.coupling.tocoo()
        for j in range(3):
            rows.append(3 * W.col + j)
            cols.append(W.row)
            vals.append(-W.data * t[j, W.row])
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(n_dofs, ns))


def solve_compliant_contact(K: sp.spmatrix, f: np.ndarray, fixed: np.ndarray,
                            coords: np.ndarray, pair: ContactPair, compliance: np.ndarray,
                            initial_active: np.ndarray | None = None, tol: float = 1e-9,
                            max_iter: int = 60, solver=None) -> CompliantResult:
    """Contact of ``pair`` through springs of compliance ``compliance`` (m/Pa per slave node).

    Parameters
    ----------
    K, f, fixed, coords
        As in :func:`brakewear.contact.solve_contact` (supports are zero).
    compliance
        (n_slave,) gap change per unit contact pressure, > 0 (``dt k v`` for
        an implicit Archard step).
    initial_active
        Start set (default: the nodes with ``g0 <= 0``, or the closest ones).
    solver
        A base :class:`~brakewear.solvers.AMGSolver` of ``K`` with its supports
        (:func:`compliant_preconditioner`), shared by many solves: each active
        set gets a refreshed copy, the base is never modified, so the result
        depends only on the inputs (exact resume).  Default: a hierarchy
        built for this solve.

    The active set follows the penalty rule: a node is active while its
    spring is compressed (``g0 + C u < 0``).  A repeating set raises
    :class:`~brakewear.contact.ActiveSetError` with its figures.
    """
    from .elasticity import apply_dirichlet
    from .solvers import amg_solver

    t0 = time.perf_counter()
    K = K.tocsr()
    N = K.shape[0]
    eps = np.asarray(compliance, dtype=float)
    ns = pair.slave.size
    if eps.shape != (ns,) or not np.all(np.isfinite(eps)) or np.any(eps <= 0):
        raise ValueError(f"{pair.name}: compliance must be ({ns},) finite and > 0 m/Pa; got "
                         f"shape {eps.shape}, min {np.min(eps) if eps.size else None!r}")
    kappa = pair.area / eps
    C = constraint_rows(pair, N)
    G = _drag_loads(pair, N) if pair.mu > 0 else None
    fixed = np.unique(np.asarray(fixed, dtype=np.int64))
    is_fixed = np.zeros(N, dtype=bool)
    is_fixed[fixed] = True
    if initial_active is None:
        active = pair.g0 <= 0
        if not active.any():
            active = pair.g0 <= pair.g0.min() + 1e-12 * max(np.abs(pair.g0).max(), 1e-300)
    else:
        active = np.asarray(initial_active, dtype=bool).copy()
    base, amg, x, seen, its, lin = solver, None, None, set(), 0, 0
    if base is not None and base.A.shape != (N, N):
        raise ValueError(f"solver is a hierarchy of size {base.A.shape[0]}; the system has {N}")
    for its in range(1, max_iter + 1):
        if not active.any():
            raise ContactLostError(f"{pair.name}: no node is compressed after {its - 1} "
                                   "iteration(s): the load separates the bodies")
        Ca = C[active]
        ka = kappa[active]
        A = (K + Ca.T @ sp.diags(ka) @ Ca).tocsr()
        b = f - Ca.T @ (ka * pair.g0[active])
        Ad, bd = apply_dirichlet(A.tobsr(blocksize=(3, 3)), b, fixed)
        Aop = Ad
        if G is not None:
            Ga = G[:, active]
            # friction = G lambda with lambda = -kappa (g0 + C u): linear in u
            E = (Ga @ sp.diags(ka) @ Ca).tocsr()
            bd = bd - np.where(is_fixed, 0.0, Ga @ (ka * pair.g0[active]))
            Ec = E.tocoo()
            keep = ~is_fixed[Ec.row] & ~is_fixed[Ec.col]
            Aop = (Ad.tocsr() + sp.csr_matrix((Ec.data[keep], (Ec.row[keep], Ec.col[keep])),
                                              shape=(N, N))).tocsr()
        if base is not None:
            amg = base.refreshed(Ad)
            amg.tol = tol
        elif amg is None:
            amg = amg_solver(Ad, coords=coords, fixed=fixed, tol=tol)
        else:
            amg.refresh(Ad)
        x = amg.solve(bd, x0=x, A=Aop, krylov="gmres" if G is not None else "cg")
        lin += amg.info.iterations
        g = pair.g0 + C @ x
        new = g < 0
        if np.array_equal(new, active):
            break
        key = np.packbits(new).tobytes()
        if key in seen:
            raise ActiveSetError(f"{pair.name}: compliant active set cycles after {its} "
                                 f"iterations ({int(active.sum())} -> {int(new.sum())} active)")
        seen.add(np.packbits(active).tobytes())
        active = new
    else:
        raise ActiveSetError(f"{pair.name}: compliant active set did not settle in {max_iter} "
                             f"iterations (last count {int(active.sum())})")
    force = np.where(active, -kappa * g, 0.0)
    info = {"active_set_iterations": its, "linear_iterations": lin,
            "normal_force": float(force.sum()), "time_s": time.perf_counter() - t0}
    return CompliantResult(x, force / pair.area, force, g, active, info)


def compliant_preconditioner(K: sp.spmatrix, fixed: np.ndarray, coords: np.ndarray,
                             tol: float = 1e-9):
    """The base AMG hierarchy of ``K`` with its supports, for
    ``solve_compliant_contact(..., solver=)``: built once per stiffness (a
    wear history in gap-offset mode keeps it for every step)."""
    from .elasticity import apply_dirichlet
    from .solvers import amg_solver

    K = K.tocsr()
    fixed = np.unique(np.asarray(fixed, dtype=np.int64))
    Kd, _ = apply_dirichlet(K.tobsr(blocksize=(3, 3)), np.zeros(K.shape[0]), fixed)
    return amg_solver(Kd, coords=coords, fixed=fixed, tol=tol)
