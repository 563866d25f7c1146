"""Meshes: structured tetrahedra, the parametric brake meshes with named surfaces, files."""

from . import brake, estimate, io, rotor, series, structured, topology
from .brake import *  # noqa: F403
from .estimate import *  # noqa: F403
from .io import *  # noqa: F403
from .rotor import *  # noqa: F403
from .series import *  # noqa: F403
from .structured import *  # noqa: F403
from .topology import *  # noqa: F403

__all__ = [
    *brake.__all__,
    *estimate.__all__,
    *io.__all__,
    *rotor.__all__,
    *series.__all__,
    *structured.__all__,
    *topology.__all__,
]
