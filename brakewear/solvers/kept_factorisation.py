"""Dense systems whose equations switch between a few kinds, solved from one kept LU.

A contact problem held by rows (:mod:`brakewear.caliper.joint`) is
a dense system ``M(code) z = r`` whose equation ``k`` is, by its code, the
identity (``z_k = 0``: an open node or row), the ``k``-th row of a fixed
matrix ``Ms`` (a node or row in contact), or a row of its own (a friction row
that slips).  Between two solves a few codes change.

:class:`KeptFactorisation` factorises the system of one *reference* code
(only its unknowns whose equation is not the identity: an LU of their block)
and solves the system of any other code by the Woodbury identity over the
equations ``K`` whose code differs: with ``X = M_ref^-1 E_K`` (one column per
changed equation, each solved once per reference and kept) and ``R`` the new
equations' rows,

    z = y - X w,   y = M_ref^-1 r~,   (R X) w = R y - r_K,

(``r~`` is ``r`` with the rows ``K`` set to zero).  The capacitance ``R X``
(``|K| x |K|``) is factorised once per code and kept.  When more than
``max_changes`` equations differ, the code at hand becomes the reference
(one new LU).  So a settled state costs one triangular solve pair of the
reference's block and two thin products; a state a few equations away adds
a few columns; only a state far from the reference is factorised.

Singular systems (a state that leaves an unknown undetermined) raise
:class:`SingularState`, found from the LU's or the capacitance's pivots.
"""
from __future__ import annotations

import logging
import warnings
from collections import OrderedDict

import numpy as np
from scipy.linalg import LinAlgWarning, lu_factor
from scipy.linalg.lapack import dgetrs

from ..errors import SolverError

logger = logging.getLogger(__name__)

__all__ = ["KeptFactorisation", "SingularState", "equilibrate", "gmres", "IDENT", "FULL"]

#: equation codes: the identity (z_k = 0) and the full row of ``Ms``; codes >= 2 are
#: the caller's own rows
IDENT, FULL = 0, 1
#: a pivot below this share of the largest is a singular system
_PIVOT = 1e-13
#: capacitance systems kept per reference
_KEEP = 24


def equilibrate(M: np.ndarray, sweeps: int = 4):
    """Row and column scales ``(r, c)`` making ``r M c`` near 1 in every row and
    column's largest entry (Ruiz's iteration).

    Parameters
    ----------
    M
        A dense matrix.
    sweeps
        Ruiz's sweeps.

    Returns
    -------
    tuple
        ``(r, c)``: the row and column scales.
    """
    r, c = np.ones(M.shape[0]), np.ones(M.shape[1])
    A = np.abs(M)
    for _ in range(sweeps):
        S = A * r[:, None] * c[None, :]
        rm, cm = S.max(axis=1), S.max(axis=0)
        r /= np.sqrt(np.where(rm > 0, rm, 1.0))
        c /= np.sqrt(np.where(cm > 0, cm, 1.0))
    return r, c


def lu_solve(lu, b, check_finite: bool = False) -> np.ndarray:
    """``scipy.linalg.lu_solve`` of a factorisation of ``lu_factor``, through LAPACK's
    getrs directly (the same numbers, without the wrapper's checks: these solves
    are many and small)."""
    x, info = dgetrs(lu[0], lu[1], b)
    if info != 0:
        raise SolverError(f"getrs failed (info = {info})")
    return x


class SingularState(SolverError):
    """The system of a code is singular (an unknown left undetermined)."""


def _checked_lu(M: np.ndarray, what: str, scale: float | None = None):
    """The LU of ``M``; singular when a pivot is below :data:`_PIVOT` of the largest
    (or of ``scale``, the size its entries would have without cancellation)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LinAlgWarning)
        lu = lu_factor(M, check_finite=False)
    piv = np.abs(np.diag(lu[0]))
    top = piv.max() if scale is None else scale
    if piv.size and (not np.all(np.isfinite(piv)) or piv.min() <= _PIVOT * top):
        raise SingularState(f"{what}: singular (smallest pivot {piv.min():.3g} of "
                            f"{top:.3g})")
    return lu


class _Prepared:
    """The Woodbury correction of one code against the reference."""

    __slots__ = ("K", "X", "ident", "dense", "Rd", "lu")

    def __init__(self, K, X, ident, dense, Rd, lu):
        self.K, self.X, self.ident, self.dense, self.Rd, self.lu = K, X, ident, dense, Rd, lu


class KeptFactorisation:
    """Solve ``M(code) z = r`` from one kept LU and Woodbury corrections (see the module).

    Parameters
    ----------
    Ms
        (N, N) the full rows (equation code :data:`FULL`).
    special
        ``special(ks, codes) -> (len(ks), N)``: the rows of the caller's own codes.
    max_changes
        Equations that may differ from the reference before the code at hand
        is factorised as the new reference.
    """

    def __init__(self, Ms: np.ndarray, special, max_changes: int = 48):
        self.Ms, self.special, self.max_changes = Ms, special, int(max_changes)
        self.N = Ms.shape[0]
        self.code = None            # the reference's codes
        self.factorised = 0         # reference LUs made
        self.updated = 0            # capacitance systems made

    # ------------------------------------------------------------ reference --
    def _rows(self, code: np.ndarray, ks: np.ndarray) -> np.ndarray:
        """The equations ``ks`` of ``code`` as dense rows (identity rows included)."""
        out = np.zeros((ks.size, self.N))
        c = code[ks]
        full = c == FULL
        out[full] = self.Ms[ks[full]]
        ident = c == IDENT
        out[np.nonzero(ident)[0], ks[ident]] = 1.0
        own = ~(full | ident)
        if own.any():
            out[own] = self.special(ks[own], c[own])
        return out

    def set_reference(self, code: np.ndarray) -> None:
        """Factorise the system of ``code`` (its non-identity unknowns' block)."""
        code = np.asarray(code, dtype=np.int8).copy()
        U = np.nonzero(code != IDENT)[0]
        MU = self._rows(code, U)                # |U| x N
        lu = _checked_lu(MU[:, U], "the reference system")
        self.code, self.U, self.MU, self.lu = code, U, MU, lu
        self.pos = np.full(self.N, -1, dtype=np.int64)
        self.pos[U] = np.arange(U.size)
        self.columns: dict = {}                 # k -> M_ref^-1 e_k
        self.prepared: OrderedDict = OrderedDict()
        self.factorised += 1

    def _columns(self, ks: np.ndarray) -> np.ndarray:
        """``M_ref^-1 e_k`` of each ``k`` in ``ks`` (N x len(ks)), solved once each."""
        new = np.array([k for k in ks if k not in self.columns], dtype=np.int64)
        if new.size:
            # z_k = 1 on an identity equation of the reference, its column moved right
            B = np.zeros((self.U.size, new.size))
            inU = self.pos[new] >= 0
            B[self.pos[new[inU]], np.nonzero(inU)[0]] = 1.0
            B[:, ~inU] = -self.MU[:, new[~inU]]
            Y = lu_solve(self.lu, B, check_finite=False)
            for j, k in enumerate(new):
                col = np.zeros(self.N)
                col[self.U] = Y[:, j]
                if not inU[j]:
                    col[k] = 1.0
                self.columns[int(k)] = col
        return np.stack([self.columns[int(k)] for k in ks], axis=1) if ks.size else \
            np.zeros((self.N, 0))

    # -------------------------------------------------------------- solves --
    def prepare(self, code: np.ndarray) -> _Prepared:
        """The correction of ``code`` (kept); a code far from the reference
        becomes the reference.  Raises :class:`SingularState`."""
        code = np.asarray(code, dtype=np.int8)
        if self.code is None:
            self.set_reference(code)
        K = np.nonzero(code != self.code)[0]
        if K.size > self.max_changes:
            self.set_reference(code)
            K = K[:0]
        key = code.tobytes()
        got = self.prepared.get(key)
        if got is not None:
            self.prepared.move_to_end(key)
            return got
        X = self._columns(K)
        ident = code[K] == IDENT
        dense = ~ident
        Rd = self._rows(code, K[dense])
        C = np.empty((K.size, K.size))
        C[ident] = X[K[ident]]
        C[dense] = Rd @ X
        # the entries' size without cancellation: |row| |column| (a new equation
        # that the reference's others already imply cancels to round-off)
        rn = np.ones(K.size)
        rn[dense] = np.linalg.norm(Rd, axis=1)
        size = float((rn[:, None] * np.linalg.norm(X, axis=0)[None, :]).max()) if K.size else 0
        try:
            lu = _checked_lu(C, "the changed equations' system", size) if K.size else None
        except SingularState:
            # near-singular against this reference: factorise the state itself (which
            # raises if it is singular)
            self.set_reference(code)
            return self.prepare(code)
        got = _Prepared(K, X, ident, dense, Rd, lu)
        self.prepared[key] = got
        self.updated += 1
        while len(self.prepared) > _KEEP:
            self.prepared.popitem(last=False)
        return got

    def solve(self, prep: _Prepared, r: np.ndarray) -> np.ndarray:
        """``z`` with ``M(code) z = r`` (``r`` zero on the identity equations of the
        reference that the code keeps)."""
        K = prep.K
        rt = r[self.U].copy()
        if K.size:
            inU = self.pos[K]
            rt[inU[inU >= 0]] = 0.0
        z = np.zeros(self.N)
        z[self.U] = lu_solve(self.lu, rt, check_finite=False)
        if not K.size:
            return z
        Ry = np.empty(K.size)
        Ry[prep.ident] = z[K[prep.ident]]
        Ry[prep.dense] = prep.Rd @ z
        w = lu_solve(prep.lu, Ry - r[K], check_finite=False)
        return z - prep.X @ w


    def product(self, code: np.ndarray, z: np.ndarray) -> np.ndarray:
        """``M(code) z``."""
        code = np.asarray(code, dtype=np.int8)
        out = np.where(code == IDENT, z, 0.0)
        full = code == FULL
        out[full] = self.Ms[full] @ z
        own = np.nonzero(~(full | (code == IDENT)))[0]
        if own.size:
            out[own] = self.special(own, code[own]) @ z
        return out


def gmres(apply, r0: np.ndarray, tol: float, maxiter: int):
    """Right-preconditioned GMRES on ``apply`` (``v -> (I + P M^-1) v``) from ``r0``:
    ``(u, residual estimate, iterations)`` with ``apply(u) ~= r0``."""
    beta = float(np.linalg.norm(r0))
    if beta == 0.0:
        return np.zeros_like(r0), 0.0, 0
    V = np.zeros((maxiter + 1, r0.size))
    H = np.zeros((maxiter + 1, maxiter))
    cs, sn = np.zeros(maxiter), np.zeros(maxiter)
    g = np.zeros(maxiter + 1)
    g[0] = beta
    V[0] = r0 / beta
    k = 0
    for j in range(maxiter):
        w = apply(V[j])
        for _ in range(2):                     # modified Gram-Schmidt, twice
            h = V[:j + 1] @ w
            w -= h @ V[:j + 1]
            H[:j + 1, j] += h
        h_next = float(np.linalg.norm(w))
        H[j + 1, j] = h_next
        for i in range(j):
            H[i, j], H[i + 1, j] = (cs[i] * H[i, j] + sn[i] * H[i + 1, j],
                                    -sn[i] * H[i, j] + cs[i] * H[i + 1, j])
        d = np.hypot(H[j, j], H[j + 1, j])
        cs[j], sn[j] = (H[j, j] / d, H[j + 1, j] / d) if d > 0 else (1.0, 0.0)
        H[j, j], H[j + 1, j] = d, 0.0
        g[j + 1] = -sn[j] * g[j]
        g[j] = cs[j] * g[j]
        k = j + 1
        if abs(g[k]) <= tol or h_next == 0.0:
            break
        V[j + 1] = w / h_next
    y = np.linalg.solve(np.triu(H[:k, :k]), g[:k]) if k else np.zeros(0)
    return y @ V[:k], abs(g[k]), k
