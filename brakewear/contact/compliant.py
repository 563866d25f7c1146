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

Rigid stops without compliance (the pad's abutments in the bracket,
:mod:`~brakewear.contact.supports`) join the solve as ``supports``: their
active constraints are eliminated as in the Lagrange solve, each pair with
its own active set (:mod:`~brakewear.contact.compliant_sets`).
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp

from ..errors import ContactError
from .active_set import COMPLIANT, ActiveSetDriver, ActiveSetOptions
from .basis import in_slave_basis
from .compliant_rings import RingBlock
from .compliant_sets import CompliantSets, SupportedSets
from .pairs import ContactPair

logger = logging.getLogger(__name__)

__all__ = [
    "constraint_rows",
    "drag_loads",
    "solve_compliant_contact",
    "compliant_preconditioner",
    "CompliantResult",
]


@dataclass
class CompliantResult:
    """Contact through compliant springs: displacements and the nodal contact state."""

    u: np.ndarray
    pressure: np.ndarray   # (ns,) Pa, spring force / tributary area, 0 where open
    force: np.ndarray      # (ns,) N, normal force at each slave node
    gap: np.ndarray        # (ns,) m, g0 + C u (negative: the layer is compressed)
    active: np.ndarray     # (ns,) bool
    info: dict = field(default_factory=dict)
    # per support pair (rigid stops, ``supports=``): normal force (N), state, gap (m)
    support_force: list = field(default_factory=list)
    support_active: list = field(default_factory=list)
    support_gap: list = field(default_factory=list)


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


def drag_loads(pair: ContactPair, n_dofs: int, mu: float | None = None) -> sp.csr_matrix:
    """``G`` (n_dofs x n_slave): nodal friction load per newton of normal force, at
    the friction coefficient ``mu`` (default the pair's; a number or one per slave
    node).  A pair built without friction has no sliding direction and refuses
    ``mu > 0``."""
    ns, s = pair.slave.size, pair.slave
    mu = pair.mu if mu is None else mu
    if pair.drag is None:
        if np.any(np.asarray(mu) > 0):
            raise ContactError(f"{pair.name}: mu = {mu!r} needs a sliding direction; the pair "
                               "was built without friction (build it with mu > 0)")
        return sp.csr_matrix((n_dofs, ns))
    t = np.asarray(mu, dtype=float) * pair.drag
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
                            max_iter: int = 60, solver=None, x0: np.ndarray | None = None,
                            loose_tol: float | None = 1e-4, release_tol: float = 1e-6,
                            cycle_tol: float = 1e-3,
                            options: ActiveSetOptions | None = None,
                            supports: list | None = None,
                            rings: tuple | None = None) -> CompliantResult:
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
        With ``x0`` the start set is the one ``x0`` predicts (``g0 + C x0 < 0``);
        ``initial_active`` is then used only if that set is empty.
    solver
        A base :class:`~brakewear.solvers.AMGSolver` of ``K`` with its supports
        (:func:`compliant_preconditioner`), shared by many solves: each active
        set gets a refreshed copy, the base is never modified, so the result
        depends only on the inputs (exact resume).  Default: a hierarchy
        built for this solve.
    x0
        Initial displacement guess (e.g. extrapolated from the previous wear
        steps): the Krylov solves start from it, and so does the active set.
        The answer is the same to ``tol``.
    loose_tol
        Relative residual of the solves while the active set still moves
        (inexact active-set iteration); once a set repeats its predecessor the
        same operator is solved on to ``tol``, so the accepted set is always
        checked with a tight solution.  A set that reappears during the loose
        phase switches to tight solves from there on (inexact solves can
        cycle where exact ones do not).  ``None``: every solve tight.
    release_tol, cycle_tol
        Hysteresis of the active set, relative to the largest spring force:
        an active node is released when its spring pulls harder than
        ``release_tol`` x that force, an open node enters when its spring
        would push harder than that.  If a set repeats under tight solves
        (friction makes the operator unsymmetric, and the sign rule can then
        flip an edge node forever), the band widens to ``cycle_tol``; only a
        cycle beyond that raises.  ``info`` reports the band used and the
        largest kept tension and missed compression.

    options
        The active-set policy (default :data:`~brakewear.contact.active_set.COMPLIANT`
        with ``max_iter``, ``loose_tol``, ``release_tol`` and ``cycle_tol`` from
        the arguments).
    supports
        Rigid pairs without compliance (the pad's abutments,
        :func:`~brakewear.contact.supports.abutment_pairs`; no friction), each
        with its own active set, their active constraints eliminated
        (:mod:`~brakewear.contact.compliant_sets`); they start from their
        gaps at ``x0`` (or ``g0``).  The result's ``support_force``,
        ``support_active`` and ``support_gap`` give their state.  ``solver``
        must then be the hierarchy of :func:`compliant_preconditioner` with the
        same ``supports`` (their quadratic faces change the unknowns).
    rings
        ``(ring_gap, ring_depth)``: the rotor's ring wear of the step, implicit
        with the pad's (:mod:`~brakewear.contact.compliant_rings`).
        ``ring_gap`` (n_slave x m, sparse) is the gap each slave node sees per
        metre of each ring's depth, ``ring_depth`` (m x n_slave) each ring's
        depth per newton of end-of-step force at each slave node.  The ring
        depths are solved with the displacements (``info["ring_depth"]``, m)
        and open the gap of every slave node (``gap`` includes them).

    The active set follows the penalty rule: a node is active while its
    spring is compressed (``g0 + C u < 0``), within the hysteresis band.  A
    set that still repeats with the wide band raises
    :class:`~brakewear.errors.ActiveSetError` with its figures.
    """
    t0 = time.perf_counter()
    K = K.tocsr()
    N = K.shape[0]
    eps = np.asarray(compliance, dtype=float)
    ns = pair.slave.size
    if eps.shape != (ns,) or not np.all(np.isfinite(eps)) or np.any(eps <= 0):
        raise ContactError(f"{pair.name}: compliance must be ({ns},) finite and > 0 m/Pa; got "
                           f"shape {eps.shape}, min {np.min(eps) if eps.size else None!r}")
    if x0 is not None and np.shape(x0) != (N,):
        raise ContactError(f"x0 has shape {np.shape(x0)}; the system has {N} DOFs")
    fixed = np.unique(np.asarray(fixed, dtype=np.int64))
    supports = list(supports or [])
    _check_supports(pair, supports)
    # a quadratic slave face: solve in its transformed unknowns, u = T u~
    for pr in [pair, *supports]:
        if pr.basis is not None and x0 is not None:
            x0 = pr.basis.dof_matrix(N, inverse=True) @ np.asarray(x0, dtype=float)
    K, f, _, (pair, *supports), T = in_slave_basis(K, f, fixed, np.zeros(fixed.size),
                                                   [pair, *supports])
    kappa = pair.area / eps
    is_fixed = np.zeros(N, dtype=bool)
    is_fixed[fixed] = True
    # the constraint rows and friction loads without the supported DOFs: the
    # spring and friction terms then never touch a Dirichlet row or column,
    # and the system of an active set is K_d + (small update), K_d the
    # supported stiffness the base hierarchy was built on
    free = sp.diags((~is_fixed).astype(float))
    C = (constraint_rows(pair, N) @ free).tocsr()
    G = (free @ drag_loads(pair, N)).tocsc() if pair.frictional else None
    base = solver
    if base is not None:
        if base.A.shape != (N, N):
            raise ContactError(f"solver is a hierarchy of size {base.A.shape[0]}; the system has "
                               f"{N}")
        Kd = base.ml.levels[0].A
    else:
        base = compliant_preconditioner(K, fixed, coords, tol)   # K is already transformed
        Kd = base.ml.levels[0].A
    fd = np.where(is_fixed, 0.0, np.asarray(f, dtype=float))
    if initial_active is None:
        active = pair.g0 <= 0
        if not active.any():
            active = pair.g0 <= pair.g0.min() + 1e-12 * max(np.abs(pair.g0).max(), 1e-300)
    else:
        active = np.asarray(initial_active, dtype=bool).copy()
    x = None if x0 is None else np.asarray(x0, dtype=float).copy()
    if x is not None:
        # the set the initial guess predicts: with an extrapolated displacement
        # it already holds most of the step's change (one active-set iteration
        # saved in most wear steps)
        guess = pair.g0 + C @ x < 0
        if guess.any():
            active = guess
    options = replace(options or COMPLIANT, max_iter=max_iter, loose_tol=loose_tol,
                      release_tol=release_tol, cycle_band=cycle_tol)
    block = None if rings is None else RingBlock(rings[0], rings[1], kappa, pair.g0)
    if supports:
        problem, active = _supported(pair, kappa, C, G, Kd, fd, base, x, supports, is_fixed,
                                     coords, active, block)
    else:
        problem = CompliantSets(pair, kappa, C, G, Kd, fd, base, x, block)
    driver = ActiveSetDriver(options, tol, name=pair.name)
    active = driver.run(problem, active)
    x = problem.u
    state = {}
    if supports:
        active, a_s = problem.split(active)
        state = {"support_force": list(problem.support_force), "support_active": a_s,
                 "support_gap": list(problem.support_gap)}
    g = problem.gaps(x)
    force = np.where(active, -kappa * g, 0.0)
    fmax = max(float(force.max()), 1e-300)
    info = {**driver.report(), "linear_iterations": problem.lin,
            "linear_solves": driver.solves, "normal_force": float(force.sum()),
            "time_s": time.perf_counter() - t0,
            # the largest tension an active node keeps (within the band) and
            # the largest compression an open node misses, relative to the largest force
            "max_tension": float(max(-force.min(), 0.0) / fmax) + 0.0,
            "max_open_compression": float(max((-kappa * g)[~active].max(initial=0.0), 0.0)
                                          / fmax)}
    # the pressure: the springs' compressive force (a tension kept within the
    # band counts as no pressure: no wear, no negative Archard rate)
    if supports:
        info["support_normal_force"] = [float(v.sum()) for v in state["support_force"]]
    if block is not None:
        info["ring_depth"] = block.d.copy()
    u = x if T is None else T @ x
    return CompliantResult(u, np.maximum(force, 0.0) / pair.area, force, g, active, info,
                           **state)


def _check_supports(pair: ContactPair, supports: list) -> None:
    """Support pairs are rigid stops: no friction, their own slave nodes."""
    from .elimination import check_disjoint

    for s in supports:
        if not isinstance(s, ContactPair):
            raise ContactError(f"supports: {type(s).__name__} is not a ContactPair")
        if s.frictional:
            raise ContactError(f"{s.name}: a support pair has no friction (mu = {s.mu!r})")
    if supports:
        check_disjoint([pair, *supports])


def _supported(pair, kappa, C, G, Kd, fd, base, x, supports, is_fixed, coords, active,
               block):
    """The set problem with rigid ``supports`` and its flat start set (the compliant
    pair's, then each stop's: closed where its gap at ``x`` (or ``g0``) is shut)."""
    size = float(np.linalg.norm(coords.max(axis=1) - coords.min(axis=1)))
    problem = SupportedSets(pair, kappa, C, G, Kd, fd, base, x, supports, is_fixed,
                            1e-10 * size, block)
    start = [g <= problem.gap_tol for g in problem.support_gap]
    return problem, np.concatenate([active, *start])


def compliant_preconditioner(K: sp.spmatrix, fixed: np.ndarray, coords: np.ndarray,
                             tol: float = 1e-9, pair: ContactPair | None = None,
                             supports: list | None = None):
    """The base AMG hierarchy of ``K`` with its supports, for
    ``solve_compliant_contact(..., solver=)``: built once per stiffness (a
    wear history in gap-offset mode keeps it for every step).  With the
    ``pair`` of a quadratic slave face (or ``supports`` pairs with quadratic
    faces), the hierarchy of its transformed stiffness
    (:func:`~brakewear.contact.basis.in_slave_basis`), which is the one the
    solve uses."""
    from ..fem.boundary import apply_dirichlet
    from ..solvers.amg import amg_solver

    K = K.tocsr()
    fixed = np.unique(np.asarray(fixed, dtype=np.int64))
    pairs = ([] if pair is None else [pair]) + list(supports or [])
    if pairs:
        K = in_slave_basis(K, np.zeros(K.shape[0]), fixed, np.zeros(fixed.size), pairs)[0]
    Kd, _ = apply_dirichlet(K.tobsr(blocksize=(3, 3)), np.zeros(K.shape[0]), fixed)
    return amg_solver(Kd, coords=coords, fixed=fixed, tol=tol)
