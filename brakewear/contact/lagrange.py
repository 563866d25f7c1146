"""Interfaces between bodies: node-to-surface projection and tied constraints.

Slave nodes (for the pad-rotor interface, the pad's friction-face nodes) are
projected onto master facets (the rotor's friction face).  The projection
gives, per slave node, the master facet, the barycentric weights of the
projected point, the signed normal gap and the master's outward normal.

A *tie* glues the slave nodes to the master surface: every slave DOF equals
the master displacement interpolated at its projection.  It is imposed by
multi-point-constraint elimination, ``u = P u_r``, which keeps the reduced
system ``P^T K P`` symmetric positive definite for pyamg; the interface
traction is recovered as the slave nodes' residual forces ``K u - f``.  The
same projection and elimination are the building blocks of frictional
contact, where only the normal component is tied on the active set.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import ActiveSetError, ContactLostError
from .active_set import (
    _FIRST,
    _INEXACT,
    _MEDIUM,
    _SETTLING,
    _conservative_update,
    _pdas_update,
    _set_key,
)
from .elimination import (
    _bodies,
    _contact_system,
    _dirichlet_base,
    _prolongation,
    _reduced_modes,
    _reduced_start,
    _SetOperators,
)

logger = logging.getLogger(__name__)

__all__ = ["ContactResult", "solve_contact", "contact_preconditioner"]


@dataclass
class ContactResult:
    """Contact solution: displacements and, per pair, the nodal contact state."""

    u: np.ndarray
    pressure: list       # per pair: (ns,) normal pressure (Pa), 0 where open
    force: list          # per pair: (ns,) normal nodal force (N)
    gap: list            # per pair: (ns,) normal gap after deformation (m)
    active: list         # per pair: (ns,) bool, in contact
    friction: list       # per pair: (3, ns) tangential nodal force on the slave (N)
    info: dict = field(default_factory=dict)


def solve_contact(K: sp.spmatrix, f: np.ndarray, fixed: np.ndarray, coords: np.ndarray,
                  pairs: list, fixed_values: np.ndarray | float = 0.0, tol: float = 1e-9,
                  gap_tol: float | None = None,
                  max_iter: int = 60, linear: str = "amg", release_tol: float = 1e-6,
                  initial_active: list | None = None, solver=None) -> ContactResult:
    """Frictional node-to-surface contact by active sets on an eliminated system.

    Parameters
    ----------
    K, f
        Global stiffness (all bodies, DOF ``3 node + i``) and load.
    fixed, fixed_values
        Supported DOFs and their prescribed displacements (default 0).  A
        supported normal DOF on an active slave node is refused.
    coords
        Node coordinates (3, n_nodes) for the rigid-body near-nullspace.
    pairs
        :class:`ContactPair` list.
    tol
        Relative residual of each linear solve.
    gap_tol
        Penetration tolerated before a node is activated; default 1e-10 times
        the model size.
    linear
        ``"amg"`` (pyamg CG, hierarchy reused across iterations) or
        ``"direct"`` (small systems).
    release_tol
        A contact node is released only if its multiplier is below
        ``-release_tol * max |lambda|``: a margin above the linear solver's
        noise, without which nodes at the contact edge can flip forever.
    initial_active
        Starting active set per pair (default: the nodes with ``g0 <=
        gap_tol``, else the closest ones); a wear step passes the last one.
        A given set is taken as a good guess: every solve is then tight.
    solver
        A hierarchy from :func:`contact_preconditioner` for this ``K``,
        ``fixed`` and pair geometry, shared between solves (a wear loop).
        It is never modified: each active set gets a refreshed copy, so the
        result depends only on the inputs and this hierarchy, not on earlier
        solves.  Default: one is built at the initial active set.

    The active set follows the primal-dual rule (a node in contact stays if
    its multiplier is compressive, an open node enters if it penetrates).
    If an active set repeats (cycling), the update turns conservative: add
    penetrating nodes, release only the most tensile one per iteration.
    Sliding friction with a known slip direction is linear in the
    displacements (``mu`` times the normal reaction, along ``drag``), so it
    enters the operator itself: each active set is one flexible GMRES solve
    (AMG of the symmetric part as preconditioner), not a fixed point.

    Cost: per active set, ``P^T K P`` is ``K`` plus a difference local to
    the contact rows, and the AMG operators of every level are updated by
    that difference (the coarsest level is refactorised: a few hundredths of
    a second).  While the set moves, the first solve stops at
    ``1e-2`` and later ones at a tenth of their warm-start residual; once it
    repeats (or an edge node flips twice), the solves stop at ``1e-6`` while
    the set still changes, and one solve to ``tol`` confirms the last one.
    The near-nullspace keeps the rigid-body modes on the dummy DOFs, and the
    aggregates stay inside the bodies of ``K`` (:func:`_bodies`), so a
    hierarchy built at one set still serves the others (490k brake, final
    set: 34 FGMRES iterations refreshed from the all-closed set, 29 built
    there; 48 with aggregates across the interface).  Each new set starts
    from the last displacement (:func:`_reduced_start`).
    """
    from ..solvers.amg import amg_solver
    from ..solvers.direct import direct_solve

    t_start = time.perf_counter()
    K = K.tocsr()
    N = K.shape[0]
    f = np.asarray(f, dtype=float)
    fixed = np.asarray(fixed, dtype=np.int64)
    fvals = np.broadcast_to(np.asarray(fixed_values, dtype=float), fixed.shape)
    fixed, first = np.unique(fixed, return_index=True)
    fvals = fvals[first]
    size = float(np.linalg.norm(coords.max(axis=1) - coords.min(axis=1)))
    gap_tol = 1e-10 * size if gap_tol is None else gap_tol
    if linear not in ("amg", "direct"):
        raise ValueError(f"linear = {linear!r}; allowed: 'amg', 'direct'")
    if initial_active is None:
        active = [pr.g0 <= gap_tol for pr in pairs]
        if not any(a.any() for a in active):  # first touch: the closest nodes
            gmin = min(pr.g0.min() for pr in pairs)
            active = [pr.g0 <= gmin + gap_tol for pr in pairs]
    else:
        active = [np.asarray(a, dtype=bool).copy() for a in initial_active]
    base_delta = None  # the base hierarchy's operator minus Kd, where known
    if solver is not None:
        _check_base(solver, N)
        known = getattr(solver, "contact_delta", None)  # set by contact_preconditioner
        if known is not None and known[0] is solver.A:
            base_delta = known[1]
    seen = set()
    flips = [np.zeros(pr.slave.size, dtype=np.int64) for pr in pairs]  # state changes per node
    conservative = False
    x = None
    lin_its, builds, refreshes, history = 0, 0, 0, []
    is_fixed = np.zeros(N, dtype=bool)
    is_fixed[fixed] = True
    u_fixed = np.zeros(N)
    u_fixed[fixed] = fvals
    frictional = any(pr.mu > 0 for pr in pairs)
    Kd = _dirichlet_base(K, is_fixed)
    diagK = K.diagonal()
    base = solver  # the hierarchy every refresh starts from; never modified here
    bodies = False  # node labels of K's bodies for the hierarchy's aggregates, when needed
    fine = None    # _SetOperators, from the second active set on
    coarse = None  # the base hierarchy's coarse operators in place (AMGSolver.level_buffers)
    refreshes_of_base = 0
    work = None    # the preconditioner of the current active set
    set_key = None
    # inexact phase: while the active set moves, each solve only has to cut its
    # warm-start residual by _INEXACT; once it stops moving, a tight solve confirms it.
    # A given initial set (a wear step, an outer iteration) is taken as nearly right:
    # tight solves from the start, since a loose one's noise moves edge nodes in and
    # out (measured on the 57k brake from its converged set: 48 iterations and a cycle
    # with a loose first solve, 39 and no change with a tight one)
    tight = initial_active is not None
    tight_reason = "given set" if tight else None  # why the solves went tight (info)
    tight_from = 1 if tight else None
    # after the loose phase the solves first stop at _MEDIUM: accurate enough to decide
    # the edge nodes, and if they still move, much cheaper than a solve to tol each time
    # (Hertz 491k made five tight solves of 16-19 iterations while its set shrank); a
    # set that a medium solve reproduces is then confirmed by one solve to tol
    medium = False
    ref_rate = None     # residual reduction per iteration of the first solve of >= 4 its
    for it in range(1, max_iter + 1):
        if not any(a.any() for a in active):
            raise ContactLostError(
                f"no node is in contact after {it - 1} active-set iteration(s): the load "
                f"separates the bodies (net load {f.reshape(-1, 3).sum(axis=0)} N). A contact "
                "solve needs a load that presses the surfaces together.")
        key = _set_key(active)
        if key != set_key:  # a new active set: its operator and preconditioner
            P, c, elim = _prolongation(N, pairs, active)
            clash = np.intersect1d(elim, fixed)
            if clash.size:
                raise ValueError(f"{clash.size} supported DOF(s) are the normal DOF of a contact "
                                 f"node (first: DOF {clash[0]}); a node cannot be both supported "
                                 "and in contact along the normal")
            if fine is None and set_key is not None and linear == "amg":
                # a second set in this solve: from now on each set's operator is formed
                # in place (one pass over K to set up, none per set)
                fine = _SetOperators(K, Kd, pairs, is_fixed)
            A, E, bd, dK = _contact_system(K, Kd, f, pairs, active, P, c, elim, is_fixed,
                                           u_fixed, frictional, diagK, fine)
            if x is not None:  # warm start: the last displacement in this set's unknowns
                x = _reduced_start(u, pairs, active)
            set_key = key
            if E is None:
                Aop = A
            elif linear == "direct":
                Aop = (A - E[0] @ E[1]).tocsr()
            else:
                Aop = spla.LinearOperator(
                    A.shape, matvec=lambda v, A=A, G=E[0], S=E[1]: A @ v - G @ (S @ v),
                    dtype=float)
            if linear == "amg":
                if base is None or (ref_rate is not None and _stale(work.info, ref_rate)):
                    # the first set, or the aggregates have gone stale: a hierarchy of this set
                    if bodies is False:
                        bodies = _bodies(K)
                    # the set's CSR operator serves as the finest level unless it lives
                    # in fine's buffer, which the next set overwrites
                    base = amg_solver(A.tobsr(blocksize=(3, 3)),
                                      B=_reduced_modes(coords, pairs, active, fixed), tol=tol,
                                      bodies=bodies, fine_csr=A if fine is None else None)
                    base_delta = dK
                    builds += 1
                    refreshes_of_base = 0
                    work = base
                else:  # same aggregates, operators of this set (base left as it is)
                    # A - base.A from the two small contact differences: at 490k DOFs the
                    # subtraction of the two full matrices took 0.7 s per set
                    # coarse operators in place from the second refresh of a big hierarchy
                    # on (_BUFFER_MIN_NNZ)
                    if fine is not None and refreshes_of_base >= 1 and \
                            (coarse is None or coarse.ml is not base.ml) and \
                            sum(lv.A.nnz for lv in base.ml.levels[1:]) >= _BUFFER_MIN_NNZ:
                        coarse = base.level_buffers(fine.Z)
                    work = base.refreshed(A, depth=_REFRESH_DEPTH,
                                          dA=None if base_delta is None else dK - base_delta,
                                          buffers=coarse)
                    refreshes += 1
                    refreshes_of_base += 1
        if linear == "direct":
            x = direct_solve(Aop, bd)
            its = "direct"
        else:
            work.tol = tol
            rtol0 = None
            if tight and medium:
                work.tol = max(tol, _MEDIUM)
            elif not tight:
                if x is None:
                    work.tol = max(tol, _FIRST)
                else:  # cut the warm start's residual by _INEXACT
                    rtol0 = _INEXACT
            x = work.solve(bd, x0=x, A=Aop, krylov="gmres" if frictional else "cg", rtol0=rtol0)
            its = work.info.iterations
            if ref_rate is None and its >= 4:
                # the reference rate of this hierarchy: a solve of at least 4 iterations
                # (Hertz at 491k: a 2-iteration first solve reduced 0.09 per iteration,
                # so every later tight solve at 0.3 looked stale and was rebuilt, 9 s each)
                ref_rate = work.info.convergence_factor
            lin_its += its
        u = P @ x + c
        logger.debug("active-set iteration %d: %d active, %s linear iterations", it,
                     sum(int(a.sum()) for a in active), its)
        r = (K @ u - f).reshape(-1, 3)
        lam = [np.where(a, np.einsum("ij,ij->j", pr.normal, r[pr.slave].T), 0.0)
               for pr, a in zip(pairs, active)]
        gaps = [np.where(a, 0.0, pr.gaps(u)) for pr, a in zip(pairs, active)]
        ltol = [release_tol * max(np.abs(l).max(), 1e-300) for l in lam]
        update = _conservative_update if conservative else _pdas_update
        new_active = update(active, lam, gaps, gap_tol, ltol)
        same = all(np.array_equal(a, b2) for a, b2 in zip(active, new_active))
        history.append(int(sum(a.sum() for a in active)))
        if same:
            if (tight and not medium) or linear == "direct":
                break
            if tight:  # a medium solve reproduced its set: confirm it to tol
                medium = False
            else:
                tight, medium, tight_reason = True, True, "set repeated"
                tight_from = it + 1
            continue
        n_act = sum(int(a.sum()) for a in active)
        if not any(a.any() for a in new_active) and n_act > 1:
            # the primal-dual rule released every node at once (an overshoot on a
            # very non-conformal start; an empty set is singular): keep the tenth
            # of the set that pulls least.  A load that really lifts the pad off
            # empties the set in a few such steps and ends in ContactLostError.
            keep = max(1, n_act // 10)
            cut = np.sort(np.concatenate([l[a] for l, a in zip(lam, active)]))[-keep]
            new_active = [a & (l >= cut) for a, l in zip(active, lam)]
            logger.info("active set would empty after %d iterations; keeping the %d least "
                        "tensile nodes", it, keep)
        if not tight:
            # once the set has nearly settled, a node that changes state a second time
            # while the solves are loose is deciding on the solver's noise (a contact
            # edge where the pressure goes to zero): from here on every solve is tight.
            # Hertz at 151k wandered for 20 loose sets without repeating one exactly,
            # edge nodes flipping in turn.  Large early updates do not count: there the
            # primal-dual rule overshoots (Hertz at 491k: 1596 -> 864 -> 1255 active
            # nodes), which is no noise.  (Holding such nodes fixed and going on with
            # loose solves instead took more sets: Hertz 491k 51.7 s against 45.5 s.)
            changed = sum(int(np.count_nonzero(a != b2)) for a, b2 in zip(active, new_active))
            if changed <= _SETTLING * max(n_act, 1):
                for fl, a, b2 in zip(flips, active, new_active):
                    fl += a != b2
                if max(int(fl.max()) for fl in flips) >= 2:
                    tight, medium, tight_reason, tight_from = True, True, "flip", it + 1
                    logger.debug("a node flipped twice under loose solves; tight solves "
                                 "from now on")
        key = _set_key(new_active)
        # a set that repeats cycles; one that wanders for a third of the budget
        # without repeating exactly (edge nodes flipping in turn) is treated alike
        if (key in seen or it >= max_iter // 3) and not conservative:
            logger.info("active set %s after %d iterations; switching to conservative "
                        "updates", "cycles" if key in seen else "does not settle", it)
            conservative = True
            medium = False  # a loose solve's noise is what lets an edge node flip forever
            if not tight:
                tight, tight_reason, tight_from = True, "conservative", it + 1
            new_active = _conservative_update(active, lam, gaps, gap_tol, ltol)
        seen.add(_set_key(active))
        active = new_active
    else:
        raise ActiveSetError(
            f"active set did not settle in {max_iter} iterations (active counts "
            f"{history[-6:]}, conservative={conservative})")
    # final state and the checks every solve must pass
    gaps = [pr.gaps(u) for pr in pairs]
    fric = [pr.mu * l * pr.drag if pr.mu > 0 else np.zeros((3, pr.slave.size))
            for pr, l in zip(pairs, lam)]
    pressure = [l / pr.area for l, pr in zip(lam, pairs)]
    info = {
        "active_set_iterations": it, "linear_iterations": lin_its, "amg_builds": builds,
        "amg_refreshes": refreshes,
        "conservative": conservative, "active_counts": history,
        "tight_from": tight_from, "tight_reason": tight_reason,
        "normal_force": [float(l.sum()) for l in lam],
        "min_multiplier": min(float(l.min()) for l in lam),
        "min_gap": min(float(g.min()) for g in gaps),
        "max_complementarity": max(float(np.abs(l * g).max()) for l, g in zip(lam, gaps)),
        "gap_tol": gap_tol, "time_s": time.perf_counter() - t_start,
    }
    if info["min_gap"] < -max(gap_tol, 1e-10 * size):
        raise ActiveSetError(f"penetration {info['min_gap']:.3e} m exceeds the gap tolerance "
                             f"{gap_tol:.1e} m after convergence")
    return ContactResult(u, pressure, lam, gaps, active, fric, info)


def _check_base(solver, N: int) -> None:
    from ..solvers.amg import AMGSolver

    if not isinstance(solver, AMGSolver) or solver.A.shape != (N, N):
        shape = getattr(getattr(solver, "A", None), "shape", None)
        raise ValueError(f"solver = {type(solver).__name__} (matrix shape {shape}); need the "
                         f"AMGSolver of contact_preconditioner() for this {N}-DOF system")


def contact_preconditioner(K: sp.spmatrix, fixed: np.ndarray, coords: np.ndarray, pairs: list,
                           active: list | None = None, tol: float = 1e-9):
    """AMG hierarchy of the eliminated contact operator, for ``solve_contact(..., solver=)``.

    Built at ``active`` (default: every slave node in contact).  The operator
    does not depend on the gaps ``g0``, the loads or the friction, so in a
    wear loop (constant ``K``, changing ``g0`` and active set) one hierarchy
    serves every step.  :func:`solve_contact` never modifies it: each active
    set gets its own refreshed copy (:meth:`AMGSolver.refreshed`), so a
    solve's result depends only on its inputs and this hierarchy, never on
    earlier solves.
    """
    from ..solvers.amg import amg_solver

    K = K.tocsr()
    N = K.shape[0]
    fixed = np.unique(np.asarray(fixed, dtype=np.int64))
    if active is None:
        active = [np.ones(pr.slave.size, dtype=bool) for pr in pairs]
    else:
        active = [np.asarray(a, dtype=bool) for a in active]
        for pr, a in zip(pairs, active):
            if a.shape != pr.slave.shape:
                raise ValueError(f"{pr.name}: active has shape {a.shape}; need {pr.slave.shape}")
    is_fixed = np.zeros(N, dtype=bool)
    is_fixed[fixed] = True
    P, c, elim = _prolongation(N, pairs, active)
    A, _, _, dK = _contact_system(K, _dirichlet_base(K, is_fixed), np.zeros(N), pairs, active,
                                  P, c, elim, is_fixed, np.zeros(N), False)
    solver = amg_solver(A.tobsr(blocksize=(3, 3)), B=_reduced_modes(coords, pairs, active, fixed),
                        tol=tol, bodies=_bodies(K), fine_csr=A)
    # its operator minus the Dirichlet-masked K, valid while solver.A is this operator:
    # solve_contact forms each set's update from it instead of subtracting two full matrices
    solver.contact_delta = (solver.A, dK)
    return solver


def _stale(info, ref_rate: float) -> bool:
    """The aggregates have gone stale when a solve on a refreshed copy needs
    twice the iterations per decade of residual of the reference solve (the
    first of at least 4 iterations): a reduction factor above the square root
    of the reference's.  Iteration
    counts are not compared: the solves stop at different tolerances."""
    return bool(info.iterations > 3 and info.convergence_factor > max(ref_rate, 1e-3) ** 0.5)


# coarse levels that see each active set: all of them.  With only the first coarse level
# updated (the coarsest keeping the base's LU), a hierarchy built at the all-closed start
# set preconditioned the 154k brake's final set at 40 FGMRES iterations to 1e-9 (27 with
# every level updated, 24 for one built at that set), went stale and was rebuilt once
# per cold solve: 9.1-9.7 s against 6.1-6.7 s with every level (57k: 72 -> 48 iterations)
_REFRESH_DEPTH = None


# coarse operators written in place (AMGSolver.level_buffers) only for hierarchies whose
# coarse levels hold at least this many entries: their setup (a copy of each coarse level
# and the search of the pushed-down pattern, which covers 14-31 % of the first coarse
# level) cost 0.14-0.26 s on the 57k brake and 0.47 s on the 154k one, against full sums
# of 0.02-0.04 s and about 0.08 s per refresh; at 490k (17M coarse entries) 0.9-1.8 s
# against 0.35-0.5 s per refresh, paid back from the third or fourth set
_BUFFER_MIN_NNZ = 10_000_000
