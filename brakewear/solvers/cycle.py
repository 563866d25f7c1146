"""The AMG V-cycle used as a preconditioner, and backward Gauss-Seidel over reversed copies."""
from __future__ import annotations

import logging
import weakref

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from pyamg import amg_core

logger = logging.getLogger(__name__)

__all__ = []


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
    2.2x slower than its forward one on these matrices (docs/solvers.md).
    A copy costs about three forward sweeps, and much more where fresh
    memory is slow (the same 8M-entry copy has been measured at 13 to 300 ms
    on one shared machine), so:

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

    def __init__(self, n_levels: int, inherit: _BackwardSweeps | None = None):
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
