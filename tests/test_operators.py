"""The Krylov solvers' operators against the dense matrices they stand for."""
from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.linalg import lu_factor

from brakewear.errors import SolverSettingsError
from brakewear.solvers import Bordered, BorderedPreconditioner, ProductSum

RNG = np.random.default_rng(7)
N, M = 12, 3


def _dense(n, m):
    return RNG.standard_normal((n, m))


def test_product_sum_is_the_sum_it_stands_for():
    A = sp.random(N, N, density=0.4, random_state=1, format="csr") + 5 * sp.eye(N)
    L, R, E = _dense(N, M), _dense(M, N), sp.random(N, N, density=0.2, random_state=2)
    op = ProductSum(A, [(1, L, R), (-1, E, None)])
    v = RNG.standard_normal(N)
    want = A.toarray() @ v + L @ (R @ v) - E.toarray() @ v
    assert np.allclose(op @ v, want, rtol=1e-13, atol=1e-13 * np.abs(want).max())
    with pytest.raises(SolverSettingsError, match="sign 2"):
        ProductSum(A, [(2, L, R)])


def test_bordered_and_its_preconditioner():
    """The bordered operator is the block matrix ``[[A, U], [s R, s D]]``; with an exact
    ``A^-1`` its preconditioner inverts the block lower triangle ``[[A, 0], [s R, s D]]``."""
    A = _dense(N, N) + 8 * np.eye(N)
    U, R, D = _dense(N, M), _dense(M, N), _dense(M, M) + 4 * np.eye(M)
    s = np.array([1e3, 2.0, 0.5])
    K = np.block([[A, U], [s[:, None] * R, s[:, None] * D]])
    y = RNG.standard_normal(N + M)
    assert np.allclose(Bordered(A, U, sp.csr_matrix(R), D, s) @ y, K @ y, rtol=1e-13,
                       atol=1e-12 * np.abs(K @ y).max())
    L = np.block([[A, np.zeros((N, M))], [s[:, None] * R, s[:, None] * D]])
    P = BorderedPreconditioner(np.linalg.inv(A), R, lu_factor(D), s)
    r = RNG.standard_normal(N + M)
    assert np.allclose(L @ (P @ r), r, rtol=1e-10, atol=1e-10 * np.abs(r).max())
