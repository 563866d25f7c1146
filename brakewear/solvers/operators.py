"""A matrix plus sparse products, applied without forming their sum (:class:`ProductSum`)."""
from __future__ import annotations

import logging

import numpy as np
from scipy.sparse.linalg import LinearOperator

from ..errors import SolverSettingsError

logger = logging.getLogger(__name__)

__all__ = ["ProductSum"]


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
