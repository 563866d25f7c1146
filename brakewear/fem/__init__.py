"""Finite-element building blocks: forms, fast assembly, boundary conditions, stresses, heat.

Form factories in scikit-fem style (:mod:`~brakewear.fem.forms`), the chunked
elasticity assembly tested against them (:mod:`~brakewear.fem.assembly`),
Dirichlet conditions and tractions (:mod:`~brakewear.fem.boundary`), stress
recovery (:mod:`~brakewear.fem.stress`) and transient heat conduction of one
body (:mod:`~brakewear.fem.heat`).
"""

from . import assembly, boundary, forms, heat, stress
from .assembly import *  # noqa: F403
from .boundary import *  # noqa: F403
from .forms import *  # noqa: F403
from .heat import *  # noqa: F403
from .stress import *  # noqa: F403

__all__ = [
    *assembly.__all__,
    *boundary.__all__,
    *forms.__all__,
    *heat.__all__,
    *stress.__all__,
]
