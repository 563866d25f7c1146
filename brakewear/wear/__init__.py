"""The wear loop: Archard wear of pad and rotor integrated in time.

* :mod:`~brakewear.wear.numerics` -- :class:`Numerics`, how the loop integrates
  (one set of defaults for Python calls and scene files);
* :mod:`~brakewear.wear.control` -- :class:`StepControl`, the step size;
* :mod:`~brakewear.wear.limits` -- :class:`WearLimits`, when a surface is worn through;
* :mod:`~brakewear.wear.speed` -- :class:`ConstantSpeed`, :class:`LinearSpeed`,
  the rotor's speed over a history (a drag, a stop);
* :mod:`~brakewear.wear.state` -- :class:`WearState` and its checkpoints;
* :mod:`~brakewear.wear.stepper` -- :func:`wear_history`, the loop itself.
"""

from . import control, limits, numerics, speed, state, stepper
from .control import *  # noqa: F403
from .limits import *  # noqa: F403
from .numerics import *  # noqa: F403
from .speed import *  # noqa: F403
from .state import *  # noqa: F403
from .stepper import *  # noqa: F403

__all__ = [*control.__all__, *limits.__all__, *numerics.__all__, *speed.__all__, *state.__all__, *stepper.__all__]
