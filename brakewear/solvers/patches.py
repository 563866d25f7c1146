"""Changes to pyamg's and scipy's internals for the time of an AMG setup.

Every patch is a context manager that swaps one module-level function (or
method) for the duration of a setup and restores it afterwards.  Each first
checks that what it swaps still has the parameters it relies on
(:func:`_fits`): a pyamg or scipy release that changed them gets no patch
and a warning, and the solves run as those libraries ship them (slower, the
same answers), rather than failing or patching the wrong thing.
"""
from __future__ import annotations

import inspect
import logging
from contextlib import contextmanager
from functools import partial

import numpy as np
import pyamg.aggregation.smooth as _pyamg_smooth
import pyamg.util.linalg as _pyamg_linalg
import scipy.sparse as sp

from ..errors import SolverSettingsError

logger = logging.getLogger(__name__)

__all__ = []

_WARNED: set = set()


def _fits(owner, name: str, params: tuple[str, ...]) -> bool:
    """Whether ``owner.name`` exists and takes ``params``; warns once if not."""
    target = getattr(owner, name, None)
    try:
        ok = target is not None and all(p in inspect.signature(target).parameters
                                        for p in params)
    except (TypeError, ValueError):
        ok = False
    if not ok and (owner, name) not in _WARNED:
        _WARNED.add((owner, name))
        logger.warning("%s.%s is not the function brakewear's setup patches (it needs the "
                       "parameters %s): running without that patch (slower AMG setups, the "
                       "same answers)", getattr(owner, "__name__", owner), name,
                       ", ".join(params))
    return ok


@contextmanager
def _single_pass_spectral_radius():
    """Let pyamg's Jacobi prolongation smoother estimate rho(D^-1 A) in one Arnoldi pass.

    pyamg restarts its Arnoldi estimate up to five times (15 products each)
    until the Ritz value settles to 1 %; on elasticity it always takes the
    restart, and the estimates cost about a third of the whole setup.  One
    pass of 15 steps changes the iteration count by at most one (measured on
    the 1M-DOF rotor ring, docs/solvers.md).  pyamg offers no option for
    this, so its module-level function is swapped for the time of the call.
    """
    if not _fits(_pyamg_smooth, "approximate_spectral_radius", ("A", "maxiter", "restart")):
        yield
        return
    saved = _pyamg_smooth.approximate_spectral_radius
    _pyamg_smooth.approximate_spectral_radius = partial(saved, maxiter=15, restart=0)
    try:
        yield
    finally:
        _pyamg_smooth.approximate_spectral_radius = saved


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
    if not _fits(_pyamg_linalg, "pinv_array", ("a", "tol")):
        yield
        return
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
    if not _fits(_BSR_BASE, "sum_duplicates", ("self",)):
        yield
        return
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

    if not (_fits(agg, "symmetric_strength_of_connection", ("A", "theta"))
            and _fits(agg, "standard_aggregation", ("C",))):
        yield
        return
    strength, aggregate = agg.symmetric_strength_of_connection, agg.standard_aggregation
    labels = [np.asarray(bodies)]

    def split(A, **kwargs):
        C = strength(A, **kwargs).tocsr()
        lab = labels[0]
        if lab.shape != (C.shape[0],):
            raise SolverSettingsError(f"bodies has {lab.size} labels; the strength graph of "
                                      f"this level has {C.shape[0]} nodes (one label per 3x3 "
                                      "block row)")
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
