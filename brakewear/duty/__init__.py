"""Duty of a brake: the vehicle, the applications (stops, drags, dwells) and schedules.

* :mod:`~brakewear.duty.vehicle` -- :class:`Vehicle`: a deceleration as the
  brake's torque and back; the brake's torque against its line pressure;
* :mod:`~brakewear.duty.applications` -- :class:`Stop`, :class:`Drag`,
  :class:`Dwell`, each resolving itself against a vehicle and the brake;
* :mod:`~brakewear.duty.kinds` -- the table of kinds: :func:`register_application`
  adds one;
* :mod:`~brakewear.duty.schedule` -- schedules from a table or a drive-cycle CSV;
* :mod:`~brakewear.duty.runner` -- :func:`run_schedule`: wear, heat and
  energy per application;
* :mod:`~brakewear.duty.states` -- what a schedule carries besides the wear
  (a rust layer, the rotor's heat), asked before and after each application;
* :mod:`~brakewear.duty.cycle` -- a drive cycle replayed through the
  vehicle's blending: the friction work ordinary driving gives the rotor.
"""

from . import applications, cycle, kinds, runner, schedule, states, vehicle
from .applications import *  # noqa: F403
from .cycle import *  # noqa: F403
from .kinds import *  # noqa: F403
from .runner import *  # noqa: F403
from .schedule import *  # noqa: F403
from .states import *  # noqa: F403
from .vehicle import *  # noqa: F403

__all__ = [*vehicle.__all__, *applications.__all__, *kinds.__all__, *schedule.__all__,
           *runner.__all__, *cycle.__all__, *states.__all__]
