"""Linear solvers: pyamg smoothed aggregation with the rigid-body near-nullspace, Krylov, direct."""

from .amg import (
    SA_OPTIONS,
    SMOOTHERS,
    AMGSolver,
    SolveInfo,
    amg_solver,
    rigid_body_modes,
)
from .direct import DIRECT_MAX_DOFS, direct_solve
from .patched import PatchedMatrix

__all__ = [
    "SolveInfo",
    "rigid_body_modes",
    "AMGSolver",
    "amg_solver",
    "SA_OPTIONS",
    "SMOOTHERS",
    "direct_solve",
    "DIRECT_MAX_DOFS",
    "PatchedMatrix",
]
