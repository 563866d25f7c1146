"""The wear loop: Archard wear of pad and rotor integrated in time.

* :mod:`~brakewear.wear.numerics` -- :class:`Numerics`, how the loop integrates
  (one set of defaults for Python calls and scene files);
* :mod:`~brakewear.wear.control` -- :class:`StepControl`, the step size;
* :mod:`~brakewear.wear.limits` -- :class:`WearLimits`, when a surface is worn through;
* :mod:`~brakewear.wear.speed` -- :class:`ConstantSpeed`, :class:`LinearSpeed`,
  the rotor's speed over a history (a drag, a stop);
* :mod:`~brakewear.wear.state` -- :class:`WearState` and its checkpoints;
* :mod:`~brakewear.wear.run` -- :class:`Run`, one run described once (what
  every runner takes);
* :mod:`~brakewear.wear.coupling` -- :class:`ThermalCoupling`, what the loop
  asks of thermal coupling;
* :mod:`~brakewear.wear.stepper` -- :func:`wear_history`, the loop itself.
"""

from . import control, coupling, limits, numerics, run, speed, state, stepper
from .control import *  # noqa: F403
from .coupling import *  # noqa: F403
from .limits import *  # noqa: F403
from .numerics import *  # noqa: F403
from .run import *  # noqa: F403
from .speed import *  # noqa: F403
from .state import *  # noqa: F403
from .stepper import *  # noqa: F403

__all__ = [*control.__all__, *coupling.__all__, *limits.__all__, *numerics.__all__, *run.__all__,
           *speed.__all__, *state.__all__, *stepper.__all__]
