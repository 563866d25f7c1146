"""Linear solvers: pyamg smoothed aggregation with the rigid-body near-nullspace, Krylov, direct."""

from . import amg, direct, operators, patched
from .amg import *  # noqa: F403
from .direct import *  # noqa: F403
from .operators import *  # noqa: F403
from .patched import *  # noqa: F403

__all__ = [*amg.__all__, *direct.__all__, *operators.__all__, *patched.__all__]
