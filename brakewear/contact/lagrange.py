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
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp

from ..errors import ActiveSetError, ContactError
from ..solvers.operators import ProductSum
from .active_set import LAGRANGE, ActiveSetDriver, ActiveSetOptions, Margins
from .basis import in_slave_basis
from .elimination import (
    _contact_system,
    _dirichlet_base,
    _prolongation,
    _reduced_modes,
    _reduced_start,
    _SetOperators,
    body_labels,
    check_disjoint,
)

logger = logging.getLogger(__name__)

__all__ = ["ContactResult", "solve_contact", "contact_preconditioner"]


@dataclass
class ContactResult:
    """Contact solution: displacements and, per pair, the nodal contact state.

    ``u`` is the nodal displacement.  On a quadratic slave face the nodal
    forces (normal and friction) are those of the transformed basis
    (:mod:`~brakewear.contact.basis`: ``int phi~_j p dA`` at node ``j``, all
    of the same sign; their sums are the totals), ``pressure`` is force over
    the pair's area (the dual pressure's nodal coefficient) and ``gap`` the
    weak gap.
    """

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
                  initial_active: list | None = None, solver=None,
                  options: ActiveSetOptions | None = None) -> ContactResult:
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
        :class:`ContactPair` list; the first is the loaded contact (pad on
        rotor), any others hold bodies in place (bracket stops).
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
        gap_tol``; if the first pair, the loaded contact, has none, its
        closest ones); a wear step passes the last one.
        A given set is taken as a good guess: every solve is then tight.
    solver
        A hierarchy from :func:`contact_preconditioner` for this ``K``,
        ``fixed`` and pair geometry, shared between solves (a wear loop).
        It is never modified: each active set gets a refreshed copy, so the
        result depends only on the inputs and this hierarchy, not on earlier
        solves.  Default: one is built at the initial active set.
    options
        The active-set policy and tuning (default :data:`~brakewear.contact.active_set.LAGRANGE`
        with ``max_iter`` and ``release_tol`` from the arguments).

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
    aggregates stay inside the bodies of ``K`` (:func:`body_labels`), so a
    hierarchy built at one set still serves the others (490k brake, final
    set: 34 FGMRES iterations refreshed from the all-closed set, 29 built
    there; 48 with aggregates across the interface).  Each new set starts
    from the last displacement (:func:`_reduced_start`).
    """
    t_start = time.perf_counter()
    K = K.tocsr()
    N = K.shape[0]
    f = np.asarray(f, dtype=float)
    fixed = np.asarray(fixed, dtype=np.int64)
    fvals = np.broadcast_to(np.asarray(fixed_values, dtype=float), fixed.shape)
    fixed, first = np.unique(fixed, return_index=True)
    fvals = fvals[first]
    # quadratic slave faces: solve in their transformed unknowns, u = T u~
    check_disjoint(pairs)
    K, f, fvals, pairs, T = in_slave_basis(K, f, fixed, fvals, pairs)
    size = float(np.linalg.norm(coords.max(axis=1) - coords.min(axis=1)))
    gap_tol = 1e-10 * size if gap_tol is None else gap_tol
    if linear not in ("amg", "direct"):
        raise ContactError(f"linear = {linear!r}; allowed: 'amg', 'direct'")
    if initial_active is None:
        active = [pr.g0 <= gap_tol for pr in pairs]
        if not active[0].any():
            # first touch of the loaded contact (the first pair): its closest nodes,
            # whatever the other pairs (a bracket stop that touches holds the pad
            # in its plane, not against the rotor)
            active[0] = pairs[0].g0 <= pairs[0].g0.min() + gap_tol
    else:
        active = [np.asarray(a, dtype=bool).copy() for a in initial_active]
    if solver is not None:
        _check_base(solver, N)
    options = replace(options or LAGRANGE, max_iter=max_iter, release_tol=release_tol)
    problem = _LagrangeSets(K, f, fixed, fvals, coords, pairs, gap_tol, tol, linear, solver)
    # A given initial set (a wear step, an outer iteration) is taken as nearly right:
    # tight solves from the start, since a loose one's noise moves edge nodes in and
    # out (measured on the 57k brake from its converged set: 48 iterations and a cycle
    # with a loose first solve, 39 and no change with a tight one)
    driver = ActiveSetDriver(options, tol, exact=linear == "direct",
                             tight=initial_active is not None,
                             hint=f" (net load {f.reshape(-1, 3).sum(axis=0)} N). A contact "
                                  "solve needs a load that presses the surfaces together.")
    flat = driver.run(problem, np.concatenate(active))
    active = problem.split(flat)
    u, lam = problem.u, problem.split(problem.lam)   # u in the transformed unknowns
    # final state and the checks every solve must pass
    gaps = [pr.gaps(u) for pr in pairs]
    fric = [pr.traction() * l if pr.frictional else np.zeros((3, pr.slave.size))
            for pr, l in zip(pairs, lam)]
    pressure = [l / pr.area for l, pr in zip(lam, pairs)]
    report = driver.report()
    report.pop("hysteresis_band")
    info = {
        **report, "linear_iterations": problem.lin_its, "amg_builds": problem.builds,
        "amg_refreshes": problem.refreshes,
        "normal_force": [float(l.sum()) for l in lam],
        "min_multiplier": min(float(l.min()) for l in lam),
        "min_gap": min(float(g.min()) for g in gaps),
        "max_complementarity": max(float(np.abs(l * g).max()) for l, g in zip(lam, gaps)),
        "gap_tol": gap_tol, "time_s": time.perf_counter() - t_start,
    }
    if info["min_gap"] < -max(gap_tol, 1e-10 * size):
        raise ActiveSetError(f"penetration {info['min_gap']:.3e} m exceeds the gap tolerance "
                             f"{gap_tol:.1e} m after convergence")
    if T is not None:
        u = T @ u
    return ContactResult(u, pressure, lam, gaps, active, fric, info)


class _LagrangeSets:
    """The Lagrange contact problem of one active set after another (a
    :class:`~brakewear.contact.active_set.SetProblem`): the eliminated
    operator of each set, its preconditioner (a hierarchy built once and
    refreshed per set) and the multipliers and gaps of its solution.

    While the set moves, the first solve stops at ``1e-2`` and later ones at
    a tenth of their warm-start residual (the driver's schedule).  Each new
    set starts from the last displacement (:func:`_reduced_start`).
    """

    def __init__(self, K, f, fixed, fvals, coords, pairs, gap_tol, tol, linear, solver):
        N = K.shape[0]
        self.K, self.f, self.fixed, self.coords, self.pairs = K, f, fixed, coords, pairs
        self.gap_tol, self.tol, self.linear = gap_tol, tol, linear
        self.offsets = np.cumsum([0] + [pr.slave.size for pr in pairs])
        self.is_fixed = np.zeros(N, dtype=bool)
        self.is_fixed[fixed] = True
        self.u_fixed = np.zeros(N)
        self.u_fixed[fixed] = fvals
        self.frictional = any(pr.frictional for pr in pairs)
        self.Kd = _dirichlet_base(K, self.is_fixed)
        self.diagK = K.diagonal()
        self.base = solver  # the hierarchy every refresh starts from; never modified here
        self.base_delta = None  # the base hierarchy's operator minus Kd, where known
        if solver is not None:
            known = getattr(solver, "contact_delta", None)  # set by contact_preconditioner
            if known is not None and known[0] is solver.A:
                self.base_delta = known[1]
        self.bodies = False  # node labels of K's bodies for the aggregates, when needed
        self.fine = None     # _SetOperators, from the second active set on
        self.coarse = None   # the base hierarchy's coarse operators in place
        self.refreshes_of_base = 0
        self.work = None     # the preconditioner of the current active set
        self.set_key = None
        self.ref_rate = None  # residual reduction per iteration of the first solve of >= 4 its
        self.x = self.u = self.lam = None
        self.lin_its = self.builds = self.refreshes = 0

    @property
    def last_residual(self) -> float | None:
        """The relative residual of the last linear solve (0 for a direct one)."""
        if self.linear == "direct":
            return 0.0 if self.x is not None else None
        return None if self.work is None else self.work.info.relative_residual

    def split(self, flat: np.ndarray) -> list:
        """A flat per-node array as one array per pair."""
        return [flat[a:b] for a, b in zip(self.offsets[:-1], self.offsets[1:])]

    def solve(self, flat: np.ndarray, tol: float, rtol0: float | None) -> None:
        active = self.split(flat)
        key = np.packbits(flat).tobytes()
        if key != self.set_key:
            self._new_set(active, key)
        if self.linear == "direct":
            from ..solvers.direct import direct_solve

            self.x = direct_solve(self.Aop, self.bd)
            its = "direct"
        else:
            self.work.tol = tol
            self.x = self.work.solve(self.bd, x0=self.x, A=self.Aop,
                                     krylov="gmres" if self.frictional else "cg", rtol0=rtol0)
            its = self.work.info.iterations
            if self.ref_rate is None and its >= 4:
                # the reference rate of this hierarchy: a solve of at least 4 iterations
                # (Hertz at 491k: a 2-iteration first solve reduced 0.09 per iteration,
                # so every later tight solve at 0.3 looked stale and was rebuilt, 9 s each)
                self.ref_rate = self.work.info.convergence_factor
            self.lin_its += its
        self.u = self.P @ self.x + self.c
        logger.debug("active-set solve: %d active, %s linear iterations", int(flat.sum()), its)

    def margins(self, flat: np.ndarray, band: float) -> Margins:
        r = (self.K @ self.u - self.f).reshape(-1, 3)
        lam = [np.where(a, np.einsum("ij,ij->j", pr.normal, r[pr.slave].T), 0.0)
               for pr, a in zip(self.pairs, self.split(flat))]
        gaps = [np.where(a, 0.0, pr.gaps(self.u)) for pr, a in zip(self.pairs, self.split(flat))]
        self.lam = np.concatenate(lam)
        ltol = np.concatenate([np.full(l.size, band * max(np.abs(l).max(initial=0.0), 1e-300))
                               for l in lam])
        return Margins(self.lam, ltol, -np.concatenate(gaps), self.gap_tol)

    def _new_set(self, active: list, key: bytes) -> None:
        """The operator and preconditioner of a new active set."""
        from ..solvers.amg import amg_solver

        N = self.K.shape[0]
        P, c, elim = _prolongation(N, self.pairs, active)
        clash = np.intersect1d(elim, self.fixed)
        if clash.size:
            raise ContactError(f"{clash.size} supported DOF(s) are the normal DOF of a contact "
                               f"node (first: DOF {clash[0]}); a node cannot be both supported "
                               "and in contact along the normal")
        if self.fine is None and self.set_key is not None and self.linear == "amg":
            # a second set in this solve: from now on each set's operator is formed
            # in place (one pass over K to set up, none per set)
            self.fine = _SetOperators(self.K, self.Kd, self.pairs, self.is_fixed)
        A, E, self.bd, dK = _contact_system(self.K, self.Kd, self.f, self.pairs, active, P, c,
                                            elim, self.is_fixed, self.u_fixed, self.frictional,
                                            self.diagK, self.fine)
        if self.x is not None:  # warm start: the last displacement in this set's unknowns
            self.x = _reduced_start(self.u, self.pairs, active)
        self.P, self.c, self.set_key = P, c, key
        if E is None:
            self.Aop = A
        elif self.linear == "direct":
            self.Aop = (A - E[0] @ E[1]).tocsr()
        else:
            self.Aop = ProductSum(A, [(-1, E[0], E[1])])
        if self.linear != "amg":
            return
        work = self.work
        if self.base is None or (self.ref_rate is not None and _stale(work.info, self.ref_rate)):
            # the first set, or the aggregates have gone stale: a hierarchy of this set
            if self.bodies is False:
                self.bodies = body_labels(self.K)
            # the set's CSR operator serves as the finest level unless it lives
            # in fine's buffer, which the next set overwrites
            self.base = amg_solver(A.tobsr(blocksize=(3, 3)),
                                   B=_reduced_modes(self.coords, self.pairs, active, self.fixed),
                                   tol=self.tol, bodies=self.bodies,
                                   fine_csr=A if self.fine is None else None)
            self.base_delta = dK
            self.builds += 1
            self.refreshes_of_base = 0
            self.work = self.base
            return
        # same aggregates, operators of this set (base left as it is): A - base.A from
        # the two small contact differences (at 490k DOFs the subtraction of the two
        # full matrices took 0.7 s per set); coarse operators in place from the second
        # refresh of a big hierarchy on (_BUFFER_MIN_NNZ)
        base = self.base
        if self.fine is not None and self.refreshes_of_base >= 1 and \
                (self.coarse is None or self.coarse.ml is not base.ml) and \
                sum(lv.A.nnz for lv in base.ml.levels[1:]) >= _BUFFER_MIN_NNZ:
            self.coarse = base.level_buffers(self.fine.Z)
        self.work = base.refreshed(A, depth=_REFRESH_DEPTH,
                                   dA=None if self.base_delta is None else dK - self.base_delta,
                                   buffers=self.coarse)
        self.refreshes += 1
        self.refreshes_of_base += 1


def _check_base(solver, N: int) -> None:
    from ..solvers.amg import AMGSolver

    if not isinstance(solver, AMGSolver) or solver.A.shape != (N, N):
        shape = getattr(getattr(solver, "A", None), "shape", None)
        raise ContactError(f"solver = {type(solver).__name__} (matrix shape {shape}); need the "
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
                raise ContactError(f"{pr.name}: active has shape {a.shape}; need {pr.slave.shape}")
    is_fixed = np.zeros(N, dtype=bool)
    is_fixed[fixed] = True
    K, _, _, pairs, _ = in_slave_basis(K, np.zeros(N), fixed, np.zeros(fixed.size), pairs)
    P, c, elim = _prolongation(N, pairs, active)
    A, _, _, dK = _contact_system(K, _dirichlet_base(K, is_fixed), np.zeros(N), pairs, active,
                                  P, c, elim, is_fixed, np.zeros(N), False)
    solver = amg_solver(A.tobsr(blocksize=(3, 3)), B=_reduced_modes(coords, pairs, active, fixed),
                        tol=tol, bodies=body_labels(K), fine_csr=A)
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
