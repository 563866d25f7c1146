"""Linear solvers: pyamg smoothed aggregation with the rigid-body near-nullspace, Krylov, direct,
and dense systems of switching equations on a kept factorisation."""

from . import amg, direct, kept_factorisation, operators, patched
from .amg import *  # noqa: F403
from .direct import *  # noqa: F403
from .kept_factorisation import *  # noqa: F403
from .operators import *  # noqa: F403
from .patched import *  # noqa: F403

__all__ = [*amg.__all__, *direct.__all__, *kept_factorisation.__all__, *operators.__all__,
           *patched.__all__]
