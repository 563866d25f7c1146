"""Sparse direct solves (SuperLU) for small systems and reference solutions."""
from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import ConvergenceError, SolverSettingsError
from .amg import SolveInfo

logger = logging.getLogger(__name__)

__all__ = ["direct_solve", "DIRECT_MAX_DOFS"]


#: Largest system :func:`direct_solve` accepts unless told otherwise: beyond
#: this a 3D sparse factorisation costs minutes and gigabytes.
DIRECT_MAX_DOFS = 150_000


def direct_solve(A: sp.spmatrix, b: np.ndarray, max_dofs: int = DIRECT_MAX_DOFS) -> np.ndarray:
    """Sparse direct solve (SuperLU) for small systems only.

    Raises :class:`~brakewear.errors.SolverSettingsError` above ``max_dofs``
    unknowns: a 3D factorisation grows much faster than the system and belongs
    to small problems and reference solutions.
    """
    n = A.shape[0]
    if n > max_dofs:
        raise SolverSettingsError(f"direct_solve: {n} DOFs exceeds max_dofs = {max_dofs}; "
                                  "use amg_solver for large systems (or raise max_dofs knowingly)")
    lu = spla.splu(sp.csc_matrix(A), permc_spec="MMD_AT_PLUS_A")
    x = lu.solve(np.asarray(b, dtype=float))
    if not np.all(np.isfinite(x)):
        raise ConvergenceError("direct_solve: the factorisation produced non-finite values "
                               "(singular matrix: is the body constrained?)", SolveInfo())
    return x
