"""Operators the Krylov solvers apply without forming them: a matrix plus sparse
products (:class:`ProductSum`), a system bordered by a few extra unknowns
(:class:`Bordered`) and its block-triangular preconditioner
(:class:`BorderedPreconditioner`)."""
from __future__ import annotations

import logging

import numpy as np
from scipy.linalg import lu_solve
from scipy.sparse.linalg import LinearOperator

from ..errors import SolverSettingsError

logger = logging.getLogger(__name__)

__all__ = ["ProductSum", "Bordered", "BorderedPreconditioner"]


class ProductSum(LinearOperator):
    """``A v + sum_k s_k L_k (R_k v)`` as a linear operator for the Krylov solvers.

    A set's operator in contact is the stiffness plus low-rank or sparse
    corrections (friction through the constraint rows, a set's projection),
    whose product with a vector is cheap while their sum would fill in.

    Parameters
    ----------
    A
        The square matrix (sparse or anything with ``@``).
    terms
        ``(s, L, R)`` triples: sign ``s`` (+1 or -1), the factors ``L`` and
        ``R`` (``R`` None: the term is ``s L v``).
    """

    def __init__(self, A, terms=()):
        self.A = A
        self.terms = tuple(terms)
        for s, _, _ in self.terms:
            if s not in (1, -1):
                raise SolverSettingsError(f"ProductSum: sign {s!r}; need +1 or -1")
        super().__init__(dtype=np.dtype(float), shape=A.shape)

    def _matvec(self, v):
        y = self.A @ v
        for s, L, R in self.terms:
            w = L @ (v if R is None else R @ v)
            y = y - w if s < 0 else y + w
        return y


class Bordered(LinearOperator):
    """A square operator bordered by ``m`` extra unknowns, on ``y = (x, d)``:

        [ A          U       ] [x]
        [ s * R      s * D   ] [d]

    (``s`` a scale per extra row, so that those rows weigh as the others do).

    Parameters
    ----------
    A
        (n x n), anything with ``@`` (a matrix, a :class:`ProductSum`).
    U, R
        (n x m) and (m x n) borders.
    D
        (m x m) the extra unknowns' own block (dense or sparse).
    scale
        (m,) ``s``, > 0.
    """

    def __init__(self, A, U, R, D, scale: np.ndarray):
        self.A, self.U, self.R, self.D = A, U, R, D
        self.scale = np.asarray(scale, dtype=float)
        self.n = A.shape[0]
        m = self.scale.size
        super().__init__(dtype=np.dtype(float), shape=(self.n + m, self.n + m))

    def _matvec(self, y):
        y = np.ravel(y)
        x, d = y[:self.n], y[self.n:]
        return np.concatenate([self.A @ x + self.U @ d, self.scale * (self.R @ x + self.D @ d)])


class BorderedPreconditioner(LinearOperator):
    """The block lower-triangular (right) preconditioner of a :class:`Bordered`
    operator: an approximate ``A^-1`` (``M``, e.g. one AMG V-cycle) on the
    first block, then the extra rows solved exactly with their LU factors:
    ``z_x = M r_x``, ``z_d = D^-1 (r_d / s - R z_x)``.

    Parameters
    ----------
    M
        (n x n) approximate inverse of ``A`` (anything with ``@``).
    R
        (m x n) the lower border.
    lu
        :func:`scipy.linalg.lu_factor` of ``D``.
    scale
        (m,) the extra rows' scale ``s``.
    """

    def __init__(self, M, R, lu, scale: np.ndarray):
        self.M, self.R, self.lu = M, R, lu
        self.scale = np.asarray(scale, dtype=float)
        self.n = R.shape[1]
        m = self.scale.size
        super().__init__(dtype=np.dtype(float), shape=(self.n + m, self.n + m))

    def _matvec(self, r):
        r = np.ravel(r)
        zx = self.M @ r[:self.n]
        zd = lu_solve(self.lu, r[self.n:] / self.scale - self.R @ zx, check_finite=False)
        return np.concatenate([zx, zd])
