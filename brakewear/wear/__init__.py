"""The wear loop: Archard wear of pad and rotor integrated in time."""

from . import limits, numerics, stepper
from .limits import *  # noqa: F403
from .numerics import *  # noqa: F403
from .stepper import *  # noqa: F403

__all__ = [*limits.__all__, *numerics.__all__, *stepper.__all__]
