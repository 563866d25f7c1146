"""A cleaning routine: the stops a car maker programs, run as one schedule.

A routine is what the car's controller commands: ``stops`` friction-only stops
from ``speed`` to rest at ``decel``, ``interval`` seconds apart (start to
start; 60-600 s), the car driving on at ``dwell_speed`` between them
(:class:`Routine`).  It runs as any schedule does, through
:func:`brakewear.duty.run_schedule` and the application table: the stops
and dwells are :class:`~brakewear.duty.Stop` and
:class:`~brakewear.duty.Dwell` (any registered application may stand in a
schedule of :func:`routine_run`), and what the routine carries besides the
wear are schedule states (:mod:`brakewear.duty.states`):

* the rust layer (:class:`~brakewear.cleaning.rust.RustLayer`, kind
  ``"rust"``): its laws are the run's wear laws, its friction factor each
  stop's, and each wear step's rotor wear its removal;
* the rotor's heat (:class:`~brakewear.cleaning.heat.RotorHeat`, name
  ``"rotor_heat"``): each stop's thermal coning as an extra gap;
* the pads' touch (:class:`TouchFaces`, name ``"touch"``): each application
  starts from its pads touching their faces, the smallest gap of each face
  zero.  Between applications the caliper retracts and the pads come back to
  touch: the wear's uniform advance is taken up by the piston and the
  housing sliding, not by the caliper's rows, whose state (the abutments and
  the bore sticking) each application starts afresh.

Every contact solve a stop's wear loop starts without a start set starts
from the last set found (:class:`WarmStart`): the torque iteration's, with
the same thermal gap, so that the caliper's nested active sets start near
their answer.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..checks import check_int, check_number
from ..duty import KMH, Vehicle, repeated_stops
from ..duty.states import register_state
from ..errors import DutyError
from ..wear.run import Run
from .corrosion import outboard_nodes
from .heat import RotorHeat
from .rust import RustLayer

logger = logging.getLogger(__name__)

__all__ = ["Routine", "WarmStart", "TouchFaces", "routine_run", "RotorHeat", "INTERVAL_RANGE"]

register_state(RustLayer)

#: the stops' spacing a routine may have (s, start to start): a minute to ten minutes
INTERVAL_RANGE = (60.0, 600.0)


@dataclass(frozen=True)
class Routine:
    """A cleaning routine as a car maker states it (SI units).

    Parameters
    ----------
    stops : int
        Friction-only stops (1-100).
    speed : float
        Each stop's start speed (m/s); each ends at rest.
    decel : float
        Deceleration (m/s^2).
    interval : float
        Start to start (s), within :data:`INTERVAL_RANGE` and longer than a stop.
    dwell_speed : float or None
        The speed the car drives on at between the stops (m/s; None: ``speed``).
    """

    stops: int
    speed: float
    decel: float
    interval: float = 120.0
    dwell_speed: float | None = None

    def __post_init__(self):
        check_int("routine.stops", self.stops, 1, kind=DutyError, hi=100)
        check_number("routine.speed", self.speed, 0.0, 100.0, unit="m/s", kind=DutyError)
        check_number("routine.decel", self.decel, 0.0, 12.0, unit="m/s^2", kind=DutyError)
        lo, hi = INTERVAL_RANGE
        check_number("routine.interval", self.interval, lo, hi, lo_open=False, unit="s",
                     kind=DutyError)
        if not self.interval > self.speed / self.decel:
            raise DutyError(f"routine.interval = {self.interval:g} s is not allowed; a stop "
                            f"from {self.speed / KMH:.4g} km/h at {self.decel:g} m/s^2 lasts "
                            f"{self.speed / self.decel:.3g} s (start to start must be longer)")
        check_number("routine.dwell_speed", self.dwell_speed, 0.0, 100.0, lo_open=False,
                     unit="m/s", kind=DutyError, allow_none=True)

    def schedule(self) -> list:
        """Its stops and the dwells between them (:func:`brakewear.duty.repeated_stops`)."""
        dwell = self.speed if self.dwell_speed is None else self.dwell_speed
        return repeated_stops(self.stops, self.speed, decel=self.decel, interval=self.interval,
                              dwell_speed=dwell)

    def words(self, stops: int | None = None) -> str:
        """The routine in a car maker's words (with ``stops`` stops)."""
        n = self.stops if stops is None else stops
        return (f"{n} friction-only stop{'s' if n != 1 else ''} from {self.speed / KMH:g} km/h "
                f"at {self.decel:g} m/s^2, {self.interval:g} s apart")


@register_state
class TouchFaces:
    """A schedule state: each application starts with each face's pad touching (its
    smallest gap zero); see the module.

    Parameters
    ----------
    interface
        The schedule's interface (``x`` of the pad friction nodes).
    thickness
        The rotor's thickness (m; None: one face).
    """

    name: ClassVar[str] = "touch"

    def __init__(self, interface, thickness: float | None):
        n = interface.area.size
        out = (np.zeros(n, dtype=bool) if thickness is None
               else outboard_nodes(interface.x, thickness))
        self.faces = [m for m in (~out, out) if m.any()]

    def before(self, app, context: dict) -> dict | None:
        """The uniform gap per face that makes each face touch."""
        offset = np.asarray(context["offset"], dtype=float)
        gap = np.zeros(offset.size)
        for m in self.faces:
            gap[m] = -offset[m].min()
        return {"gap": gap}

    def step(self, pad_wear, rotor_wear) -> None:
        """Nothing: the wear within an application is the rows' to take."""

    def after(self, record) -> dict | None:
        """Nothing to report."""
        return None


class WarmStart:
    """An interface whose contact solves without a start set start from the last
    set it found (see the module); everything else is the wrapped interface's."""

    def __init__(self, interface, memory: dict | None = None):
        self._itf = interface
        self._memory = {"active": None} if memory is None else memory

    def __getattr__(self, name):
        return getattr(self._itf, name)

    def at_line_pressure(self, line_pressure: float) -> WarmStart:
        """The wrapped interface at ``line_pressure``, sharing the last set."""
        return WarmStart(self._itf.at_line_pressure(line_pressure), self._memory)

    def solve(self, offset, active, **kw):
        """The wrapped solve, from the last set when none is given."""
        last = self._memory["active"]
        if active is None and last is not None and last.shape == np.shape(offset):
            active = last
        sol = self._itf.solve(offset, active, **kw)
        self._memory["active"] = np.asarray(sol.active, dtype=bool).copy()
        return sol


def routine_run(model, interface, vehicle: Vehicle, rust: RustLayer, mu_iron: float,
                routine: Routine | list, *, numerics, gap0: np.ndarray | None = None,
                heat: RotorHeat | None = None, thermal=None) -> Run:
    """The run of a cleaning routine (:func:`brakewear.duty.run_schedule` runs it).

    Parameters
    ----------
    model, interface
        The brake and its interface (built: the rust layer is of it).
    vehicle
        The :class:`~brakewear.duty.Vehicle` as its controller runs the routine
        (:meth:`~brakewear.duty.Vehicle.with_friction_share`).
    rust
        The :class:`~brakewear.cleaning.rust.RustLayer` of ``interface``.
    mu_iron
        The friction coefficient on iron (the rust layer's factor multiplies it).
    routine
        A :class:`Routine`, or a schedule of registered applications.
    numerics
        The wear loop's :class:`~brakewear.wear.Numerics` (gap-offset update).
    gap0
        The gap per pad friction node the routine starts from (m): the bedded
        state and the static non-conformity.
    heat
        A :class:`~brakewear.cleaning.heat.RotorHeat` (the stops' thermal coning).
    thermal
        Full thermal coupling instead (a :class:`~brakewear.thermal.ThermalModel`).

    Returns
    -------
    Run
        With the schedule, the vehicle, the rust layer's laws and the states.
    """
    if heat is not None and thermal is not None:
        raise DutyError("routine_run: give heat (the reduced rotor's coning) or thermal "
                        "(the full model), not both")
    schedule = routine.schedule() if isinstance(routine, Routine) else list(routine)
    touch = TouchFaces(interface, model.geometry.rotor.thickness if model.full else None)
    states = (rust, touch) if heat is None else (rust, heat, touch)
    return Run(model, pad_law=rust.pad_law, rotor_law=rust.rotor_law, mu=mu_iron,
               schedule=schedule, vehicle=vehicle, numerics=numerics,
               interface=WarmStart(interface), thermal=thermal, initial_gap=gap0,
               states=states)
