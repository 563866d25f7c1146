"""Frictional heating of the brake: heat partition, pad and rotor temperatures, thermal strain."""

from ..materials import H_CONV_DEFAULT, T_AMBIENT_DEFAULT
from . import coning, convection, model, partition, quadratic, reduced, stability, strain
from .coning import *  # noqa: F403
from .convection import *  # noqa: F403
from .model import *  # noqa: F403
from .partition import *  # noqa: F403
from .quadratic import *  # noqa: F403
from .reduced import *  # noqa: F403
from .stability import *  # noqa: F403
from .strain import *  # noqa: F403

__all__ = [
    "H_CONV_DEFAULT",
    "T_AMBIENT_DEFAULT",
    *coning.__all__,
    *convection.__all__,
    *model.__all__,
    *partition.__all__,
    *quadratic.__all__,
    *reduced.__all__,
    *stability.__all__,
    *strain.__all__,
]
