"""A sparse matrix updated in place by small differences on one shared pattern."""
from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp

from ..errors import SolverSettingsError

logger = logging.getLogger(__name__)

__all__ = ["PatchedMatrix"]


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
        raise SolverSettingsError("an entry is missing from the pattern")
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
            raise SolverSettingsError(f"Z has shape {Z.shape}; M has {M.shape}")
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
            raise SolverSettingsError("a difference outside the pattern given to PatchedMatrix")
        self.data[self.zpos[self.current]] = self.m_z[self.current]
        self.data[self.zpos[i]] = self.m_z[i] + D.data
        self.current = i
        return sp.csr_matrix((self.data, self.indices, self.indptr), shape=self.shape)


class LevelBuffers:
    """In-place coarse operators for :meth:`AMGSolver.refreshed` (``level_buffers``)."""

    def __init__(self, ml, levels: list):
        self.ml = ml          # the hierarchy they belong to
        self.levels = levels  # PatchedMatrix per level below the finest (None: no pattern)
