"""Linear solvers: pyamg smoothed aggregation with rigid-body near-nullspace.

One call builds, the object solves and reports::

    solver = amg_solver(K, coords=mesh.p)      # hierarchy built once
    u = solver.solve(f)                         # CG, stops at ||r|| < tol ||f||
    solver.info.iterations, solver.info.residuals

A solve that does not reach the tolerance raises :class:`ConvergenceError`
with its figures; it never returns an unconverged vector quietly.  The
hierarchy can be reused as a preconditioner for a changed matrix (a new wear
step, an active-set update): pass ``A=`` to :meth:`AMGSolver.solve`, and call
:meth:`AMGSolver.rebuild` when the iteration count says it has gone stale.
"""
from __future__ import annotations

import copy
import logging
import time
import warnings
from contextlib import nullcontext
from dataclasses import dataclass, field

import numpy as np
import pyamg
import scipy.sparse as sp
from pyamg.relaxation.smoothing import change_smoothers

from ..errors import ConvergenceError, SolverSettingsError
from .cycle import _BackwardSweeps, _one_backward_sweep, _v_cycle
from .krylov import _fgmres
from .patched import LevelBuffers, PatchedMatrix
from .patches import (
    _batched_block_pinv,
    _single_pass_spectral_radius,
    _split_strength,
    _vectorised_bsr_dedupe,
)
from .threads import _single_threaded_blas

logger = logging.getLogger(__name__)

__all__ = ["SolveInfo", "rigid_body_modes", "AMGSolver", "amg_solver", "SA_OPTIONS", "SMOOTHERS"]


@dataclass
class SolveInfo:
    """Figures of the last solve."""

    iterations: int = 0
    residuals: list = field(default_factory=list)
    converged: bool = False
    setup_s: float = 0.0
    solve_s: float = 0.0

    @property
    def relative_residual(self) -> float:
        if not self.residuals:
            return float("nan")
        return self.residuals[-1] / self.residuals[0] if self.residuals[0] > 0 else 0.0

    @property
    def convergence_factor(self) -> float:
        """Mean residual reduction per iteration."""
        if self.iterations == 0:
            return 0.0
        return self.relative_residual ** (1.0 / self.iterations)


def rigid_body_modes(coords: np.ndarray, fixed: np.ndarray | None = None) -> np.ndarray:
    """The six rigid-body modes of a 3D body as columns (3 N, 6), DOF = 3 node + i.

    ``coords`` (3, N) are the coordinates of the scalar DOFs (vertices, and
    edge midpoints for P2).  Rows of ``fixed`` DOFs are zeroed, as they are
    in a system with eliminated Dirichlet conditions.
    """
    x = np.asarray(coords, dtype=float)
    x = x - x.mean(axis=1, keepdims=True)
    scale = np.abs(x).max() or 1.0
    x = x / scale  # modes of similar magnitude keep the tentative prolongator well conditioned
    n = x.shape[1]
    B = np.zeros((n, 3, 6))
    B[:, 0, 0] = B[:, 1, 1] = B[:, 2, 2] = 1.0
    # rotations about x, y, z: omega x r
    B[:, 1, 3], B[:, 2, 3] = -x[2], x[1]
    B[:, 0, 4], B[:, 2, 4] = x[2], -x[0]
    B[:, 0, 5], B[:, 1, 5] = -x[1], x[0]
    B = B.reshape(3 * n, 6)
    if fixed is not None:
        B[np.asarray(fixed)] = 0.0
    return B


#: pyamg ``smoothed_aggregation_solver`` options of every hierarchy.  Node
#: aggregation on the 3x3-block matrix with a small strength threshold (0.02
#: or 0.1 instead of 0.05 cost more in all: docs/amg_settings.md).
#: Energy-minimising prolongation (2 CG steps) instead of one
#: Jacobi step: on the brake systems sparser coarse operators and 25-30 % fewer
#: iterations for about the same setup (on the structured rotor ring of the
#: elasticity benchmark it saves no iterations and its setup costs ~40 % more;
#: pass ``smooth=("jacobi", ...)`` there).  ``max_coarse`` counts block rows (nodes on the finest
#: level, aggregates of 6 rigid-body modes below), so 300 keeps the coarsest
#: level at most ~1800 rows: with 1000 the 5 mm brake stopped at 2 levels
#: with a 2600-row, 10 %-dense coarse matrix to factorise.
SA_OPTIONS = dict(
    strength=("symmetric", {"theta": 0.05}),
    smooth=("energy", {"degree": 1, "maxiter": 2}),
    improve_candidates=None,
    max_coarse=300,
    coarse_solver="splu",  # pyamg's default dense pinv costs O(n^3) on a big coarse level
)


#: (presmoother, postsmoother): point Gauss-Seidel, forward before and backward
#: after, a symmetric V-cycle, so CG stays valid; 2-3x faster than pyamg's
#: defaults with block Gauss-Seidel.  The backward sweep runs as a forward one
#: over a reversed copy of the level (:class:`_BackwardSweeps`).
SMOOTHERS = (("gauss_seidel", {"sweep": "forward"}),
             ("gauss_seidel", {"sweep": "backward"}))


class AMGSolver:
    """Smoothed-aggregation AMG hierarchy + preconditioned CG.

    Parameters
    ----------
    A
        SPD matrix (CSR or 3x3 BSR; BSR aggregates whole nodes, which suits
        elasticity best).
    B
        Near-nullspace (n, k); for elasticity :func:`rigid_body_modes`.
    tol
        Relative residual ``||b - A x|| / ||b||`` to reach.
    maxiter
        CG iterations before :class:`ConvergenceError`.
    smoothers
        (presmoother, postsmoother) in pyamg's ``change_smoothers`` form;
        default :data:`SMOOTHERS`.
    fine_csr
        ``A`` itself in CSR, when the caller has it (``A`` being its BSR
        copy): the finest level's smoother then runs on it instead of a
        fresh conversion (0.3-0.4 s at 490k DOFs).  Dropped by a rebuild
        for another matrix.
    bodies
        Optional label per node (3x3 block row; per row for CSR): aggregates
        never join nodes of two labels (:func:`_split_strength`).  For a
        contact operator whose active set will change: the bodies of ``K``.
    **sa_options
        Override :data:`SA_OPTIONS` (pyamg ``smoothed_aggregation_solver``
        keywords).
    """

    def __init__(self, A: sp.spmatrix, B: np.ndarray | None = None, tol: float = 1e-8,
                 maxiter: int = 500, smoothers: tuple | None = None,
                 bodies: np.ndarray | None = None, fine_csr: sp.csr_matrix | None = None,
                 **sa_options):
        if A.shape[0] != A.shape[1]:
            raise SolverSettingsError(f"AMGSolver: matrix must be square, got shape {A.shape}")
        if fine_csr is not None and (fine_csr.format != "csr" or fine_csr.shape != A.shape):
            raise SolverSettingsError(f"fine_csr must be A in CSR: got {fine_csr.format} of "
                                      f"shape {fine_csr.shape} for A of shape {A.shape}")
        self.A = A
        self._fine_csr = fine_csr
        self.B = B
        self.bodies = None if bodies is None else np.asarray(bodies)
        if self.bodies is not None:
            rows = A.shape[0] // (A.blocksize[0] if sp.issparse(A) and A.format == "bsr" else 1)
            if self.bodies.shape != (rows,):
                raise SolverSettingsError(f"bodies has shape {self.bodies.shape}; need one "
                                          f"label per node: ({rows},)")
        self.tol = float(tol)
        self.maxiter = int(maxiter)
        self.options = copy.deepcopy(SA_OPTIONS)
        self.smoothers = copy.deepcopy(SMOOTHERS if smoothers is None else smoothers)
        self.options.update(sa_options)
        if self.bodies is not None:
            kinds = (self.options.get("strength", "symmetric"),
                     self.options.get("aggregate", "standard"))
            kinds = tuple(k[0] if isinstance(k, tuple) else k for k in kinds)
            if kinds != ("symmetric", "standard"):
                raise SolverSettingsError(f"bodies needs strength 'symmetric' and aggregate "
                                          f"'standard' (pyamg's defaults); got {kinds}")
        self.info = SolveInfo()
        self.builds = 0
        self._krylov_work = {}  # FGMRES basis arrays, shared with refreshed copies
        self.rebuild(A)

    def rebuild(self, A: sp.spmatrix | None = None) -> None:
        """(Re)build the hierarchy, for ``A`` or the current matrix."""
        if A is not None and A is not self.A:
            self.A = A
            self._fine_csr = None
        t0 = time.perf_counter()
        # pyamg's spectral-radius estimate starts from np.random: a fixed seed
        # makes every hierarchy, and so every solve, exactly repeatable (a
        # resumed wear history must repeat the uninterrupted one)
        rng_state = np.random.get_state()  # noqa: NPY002  (pyamg draws from it)
        np.random.seed(20091)  # noqa: NPY002
        try:
            with _single_pass_spectral_radius(), _single_threaded_blas(), _batched_block_pinv(), \
                    _vectorised_bsr_dedupe(), \
                    (_split_strength(self.bodies) if self.bodies is not None else nullcontext()):
                self.ml = pyamg.smoothed_aggregation_solver(self.A, B=self.B, presmoother=None,
                                                            postsmoother=None, **self.options)
        finally:
            np.random.set_state(rng_state)  # noqa: NPY002
        for i, level in enumerate(self.ml.levels):  # point smoothers: faster on CSR than BSR
            level.A = self._fine_csr if i == 0 and self._fine_csr is not None else level.A.tocsr()
            if hasattr(level, "P"):  # CSR transfers: refreshed() restricts with them
                level.P, level.R = level.P.tocsr(), level.R.tocsr()
        change_smoothers(self.ml, *self.smoothers)
        self.M = _v_cycle(self.ml, _BackwardSweeps(len(self.ml.levels))
                          if _one_backward_sweep(self.smoothers[1]) else None)
        self.builds += 1
        self.setup_s = time.perf_counter() - t0
        logger.debug("AMG hierarchy: %d levels, operator complexity %.2f, %.2f s",
                     len(self.ml.levels), self.ml.operator_complexity(), self.setup_s)

    def level_buffers(self, Z: sp.spmatrix) -> LevelBuffers:
        """Buffers for :meth:`refreshed` to write the coarse operators in place.

        ``Z``: a structural superset of every fine-level difference ``dA`` to
        come (a contact solve: the difference with every slave node active).
        It is pushed down the levels (``|P|^T Z |P|``) and each coarse
        operator gets a :class:`PatchedMatrix`.  A refreshed copy made with
        them shares their buffers: only the latest one may be used.
        """
        Z = sp.csr_matrix(Z)
        Z = (Z + Z.T).tocsr()  # symmetric: its nonzero rows are its nonzero columns
        out = []
        for lo in self.ml.levels[:-1]:
            # |P|^T Z |P| over Z's rows only (a full abs(P) alone took 0.5 s at 490k)
            rows = np.flatnonzero(np.diff(Z.indptr))
            Pa = abs(lo.P.tocsr()[rows])
            Zr = abs(Z[rows][:, rows])
            Z = (Pa.T @ (Zr @ Pa)).tocsr()
            Z.eliminate_zeros()
            out.append(PatchedMatrix(self.ml.levels[len(out) + 1].A, Z) if Z.nnz else None)
        return LevelBuffers(self.ml, out)

    def refreshed(self, A: sp.spmatrix, depth: int | None = None,
                  dA: sp.spmatrix | None = None,
                  buffers: LevelBuffers | None = None) -> AMGSolver:
        """A new solver for ``A`` on this hierarchy's aggregates; ``self`` is not changed.

        Keeps the aggregates and prolongators and updates the level operators
        by ``R dA P`` (the coarse factorisation redone): much cheaper than
        :meth:`rebuild` and nearly as good when ``A`` differs from the
        current operator locally (a new contact active set).  The result is
        a separate object whose
        hierarchy depends only on this one and on ``A``, never on earlier
        refreshes: the base can be shared by many solves (a wear history)
        and every solve stays exactly repeatable.  ``depth``: update only
        that many levels below the finest (0: the smoother sees ``A``, the
        coarse corrections keep this hierarchy's operators -- still a
        symmetric positive definite preconditioner); default all.  ``dA``:
        ``A`` minus this hierarchy's finest operator, when the caller has it
        (a small update): saves the subtraction of two full matrices.
        ``buffers``: from :meth:`level_buffers` of this hierarchy; the coarse
        operators are then written in place (no full sum per level), and
        the copy made before with the same buffers is no longer valid.
        """
        t0 = time.perf_counter()
        base = self.ml.levels
        if buffers is not None and buffers.ml is not self.ml:
            raise SolverSettingsError("buffers belong to another hierarchy (level_buffers() of "
                                      "this one)")
        A = A.tocsr()
        if dA is None:
            dA = (A - base[0].A).tocsr()
        else:
            if dA.shape != A.shape:
                raise SolverSettingsError(f"dA has shape {dA.shape}; A has {A.shape}")
            dA = sp.csr_matrix(dA)
        dA.eliminate_zeros()
        levels = []
        for i, lo in enumerate(base):
            lv = pyamg.multilevel.MultilevelSolver.Level()
            if i == 0:
                lv.A = A
            elif dA.nnz and (depth is None or i <= depth):
                # R dA P with R = P^T, as (P^T (dA P)^T)^T = ((dA P)^T P)^T: the product
                # then runs over the few nonzero rows of dA only, not over all of R
                Pl = base[i - 1].P
                dA = ((dA @ Pl).T.tocsr() @ Pl).T.tocsr()
                dA.eliminate_zeros()
                if not dA.nnz:
                    lv.A = lo.A
                elif buffers is not None and buffers.levels[i - 1] is not None:
                    lv.A = buffers.levels[i - 1].matrix(dA)
                else:
                    lv.A = (lo.A + dA).tocsr()
            else:
                lv.A = lo.A
                dA = dA[:0]  # the levels below keep theirs too
            if hasattr(lo, "P"):
                lv.P, lv.R = lo.P, lo.R
            levels.append(lv)
        new = copy.copy(self)
        new.A = A
        new.ml = pyamg.multilevel.MultilevelSolver(
            levels, coarse_solver=self.options["coarse_solver"]
        )
        if levels[-1].A is base[-1].A:  # unchanged coarsest operator: share its factorisation
            new.ml.coarse_solver = self.ml.coarse_solver
        change_smoothers(new.ml, *self.smoothers)
        new.M = _v_cycle(new.ml, None if self.M.backward is None else
                         _BackwardSweeps(len(levels), inherit=self.M.backward))
        new.info = SolveInfo()
        new.refreshes = getattr(self, "refreshes", 0) + 1
        logger.debug("AMG refreshed copy: %.2f s", time.perf_counter() - t0)
        return new

    def solve(self, b: np.ndarray, x0: np.ndarray | None = None,
              A: sp.spmatrix | None = None, krylov: str = "cg",
              rtol0: float | None = None, M=None) -> np.ndarray:
        """Solve ``A x = b`` by CG preconditioned with the hierarchy.

        ``A`` (optional) is a changed matrix to solve with the existing
        hierarchy as preconditioner; ``krylov="gmres"`` (flexible GMRES) for
        an unsymmetric one.  ``rtol0``: stop as well once the residual is
        ``rtol0`` times that of ``x0`` (an inexact solve; the tolerance
        reached is then ``max(tol, rtol0 ||r0|| / ||b||)``).  Raises
        :class:`ConvergenceError` if the tolerance is not reached in
        ``maxiter`` iterations.
        """
        op = self.A if A is None else A
        b = np.asarray(b, dtype=float)
        res: list = []
        t0 = time.perf_counter()
        if not np.any(b):
            x = np.zeros_like(b)
            self.info = SolveInfo(0, [0.0], True, self.setup_s, 0.0)
            return x
        normb = float(np.linalg.norm(b))
        tol = self.tol
        if M is not None and krylov != "gmres":
            raise SolverSettingsError("a preconditioner M other than the hierarchy's needs "
                                      "krylov='gmres'")
        with warnings.catch_warnings(record=True) as caught, _single_threaded_blas():
            warnings.simplefilter("always")
            if krylov == "cg":
                if rtol0 is not None:
                    r0 = np.linalg.norm(b - op @ x0) if x0 is not None else normb
                    tol = max(tol, rtol0 * r0 / normb)
                x, flag = pyamg.krylov.cg(op, b, x0=x0, tol=tol, maxiter=self.maxiter,
                                          M=self.M, residuals=res)
                # the true residual decides, not the recurrence
                rel = np.linalg.norm(b - op @ x) / normb
            elif krylov == "gmres":  # unsymmetric operators; right preconditioning
                # restart 30: the solves here take 5-30 iterations; the last residual
                # it reports is the true one, computed after the update
                x, res, tol = _fgmres(op, b, x0, self.M if M is None else M, tol, 30,
                                      self.maxiter, self._krylov_work, rtol0)
                rel = res[-1] / normb
            else:
                raise SolverSettingsError(f"krylov = {krylov!r}; allowed: 'cg', 'gmres'")
        notes = " ".join(str(w.message).strip() for w in caught)
        dt = time.perf_counter() - t0
        self.info = SolveInfo(len(res) - 1, res, bool(rel <= 10 * tol), self.setup_s, dt)
        if not np.all(np.isfinite(x)) or not rel <= 10 * tol:
            raise ConvergenceError(
                f"AMG-CG did not converge: relative residual {rel:.3e} after {len(res) - 1} "
                f"iterations (tol {tol:.1e}, maxiter {self.maxiter}, "
                f"mean reduction per iteration {self.info.convergence_factor:.3f}). "
                + (f"pyamg: {notes} " if notes else "")
                + "Is the body constrained against rigid motion? Is the matrix SPD?",
                self.info, figures={"iterations": self.info.iterations, "relative_residual": rel,
                                    "tol": tol, "maxiter": self.maxiter},
            )
        logger.debug("AMG-CG: %d iterations, relative residual %.2e, %.2f s",
                     self.info.iterations, rel, dt)
        return x


def amg_solver(A: sp.spmatrix, B: np.ndarray | None = None, coords: np.ndarray | None = None,
               fixed: np.ndarray | None = None, **kwargs) -> AMGSolver:
    """Build an :class:`AMGSolver`; with ``coords`` the rigid-body modes are the near-nullspace."""
    if B is None and coords is not None:
        B = rigid_body_modes(coords, fixed)
    return AMGSolver(A, B=B, **kwargs)
