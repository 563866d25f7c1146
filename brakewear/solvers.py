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
import ctypes
import logging
import os
import time
import warnings
import weakref
from dataclasses import dataclass, field

from contextlib import contextmanager, nullcontext
from functools import partial

import numpy as np
import pyamg
import pyamg.aggregation.smooth as _pyamg_smooth
import pyamg.util.linalg as _pyamg_linalg
from pyamg import amg_core
from pyamg.relaxation.smoothing import change_smoothers
import scipy.sparse as sp
import scipy.sparse.linalg as spla

logger = logging.getLogger(__name__)

__all__ = [
    "ConvergenceError",
    "SolveInfo",
    "rigid_body_modes",
    "AMGSolver",
    "PatchedMatrix",
    "amg_solver",
    "direct_solve",
    "DIRECT_MAX_DOFS",
    "SA_OPTIONS",
    "SMOOTHERS",
]

#: Largest system :func:`direct_solve` accepts unless told otherwise: beyond
#: this a 3D sparse factorisation costs minutes and gigabytes.
DIRECT_MAX_DOFS = 150_000


class ConvergenceError(RuntimeError):
    """An iterative solve stopped without reaching its tolerance."""

    def __init__(self, message: str, info: "SolveInfo"):
        super().__init__(message)
        self.info = info


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


@contextmanager
def _single_pass_spectral_radius():
    """Let pyamg's Jacobi prolongation smoother estimate rho(D^-1 A) in one Arnoldi pass.

    pyamg restarts its Arnoldi estimate up to five times (15 products each)
    until the Ritz value settles to 1 %; on elasticity it always takes the
    restart, and the estimates cost about a third of the whole setup.  One
    pass of 15 steps changes the iteration count by at most one (measured on
    the 1M-DOF rotor ring, docs/performance.md).  pyamg offers no option for
    this, so its module-level function is swapped for the time of the call.
    """
    saved = _pyamg_smooth.approximate_spectral_radius
    _pyamg_smooth.approximate_spectral_radius = partial(saved, maxiter=15, restart=0)
    try:
        yield
    finally:
        _pyamg_smooth.approximate_spectral_radius = saved


#: pyamg ``smoothed_aggregation_solver`` options of every hierarchy.  Node
#: aggregation on the 3x3-block matrix with a small strength threshold (0.02
#: or 0.1 instead of 0.05 cost more in all: docs/performance.md, "AMG
#: settings").  Energy-minimising prolongation (2 CG steps) instead of one
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


def _block_pinv(a: np.ndarray, tol: float | None = None, _loop=_pyamg_linalg.pinv_array) -> None:
    """pyamg's ``pinv_array`` (in-place pseudo-inverse of each block ``a[k]``), batched.

    pyamg inverts the (n, m, m) blocks one LAPACK call at a time from Python:
    with energy-minimising prolongation that is the fine level's n ``B^T B``
    blocks (6 x 6), a quarter of the setup on the 300k rotor ring.  The
    blocks are inverted in one batched ``numpy.linalg.inv``; exactly singular
    ones and those whose ``a inv(a)`` is not within 1e-9 of the identity
    (badly conditioned, where the pseudo-inverse's cut-off may act) go
    through pyamg's own routine, so the result is pyamg's to rounding.
    """
    if a.ndim != 3 or a.shape[1] != a.shape[2] or a.shape[1] == 1 or not np.isrealobj(a):
        _loop(a, tol)
        return
    # exactly singular blocks (a zero pivot in LU, so det == 0; a supported node's
    # zero rows) are left to pyamg's routine
    finite = np.all(np.isfinite(a), axis=(1, 2))
    with np.errstate(all="ignore"):
        idx = np.flatnonzero(finite)[np.linalg.det(a[finite]) != 0]
    try:
        with np.errstate(all="ignore"):
            inv = np.linalg.inv(a[idx])
            ok = np.abs(a[idx] @ inv - np.eye(a.shape[1])).max(axis=(1, 2)) <= 1e-9
    except np.linalg.LinAlgError:  # cannot happen after the det test; stay safe
        _loop(a, tol)
        return
    rest = np.setdiff1d(np.arange(a.shape[0]), idx[ok], assume_unique=True)
    a[idx[ok]] = inv[ok]
    if rest.size:
        sub = a[rest]
        _loop(sub, tol)
        a[rest] = sub


@contextmanager
def _batched_block_pinv():
    """Let pyamg's setup invert its small blocks with :func:`_block_pinv`."""
    saved = _pyamg_linalg.pinv_array
    _pyamg_linalg.pinv_array = _block_pinv
    try:
        yield
    finally:
        _pyamg_linalg.pinv_array = saved


#: the scipy class whose ``sum_duplicates`` BSR matrices use
_BSR_BASE = next(c for c in sp.bsr_array.__mro__ if "sum_duplicates" in c.__dict__)


def _bsr_sum_duplicates(self) -> None:
    """scipy's ``sum_duplicates`` of a BSR matrix, vectorised.

    scipy sorts the block indices in C and then merges duplicate blocks in a
    Python loop over every block row and block, even when there are none.
    pyamg's energy-minimising prolongation takes ``abs(A)`` of each level's
    BSR matrix, which runs it whenever the matrix is not flagged canonical
    (a ``tobsr`` or a product): 3.4 s of a 10 s setup at 490k DOFs.  Same
    result: blocks sorted by column, duplicates summed in order.
    """
    if self.has_canonical_format:
        return
    self.sort_indices()
    ptr, ind = self.indptr, self.indices
    n_row = ptr.size - 1
    if ind.size:
        rows = np.repeat(np.arange(n_row, dtype=ptr.dtype), np.diff(ptr))
        first = np.ones(ind.size, dtype=bool)
        first[1:] = (rows[1:] != rows[:-1]) | (ind[1:] != ind[:-1])
        if not first.all():
            starts = np.flatnonzero(first)
            self.data = np.add.reduceat(self.data, starts, axis=0)
            self.indices = ind[starts]
            counts = np.bincount(rows[starts], minlength=n_row)
            self.indptr = np.concatenate([[0], np.cumsum(counts)]).astype(ptr.dtype)
    self.has_canonical_format = True


@contextmanager
def _vectorised_bsr_dedupe():
    """Let BSR matrices merge duplicates with :func:`_bsr_sum_duplicates` during a setup."""
    saved = _BSR_BASE.sum_duplicates
    _BSR_BASE.sum_duplicates = _bsr_sum_duplicates
    try:
        yield
    finally:
        _BSR_BASE.sum_duplicates = saved


@contextmanager
def _split_strength(bodies: np.ndarray):
    """Keep the aggregates of a setup inside bodies: pyamg's strength graph loses
    every coupling between two nodes of different ``bodies`` labels.

    ``bodies`` labels the rows of the strength graph of the finest level (the
    nodes of a 3x3 BSR matrix); the labels follow the aggregates down (every
    aggregate lies in one body, since aggregation only walks the graph), so
    the coarse levels are split the same way.  Two bodies still act on each
    other through the Galerkin operators ``R A P``: what is lost is only
    aggregates (and smoothed prolongators) straddling an interface.  For
    contact that is the point: a hierarchy built with the pad tied to the
    rotor, then refreshed for a set where part of the pad face has lifted off,
    has no coarse function that ties the two sides of an open gap (490k
    brake, final set: 48 FGMRES iterations to 1e-9 on the refreshed all-closed
    hierarchy, 34 with split aggregates, 29 on one built at that set).
    """
    import pyamg.aggregation.aggregation as agg

    strength, aggregate = agg.symmetric_strength_of_connection, agg.standard_aggregation
    labels = [np.asarray(bodies)]

    def split(A, **kwargs):
        C = strength(A, **kwargs).tocsr()
        lab = labels[0]
        if lab.shape != (C.shape[0],):
            raise ValueError(f"bodies has {lab.size} labels; the strength graph of this level "
                             f"has {C.shape[0]} nodes (one label per 3x3 block row)")
        row = np.repeat(np.arange(C.shape[0]), np.diff(C.indptr))
        C = sp.csr_matrix((np.where(lab[row] == lab[C.indices], C.data, 0.0), C.indices,
                           C.indptr), shape=C.shape)
        C.eliminate_zeros()
        return C

    def aggregate_split(C, **kwargs):
        AggOp, centres = aggregate(C, **kwargs)
        Ao = sp.coo_matrix(AggOp)
        lab = np.zeros(AggOp.shape[1], dtype=labels[0].dtype)
        lab[Ao.col] = labels[0][Ao.row]
        if not np.array_equal(lab[Ao.col], labels[0][Ao.row]):  # cannot happen: see above
            raise RuntimeError("an aggregate spans two bodies")
        labels[0] = lab
        return AggOp, centres

    agg.symmetric_strength_of_connection, agg.standard_aggregation = split, aggregate_split
    try:
        yield
    finally:
        agg.symmetric_strength_of_connection, agg.standard_aggregation = strength, aggregate


_BLAS_CONTROLS: list | None = None


def _openblas_controls() -> list:
    """(get, set) thread-count functions of every OpenBLAS loaded in this process.

    NumPy and SciPy each bundle their own OpenBLAS; both are found through
    ``/proc/self/maps`` (Linux).  Elsewhere, or if the symbols are missing,
    the list is empty and nothing is changed.
    """
    global _BLAS_CONTROLS
    if _BLAS_CONTROLS is None:
        _BLAS_CONTROLS = []
        try:
            with open("/proc/self/maps") as fh:
                paths = sorted({ln.split()[-1] for ln in fh
                                if "openblas" in os.path.basename(ln.split()[-1]).lower()
                                and ".so" in ln})
        except OSError:
            paths = []
        for path in paths:
            try:
                lib = ctypes.CDLL(path)
            except OSError:
                continue
            for prefix in ("scipy_openblas", "openblas"):
                for suffix in ("64_", ""):
                    get = getattr(lib, f"{prefix}_get_num_threads{suffix}", None)
                    put = getattr(lib, f"{prefix}_set_num_threads{suffix}", None)
                    if get is not None and put is not None:
                        get.restype, put.argtypes = ctypes.c_int, [ctypes.c_int]
                        _BLAS_CONTROLS.append((get, put))
                        break
                else:
                    continue
                break
    return _BLAS_CONTROLS


@contextmanager
def _single_threaded_blas():
    """Run the block with one OpenBLAS thread, then restore the counts.

    The AMG setup and the Krylov solves make thousands of level-1 BLAS calls
    (dot products, norms) on vectors of 10^4-10^5 entries, and SuperLU's
    coarse solves level-2 ones; the sparse kernels themselves are single
    threaded.  With OpenBLAS's default threads each such call costs
    milliseconds of spinning and waking on a loaded machine: measured on the
    105k brake with 2 threads, twice the CPU time of the solve with 1
    (docs/performance.md, "AMG settings").
    """
    saved = [(get(), put) for get, put in _openblas_controls()]
    for _, put in saved:
        put(1)
    try:
        yield
    finally:
        for n, put in saved:
            put(n)


#: backward sweeps by pyamg's kernel on a level matrix before it gets a reversed copy
_COPY_AFTER = 3


def _reversed_csr(A: sp.csr_matrix, spare: tuple | None = None) -> tuple:
    """``J A J`` (``J`` the exchange matrix: rows and columns in reverse order) as CSR arrays.

    Row ``k`` of the result is row ``n-1-k`` of ``A`` with its entries in
    reverse order, so the whole value array is ``A.data`` reversed.
    Returns ``(indptr, indices, data)``, written into the leading parts of
    the ``spare`` arrays where they are large enough (no fresh memory).
    """
    n, nnz = A.shape[0], int(A.indptr[-1])

    def take(buf, size, dtype):
        return buf[:size] if buf is not None and buf.dtype == dtype and buf.size >= size \
            else np.empty(size, dtype=dtype)

    ip, ind, dat = spare if spare is not None else (None, None, None)
    ip = take(ip, n + 1, A.indptr.dtype)
    ind = take(ind, nnz, A.indices.dtype)
    dat = take(dat, nnz, A.data.dtype)
    np.subtract(A.indptr[-1], A.indptr[::-1], out=ip)
    np.subtract(A.indices.dtype.type(n - 1), A.indices[:nnz][::-1], out=ind)
    np.copyto(dat, A.data[:nnz][::-1])
    return ip, ind, dat


def _release_copies(pool: dict, owned: dict) -> None:
    """Hand the reversed copies of a dead :class:`_BackwardSweeps` to its pool."""
    for level, arrays in owned.items():
        old = pool.get(level)
        if old is None or arrays[2].size >= old[2].size:
            pool[level] = arrays


class _BackwardSweeps:
    """Backward Gauss-Seidel sweeps as forward sweeps over reversed copies of the levels.

    A backward sweep over ``A`` is a forward sweep over ``J A J`` applied to
    the reversed vectors (:func:`_reversed_csr`): the same updates in the
    same order, the sums within a row taken in reverse order (equal to
    rounding).  pyamg's backward kernel walks memory downwards and runs
    2.2x slower than its forward one on these matrices (docs/performance.md).
    A copy costs about three forward sweeps, and much more where fresh
    memory is slow (on the development VM the same 8M-entry copy took 13 to
    300 ms), so:

    * a level matrix is swept by pyamg's backward kernel for its first
      :data:`_COPY_AFTER` sweeps and copied at the next: short solves (a
      loose contact set of 2-4 iterations) never pay for a copy;
    * the copies of a refreshed hierarchy go back to a pool shared with its
      base when it is dropped, and the next refreshed copy writes its own
      into them: a contact solve refreshes its levels at every active set.

    A copy is kept while the level matrix is the same object.  ``inherit``:
    the sweeps of the hierarchy a refreshed copy came from, whose copies
    serve the levels the two share and whose pool it uses.
    """

    def __init__(self, n_levels: int, inherit: "_BackwardSweeps | None" = None):
        self.copies: list = [None] * n_levels  # (A, indptr, indices, data) per level
        self.uses: list = [(None, 0)] * n_levels  # (A, backward sweeps so far) per level
        self.inherit = inherit
        self.pool = {} if inherit is None else inherit.pool
        self._owned: dict = {}  # level -> arrays this object made (to the pool when it dies)
        weakref.finalize(self, _release_copies, self.pool, self._owned)

    def __call__(self, i: int, A: sp.csr_matrix, x: np.ndarray, b: np.ndarray) -> None:
        c = self.copies[i]
        if c is None or c[0] is not A:
            old = self.inherit.copies[i] if self.inherit is not None and \
                i < len(self.inherit.copies) else None
            if old is not None and old[0] is A:
                c = self.copies[i] = old
            else:
                seen, count = self.uses[i]
                count = count + 1 if seen is A else 1
                if count <= _COPY_AFTER:
                    self.uses[i] = (A, count)
                    amg_core.gauss_seidel(A.indptr, A.indices, A.data, x, b,
                                          A.shape[0] - 1, -1, -1)
                    return
                # only the pool's arrays are written into: this object's own may be
                # lent to a refreshed copy (inherit) that still smooths with them
                spare = self.pool.pop(i, None)
                arrays = _reversed_csr(A, spare)
                self._owned[i] = arrays if spare is None else \
                    tuple(s if s.size >= a.size else a for s, a in zip(spare, arrays))
                c = self.copies[i] = (A,) + arrays
                self.uses[i] = (None, 0)
        xr = x[::-1].copy()
        amg_core.gauss_seidel(c[1], c[2], c[3], xr, b[::-1].copy(), 0, A.shape[0], 1)
        x[:] = xr[::-1]


def _one_backward_sweep(spec) -> bool:
    """Whether a pyamg smoother spec is one plain backward Gauss-Seidel sweep."""
    name, opts = (spec, {}) if isinstance(spec, str) else spec
    return (name == "gauss_seidel" and opts.get("sweep") == "backward"
            and opts.get("iterations", 1) == 1 and set(opts) <= {"sweep", "iterations"})


def _v_cycle(ml, backward: _BackwardSweeps | None = None) -> spla.LinearOperator:
    """One V-cycle of ``ml`` from a zero guess, as a linear operator (the preconditioner).

    The same cycle as ``ml.aspreconditioner("V")`` -- pre-smoothing,
    restricted residual, coarse correction, post-smoothing on every level,
    the coarsest solved by ``ml.coarse_solver`` -- without what pyamg's
    ``solve(maxiter=1)`` adds around it: two residual norms on the finest
    level (two extra fine-level products per application, about 15 % of a
    V-cycle here) that a preconditioner never uses.  ``backward``: the
    post-smoother is one backward Gauss-Seidel sweep, done by these
    (:class:`_BackwardSweeps`) instead of ``level.postsmoother``; the
    operator keeps them as its ``backward`` attribute.
    """
    vc = _VCycle(ml, backward)
    op = spla.LinearOperator(ml.levels[0].A.shape, vc, dtype=ml.levels[0].A.dtype)
    op.backward = backward
    return op


class _VCycle:
    """The V-cycle of :func:`_v_cycle` as a callable (a method recursing through
    ``self``: a nested function calling itself is a reference cycle, which would
    leave a dropped hierarchy to the garbage collector instead of freeing it at once)."""

    def __init__(self, ml, backward: _BackwardSweeps | None):
        self.ml, self.backward = ml, backward
        self.last = len(ml.levels) - 1

    def __call__(self, b: np.ndarray) -> np.ndarray:
        return self.cycle(0, np.ravel(np.asarray(b, dtype=float)))

    def cycle(self, i: int, b: np.ndarray) -> np.ndarray:
        ml = self.ml
        if i == self.last:
            return np.asarray(ml.coarse_solver(ml.levels[i].A, b), dtype=b.dtype).reshape(b.shape)
        lv = ml.levels[i]
        x = np.zeros_like(b)
        lv.presmoother(lv.A, x, b)
        x += lv.P @ self.cycle(i + 1, lv.R @ (b - lv.A @ x))
        if self.backward is None:
            lv.postsmoother(lv.A, x, b)
        else:
            self.backward(i, lv.A, x, b)
        return x


def _fgmres(A, b: np.ndarray, x0: np.ndarray | None, M, tol: float, restart: int,
            maxiter: int, work: dict, rtol0: float | None = None
            ) -> tuple[np.ndarray, list, float]:
    """Flexible GMRES, right-preconditioned (``x = x0 + Z y``), restarted.

    Arnoldi by classical Gram-Schmidt applied twice (two matrix-vector
    products with the basis per iteration, BLAS), Givens rotations for the
    residual estimate.  pyamg's ``fgmres`` (Householder reflections applied
    one by one, and two fresh ``restart x n`` arrays per call) cost 5-15 %
    more per solve on the brake's contact operators for the same iterates
    (measured: 57k, 25 iterations 0.48-0.52 s against 0.45 s; 154k, 24
    iterations 1.34-1.52 s against 1.26-1.38 s).  ``work`` keeps the basis
    arrays between calls.  Stops when the estimated residual is below
    ``tol ||b||`` (or ``rtol0`` times the initial residual, if given and
    larger) or after ``maxiter`` iterations; returns ``x``, the residual
    history (initial residual first; each cycle's last entry is the true
    residual) and the relative tolerance it aimed at.
    """
    n = b.size
    normb = float(np.linalg.norm(b)) or 1.0
    x = np.zeros(n) if x0 is None else np.array(x0, dtype=float).ravel()
    r = b - A @ x
    beta = float(np.linalg.norm(r))
    if rtol0 is not None:
        tol = max(tol, rtol0 * beta / normb)
    res = [beta]
    key = (n, restart)
    if work.get("key") != key:
        work.clear()
        work.update(key=key, V=np.empty((restart + 1, n)), Z=np.empty((restart, n)))
    V, Z = work["V"], work["Z"]
    its = 0
    while beta > tol * normb and its < maxiter:
        H = np.zeros((restart + 1, restart))
        cs, sn = np.zeros(restart), np.zeros(restart)
        g = np.zeros(restart + 1)
        g[0] = beta
        np.multiply(r, 1.0 / beta, out=V[0])
        k = 0
        for j in range(restart):
            Z[j] = M @ V[j]
            w = A @ Z[j]
            h = V[:j + 1] @ w
            w -= h @ V[:j + 1]
            h2 = V[:j + 1] @ w  # the second pass: orthogonal to rounding
            w -= h2 @ V[:j + 1]
            col = np.empty(j + 2)
            col[:j + 1] = h + h2
            hn = float(np.linalg.norm(w))
            col[j + 1] = hn
            for i in range(j):  # the earlier rotations on the new column
                col[i], col[i + 1] = (cs[i] * col[i] + sn[i] * col[i + 1],
                                      -sn[i] * col[i] + cs[i] * col[i + 1])
            d = float(np.hypot(col[j], col[j + 1]))
            cs[j], sn[j] = (col[j] / d, col[j + 1] / d) if d > 0 else (1.0, 0.0)
            col[j], col[j + 1] = d, 0.0
            g[j + 1], g[j] = -sn[j] * g[j], cs[j] * g[j]
            H[:j + 2, j] = col
            its += 1
            k = j + 1
            res.append(abs(g[j + 1]))
            if res[-1] <= tol * normb or hn == 0.0 or its >= maxiter:
                break
            np.multiply(w, 1.0 / hn, out=V[j + 1])
        y = np.linalg.solve(H[:k, :k], g[:k]) if k else np.zeros(0)
        x += y @ Z[:k]
        r = b - A @ x
        beta = float(np.linalg.norm(r))
        res[-1] = beta
    return x, res, tol


def _find_entries(indptr, indices, rows, cols) -> np.ndarray:
    """Positions of the entries ``(rows, cols)`` in a CSR structure with sorted
    indices; each must exist."""
    if rows.size == 0:
        return np.zeros(0, dtype=np.int64)
    ur, inv = np.unique(rows, return_inverse=True)
    starts, ends = indptr[ur].astype(np.int64), indptr[ur + 1].astype(np.int64)
    lens = ends - starts
    # the entries of those rows, keyed by (rank of the row, column)
    seg = np.repeat(np.arange(ur.size), lens)
    pos = np.repeat(starts - np.concatenate([[0], np.cumsum(lens)[:-1]]), lens) \
        + np.arange(int(lens.sum()))
    span = int(indices.max()) + 1 if indices.size else 1
    keys = seg * span + indices[pos]
    want = inv.astype(np.int64) * span + cols
    i = np.minimum(np.searchsorted(keys, want), max(keys.size - 1, 0))
    if keys.size == 0 or not np.array_equal(keys[i], want):
        raise ValueError("an entry is missing from the pattern")
    return pos[i]


class PatchedMatrix:
    """``M + D`` for a sequence of small differences ``D``, each on one shared pattern.

    ``Z`` is a structural superset of every ``D`` to come.  The pattern is
    the union of ``M``'s and ``Z``'s; the values live in one buffer holding
    ``M``'s.  :meth:`matrix` restores the entries the previous difference
    changed and adds the new one: work in the size of the difference, where
    ``M + D`` is a pass over all of ``M`` (at 490k DOFs, 21M entries: 0.4-0.6
    s).  The matrix returned before is overwritten, so only the latest may be
    used.  Entries equal ``M + D`` exactly (the same single addition), plus
    explicit zeros.  ``M`` itself is not changed.
    """

    def __init__(self, M: sp.spmatrix, Z: sp.spmatrix):
        M = sp.csr_matrix(M)
        if not M.has_canonical_format:
            M = M.copy()
            M.sum_duplicates()
        Z = sp.csr_matrix(Z, copy=True)
        Z.sum_duplicates()
        if M.shape != Z.shape:
            raise ValueError(f"Z has shape {Z.shape}; M has {M.shape}")
        n = M.shape[0]
        # the pattern changes only in Z's rows: their union is formed apart (small)
        # and spliced into M's arrays -- no sum over all of M
        zr = np.flatnonzero(np.diff(Z.indptr))
        Ms, Zs = M[zr], Z[zr]
        # 1 = M only, 2 = Z only, 3 = both: M's entries are those with an odd code, in order
        code = (sp.csr_matrix((np.ones(Ms.nnz), Ms.indices, Ms.indptr), shape=Ms.shape)
                + sp.csr_matrix((np.full(Zs.nnz, 2.0), Zs.indices, Zs.indptr), shape=Zs.shape))
        code.sort_indices()
        self.shape = M.shape
        if code.nnz == Ms.nnz:  # Z inside M's pattern: M's structure is shared as it is
            self.indptr, self.indices = M.indptr, M.indices
            self.data = M.data.copy()
        else:
            lens = np.diff(M.indptr)
            lens[zr] = np.diff(code.indptr)
            self.indptr = np.zeros(n + 1, dtype=np.int64)
            np.cumsum(lens, out=self.indptr[1:])
            self.indices = np.empty(self.indptr[-1], dtype=M.indices.dtype)
            self.data = np.empty(self.indptr[-1])
            sub = np.zeros(code.nnz)
            sub[code.data != 2.0] = Ms.data
            # copy by runs of consecutive rows: M's rows between runs, the union in them
            # (slices, no mask or cumulative sum over all entries: 2 s at 490k DOFs)
            cut = np.flatnonzero(np.diff(zr) != 1) + 1
            runs = np.split(zr, cut)
            prev, k = 0, 0
            ip, mp, cp = self.indptr, M.indptr, code.indptr
            for run in runs:
                a, b = int(run[0]), int(run[-1]) + 1
                self.indices[ip[prev]:ip[a]] = M.indices[mp[prev]:mp[a]]
                self.data[ip[prev]:ip[a]] = M.data[mp[prev]:mp[a]]
                self.indices[ip[a]:ip[b]] = code.indices[cp[k]:cp[k + b - a]]
                self.data[ip[a]:ip[b]] = sub[cp[k]:cp[k + b - a]]
                prev, k = b, k + b - a
            self.indices[ip[prev]:] = M.indices[mp[prev]:]
            self.data[ip[prev]:] = M.data[mp[prev]:]
            if self.indptr[-1] < np.iinfo(np.int32).max:
                self.indptr = self.indptr.astype(np.int32)
                self.indices = self.indices.astype(np.int32, copy=False)
        # where a difference may go: Z's entries, as positions in the buffer
        zrow = np.repeat(zr, np.diff(Zs.indptr))
        self.zkeys = zrow.astype(np.int64) * n + Zs.indices
        order = np.argsort(self.zkeys, kind="stable")
        self.zkeys = self.zkeys[order]
        self.zpos = _find_entries(self.indptr, self.indices, zrow[order], Zs.indices[order])
        self.m_z = self.data[self.zpos].copy()        # M's values there
        self.current = np.zeros(0, dtype=np.int64)    # the entries of zpos changed now

    def matrix(self, D: sp.spmatrix) -> sp.csr_matrix:
        """``M + D`` on the shared pattern and buffer."""
        D = sp.csr_matrix(D)
        D.sum_duplicates()
        n = self.shape[0]
        keys = np.repeat(np.arange(n, dtype=np.int64), np.diff(D.indptr)) * n + D.indices
        i = np.minimum(np.searchsorted(self.zkeys, keys), max(self.zkeys.size - 1, 0))
        if keys.size and not np.array_equal(self.zkeys[i], keys):
            raise ValueError("a difference outside the pattern given to PatchedMatrix")
        self.data[self.zpos[self.current]] = self.m_z[self.current]
        self.data[self.zpos[i]] = self.m_z[i] + D.data
        self.current = i
        return sp.csr_matrix((self.data, self.indices, self.indptr), shape=self.shape)


class LevelBuffers:
    """In-place coarse operators for :meth:`AMGSolver.refreshed` (:meth:`AMGSolver.level_buffers`)."""

    def __init__(self, ml, levels: list):
        self.ml = ml          # the hierarchy they belong to
        self.levels = levels  # PatchedMatrix per level below the finest (None: no pattern)


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
            raise ValueError(f"AMGSolver: matrix must be square, got shape {A.shape}")
        if fine_csr is not None and (fine_csr.format != "csr" or fine_csr.shape != A.shape):
            raise ValueError(f"fine_csr must be A in CSR: got {fine_csr.format} of shape "
                             f"{fine_csr.shape} for A of shape {A.shape}")
        self.A = A
        self._fine_csr = fine_csr
        self.B = B
        self.bodies = None if bodies is None else np.asarray(bodies)
        if self.bodies is not None:
            rows = A.shape[0] // (A.blocksize[0] if sp.issparse(A) and A.format == "bsr" else 1)
            if self.bodies.shape != (rows,):
                raise ValueError(f"bodies has shape {self.bodies.shape}; need one label per "
                                 f"node: ({rows},)")
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
                raise ValueError(f"bodies needs strength 'symmetric' and aggregate 'standard' "
                                 f"(pyamg's defaults); got {kinds}")
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
        rng_state = np.random.get_state()
        np.random.seed(20091)
        try:
            with _single_pass_spectral_radius(), _single_threaded_blas(), _batched_block_pinv(), \
                    _vectorised_bsr_dedupe(), \
                    (_split_strength(self.bodies) if self.bodies is not None else nullcontext()):
                self.ml = pyamg.smoothed_aggregation_solver(self.A, B=self.B, presmoother=None,
                                                            postsmoother=None, **self.options)
        finally:
            np.random.set_state(rng_state)
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
                  buffers: LevelBuffers | None = None) -> "AMGSolver":
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
            raise ValueError("buffers belong to another hierarchy (level_buffers() of this one)")
        A = A.tocsr()
        if dA is None:
            dA = (A - base[0].A).tocsr()
        else:
            if dA.shape != A.shape:
                raise ValueError(f"dA has shape {dA.shape}; A has {A.shape}")
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
        new.ml = pyamg.multilevel.MultilevelSolver(levels, coarse_solver=self.options["coarse_solver"])
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
              rtol0: float | None = None) -> np.ndarray:
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
                x, res, tol = _fgmres(op, b, x0, self.M, tol, 30, self.maxiter,
                                      self._krylov_work, rtol0)
                rel = res[-1] / normb
            else:
                raise ValueError(f"krylov = {krylov!r}; allowed: 'cg', 'gmres'")
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
                self.info,
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


def direct_solve(A: sp.spmatrix, b: np.ndarray, max_dofs: int = DIRECT_MAX_DOFS) -> np.ndarray:
    """Sparse direct solve (SuperLU) for small systems only.

    Raises ``ValueError`` above ``max_dofs`` unknowns: a 3D factorisation
    grows much faster than the system and belongs to small problems and
    reference solutions.
    """
    n = A.shape[0]
    if n > max_dofs:
        raise ValueError(f"direct_solve: {n} DOFs exceeds max_dofs = {max_dofs}; "
                         "use amg_solver for large systems (or raise max_dofs knowingly)")
    lu = spla.splu(sp.csc_matrix(A), permc_spec="MMD_AT_PLUS_A")
    x = lu.solve(np.asarray(b, dtype=float))
    if not np.all(np.isfinite(x)):
        raise ConvergenceError("direct_solve: the factorisation produced non-finite values "
                               "(singular matrix: is the body constrained?)", SolveInfo())
    return x
