"""Applications of the brake, each resolving itself against a vehicle and a brake.

An application is one of

* :class:`Stop` -- the vehicle slows from ``v0`` to ``v1`` at a given
  deceleration, or under a given line pressure (the deceleration then
  follows from the brake's torque); the speed falls linearly within it;
* :class:`Drag` -- constant speed and line pressure for a time;
* :class:`Dwell` -- no contact for a time (the bodies cool when thermal
  coupling is on);

or any class registered by its ``name`` (:func:`register_application`).
Each answers :class:`Application`: it checks itself within a schedule
(:meth:`Application.check`), names what it needs of a vehicle, and runs
itself on the brake of a schedule (:meth:`Application.run`: the line
pressure, speeds and energy it asks for, then the brake's wear history or
its cooling), so the schedule's runner asks nothing of its type.  A scene
file lists applications by kind (the class's ``name``) in ``[schedule]
applications``, each field in the unit of its key in :attr:`Application.keys`
(:func:`~brakewear.duty.kinds.application_from_table`).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np

from ..checks import check_plausible, user_units
from ..errors import DutyError
from ..registry import OptionKey
from ..wear.speed import ConstantSpeed, LinearSpeed
from .kinds import register_application
from .vehicle import G, _check, _finite, brake_torque, line_pressure_for_torque

logger = logging.getLogger(__name__)

__all__ = ["Application", "ApplicationRecord", "ScheduleCheck", "Stop", "Drag", "Dwell",
           "application_name", "stop_decelerations", "TABLE_SOURCE"]

#: One km/h in m/s.
KMH = 1.0 / 3.6

#: the ``source`` of the applications of a scene's ``[schedule]`` table
TABLE_SOURCE = "the [schedule]"


def application_name(app, index: int) -> str:
    """How messages name application ``index``: its index from 0 and, when it came from
    a file, where (``"application 3 (cycle.csv, rows 5-6)"``, ``"application 1 of the
    [schedule]"``)."""
    src = getattr(app, "source", "")
    return f"application {index}" + (f" of {src}" if src.startswith("the [") else
                                      f" ({src})" if src else "")


@dataclass(frozen=True)
class ScheduleCheck:
    """What an application is checked against within its schedule
    (:meth:`Application.check`).

    Attributes
    ----------
    vehicle
        The :class:`~brakewear.duty.Vehicle`, or None.
    mu, geometry
        The friction coefficient and the brake geometry (None: not known, the
        checks that need them wait for the run).
    index, where
        Its place in the schedule (from 0) and how messages name it
        (:func:`application_name`).
    since_start
        s from the last braked application's start to this one's start, where known.
    following
        The next application, or None.
    """

    vehicle: Any
    mu: float | None
    geometry: Any
    index: int
    where: str
    since_start: float | None = None
    following: Any = None


@dataclass
class ApplicationRecord:
    """What one application did (SI units; energies per face unless named otherwise)."""

    index: int
    kind: str                      # the application's name: "stop", "drag", "dwell", ...
    t_start: float                 # s, since the schedule's start
    duration: float                # s
    line_pressure: float = 0.0     # Pa
    decel: float | None = None     # m/s^2 (stops)
    v0: float | None = None        # m/s
    v1: float | None = None
    omega0: float = 0.0            # rad/s
    omega1: float = 0.0
    rotor_angle: float = 0.0       # rad
    r_eff: float | None = None     # m, at the start
    r_eff_mean: float | None = None  # m, over the rotor angle (the steps' start pressures)
    torque: float | None = None    # N m, at the start
    kinetic_J: float | None = None
    regenerated_J: float | None = None
    road_J: float | None = None    # taken by the road load (all of it: Vehicle.stop_energy's)
    propulsion_J: float | None = None  # added by the motor where the road load alone
    #                                    decelerates more than the stop (0 mostly)
    road_net_J: float | None = None    # road_J - propulsion_J: the road load's net part,
    #                                    kinetic = road_net + regenerated + friction
    target_face_J: float | None = None    # the vehicle's demand on each face
    friction_face_J: float = 0.0          # the model's dissipation per face (full model: mean)
    pad_volume_m3: float = 0.0            # worn in this application
    rotor_volume_m3: float = 0.0
    steps: int = 0
    pad_temperature_max: float | None = None     # K, pad face, at the end
    rotor_temperature_max: float | None = None   # K, rotor face (a rigid one's: the ambient)
    run_s: float = 0.0
    braked: bool = True            # the brake was applied (False: a pause, no contact)
    mu: float | None = None        # the friction coefficient it ran with
    pad_wear: np.ndarray | None = field(default=None, repr=False)    # cumulative, m
    rotor_wear: np.ndarray | None = field(default=None, repr=False)
    pressure: np.ndarray | None = field(default=None, repr=False)    # at the end, Pa
    active: np.ndarray | None = field(default=None, repr=False)
    #: thermal only: the face temperatures at the end and their peaks (C), the heat into
    #: and convected from each body (J) and the largest balance error of its steps
    #: (:class:`~brakewear.wear.records.HeatTally`)
    heat: dict | None = field(default=None, repr=False)
    #: what the run's schedule states reported, by kind (:mod:`brakewear.duty.states`)
    states: dict = field(default_factory=dict, repr=False)

    @property
    def torque_drift(self) -> float | None:
        """Relative difference of the model's friction work from the vehicle's demand."""
        if not self.target_face_J:
            return None
        return self.friction_face_J / self.target_face_J - 1.0


@runtime_checkable
class Application(Protocol):
    """One application of a schedule.

    Attributes
    ----------
    name : str
        Its kind in scene files (``kind = "stop"``) and records
        (``applications.csv``).
    keys : tuple of OptionKey
        Its fields as a scene file gives them: each
        :class:`~brakewear.registry.OptionKey`'s ``unit`` and ``scale`` (the SI
        value of one unit: km/h is ``1 / 3.6``).
    braked : bool
        Whether the brake is applied (a wear history runs).
    needs_vehicle : bool
        Whether it needs a :class:`~brakewear.duty.Vehicle` (a speed of the car).

    A dataclass field ``source`` (not compared), where it has one, says where it
    came from (a scene's ``[schedule]``, a drive cycle's rows): messages name it
    (:func:`application_name`).
    """

    name: ClassVar[str]
    keys: ClassVar[tuple[OptionKey, ...]]
    braked: ClassVar[bool]

    @property
    def needs_vehicle(self) -> bool: ...

    def check(self, ctx: ScheduleCheck) -> float | None:
        """Raise a :class:`DutyError` (starting with ``ctx.where``) unless it can run in
        its place of the schedule; return the time from the last braked start to its
        own end (None: not known before it runs)."""

    def check_scene(self, vehicle, index: int) -> None:
        """The scene's check against its ``[vehicle]``, naming scene keys."""

    def run(self, brake, index: int) -> ApplicationRecord:
        """Resolve itself against ``brake.vehicle`` and ``brake`` (the schedule's
        brake: its contact, ``since_start``) and run: ``brake.wear(speed, record)``
        for a braked application, ``brake.cool(record, omega)`` for a pause."""


@register_application
@dataclass(frozen=True)
class Stop:
    """Slow from ``v0`` to ``v1`` at a deceleration, or under a line pressure.

    Parameters
    ----------
    v0, v1
        The vehicle's speeds at the start and the end (m/s).
    decel
        The deceleration (m/s^2); or
    line_pressure
        The line pressure (Pa): the deceleration follows from the brake's torque.
    source
        Where the application comes from in the user's words (a scene's
        ``[schedule]``, a drive cycle's rows), named in messages; not compared.
    """

    v0: float
    v1: float = 0.0
    decel: float | None = None
    line_pressure: float | None = None
    source: str = field(default="", compare=False)

    name: ClassVar[str] = "stop"
    keys: ClassVar[tuple[OptionKey, ...]] = (
        OptionKey("v0", unit="km/h", scale=KMH), OptionKey("v1", unit="km/h", scale=KMH),
        OptionKey("decel", unit="m/s^2"), OptionKey("line_pressure", unit="MPa", scale=1e6))
    braked: ClassVar[bool] = True

    def __post_init__(self):
        _check("stop.v0", self.v0, _finite(self.v0) and 0 < self.v0 <= 100,
               "need 0 < v0 <= 100 m/s", "m/s")
        _check("stop.v1", self.v1, _finite(self.v1) and 0 <= self.v1 < self.v0,
               f"need 0 <= v1 < v0 = {self.v0:g} m/s", "m/s")
        if (self.decel is None) == (self.line_pressure is None):
            raise DutyError("a stop needs exactly one of decel (m/s^2) and line_pressure (Pa)")
        if self.decel is not None:
            _check("stop.decel", self.decel, _finite(self.decel) and self.decel > 0,
                   "need a deceleration > 0", "m/s^2")
        else:
            _check("stop.line_pressure", self.line_pressure,
                   _finite(self.line_pressure) and self.line_pressure > 0, "need > 0", "Pa")

    @property
    def needs_vehicle(self) -> bool:
        return True

    def check(self, ctx):
        vehicle, where, mu, geometry = ctx.vehicle, ctx.where, ctx.mu, ctx.geometry
        _check_plausible_pressure(self, where)
        if vehicle is None:
            raise DutyError(f"{where}: a stop needs a vehicle (mass, tyre radius, brake share)")
        if self.decel is not None:
            vehicle.check_deceleration(self.decel, f"{where}: deceleration")
            if not vehicle.stop_torque(self.v0, self.v1, self.decel) > 0:
                raise DutyError(f"{where}: at deceleration = {self.decel!r} m/s^2 the motor "
                                f"takes all the braking the road load leaves (regen_share = "
                                f"{vehicle.regen_share:g}): the modelled brake gives no torque")
            return (self.v0 - self.v1) / self.decel
        if mu is not None and geometry is not None:
            least = stop_decelerations(self, vehicle, mu, geometry)[0]
            limit = vehicle.tyre_mu * G
            if not least <= limit:
                raise DutyError(f"{where}: line_pressure = {self.line_pressure / 1e6:g} MPa is "
                                f"not allowed; it decelerates the vehicle by at least "
                                f"{least:.3g} m/s^2 (the least torque it can give: its whole "
                                f"pressure field at the pad's inner radius, "
                                f"{geometry.pad.inner_radius * 1e3:g} mm), beyond "
                                f"tyre_mu g = {limit:.3g} m/s^2 (what the tyres can give)")
            nxt = ctx.following
            if isinstance(nxt, Dwell) and nxt.from_start:
                self._check_interval(nxt, vehicle, mu, geometry, ctx.index + 1)
        return None

    def _check_interval(self, dwell, vehicle, mu: float, geometry, index: int) -> None:
        """A dwell from this stop's start (under a line pressure) outlasts the shortest
        the stop can be (the run checks it against the stop's own pressure field)."""
        shortest = (self.v0 - self.v1) / stop_decelerations(self, vehicle, mu, geometry)[1]
        if not dwell.duration > shortest:
            raise DutyError(f"{application_name(dwell, index)}: an interval of "
                            f"{dwell.duration:g} s (start to start) is not allowed; the stop "
                            f"before it ({self.v0 / KMH:.4g} to {self.v1 / KMH:.4g} km/h "
                            f"under {self.line_pressure / 1e6:g} MPa) lasts at least "
                            f"{shortest:.4g} s (its pressure field at the pad's outer radius, "
                            f"{geometry.pad.outer_radius * 1e3:g} mm); give a longer interval")

    def check_scene(self, vehicle, index):
        if self.decel is not None:
            vehicle.check_deceleration(self.decel, key="schedule.deceleration"
                                       if self.source == TABLE_SOURCE else
                                       f"{application_name(self, index)}: deceleration")

    def run(self, brake, index):
        vehicle = brake.vehicle
        rec = ApplicationRecord(index, self.name, 0.0, 0.0)
        if self.decel is not None:          # checked with the schedule (check_schedule)
            rec.torque = vehicle.stop_torque(self.v0, self.v1, self.decel)
            guess = line_pressure_for_torque(rec.torque, brake.mu, brake.clamp_area,
                                             brake.mean_radius)
            rec.line_pressure, rec.r_eff = brake.pressure_for_torque(rec.torque, guess)
            rec.decel = self.decel
        else:
            rec.line_pressure = self.line_pressure
            rec.r_eff = brake.r_eff(brake.solve(self.line_pressure).pressure, self.line_pressure)
            rec.torque = brake_torque(self.line_pressure, brake.mu, brake.clamp_area, rec.r_eff)
            energy = vehicle.stop_energy(self.v0, self.v1, torque=rec.torque)
            vehicle.check_deceleration(
                energy["decel_max"], f"{application_name(self, index)}: the deceleration of "
                                     f"line pressure {self.line_pressure / 1e6:g} MPa")
            # a linear speed profile with the stop's distance: its rotor angle and energy
            rec.decel = energy["decel"]
        rec.v0, rec.v1 = self.v0, self.v1
        rec.duration = (self.v0 - self.v1) / rec.decel
        rec.omega0, rec.omega1 = vehicle.rotor_speed(self.v0), vehicle.rotor_speed(self.v1)
        if self.decel is not None:
            energy = vehicle.stop_energy(self.v0, self.v1, rec.decel)
        rec.kinetic_J, rec.regenerated_J = energy["kinetic_J"], energy["regenerated_J"]
        rec.road_J, rec.propulsion_J = energy["road_J"], energy["propulsion_J"]
        rec.road_net_J = rec.road_J - rec.propulsion_J
        rec.target_face_J = energy["face_J"]
        return brake.wear(LinearSpeed(rec.omega0, rec.omega1, rec.duration), rec)


@register_application
@dataclass(frozen=True)
class Drag:
    """A constant line pressure for a time at a constant speed.

    Parameters
    ----------
    line_pressure
        Pa.
    duration
        s.
    speed
        The vehicle's speed (m/s); or, without a vehicle (a dynamometer),
    omega
        The rotor's speed (rad/s).
    source
        As :class:`Stop`'s.
    """

    line_pressure: float
    duration: float
    speed: float | None = None
    omega: float | None = None
    source: str = field(default="", compare=False)

    name: ClassVar[str] = "drag"
    keys: ClassVar[tuple[OptionKey, ...]] = (
        OptionKey("line_pressure", unit="MPa", scale=1e6), OptionKey("duration", unit="s"),
        OptionKey("speed", unit="km/h", scale=KMH), OptionKey("omega", unit="rad/s"))
    braked: ClassVar[bool] = True

    def __post_init__(self):
        _check("drag.line_pressure", self.line_pressure,
               _finite(self.line_pressure) and self.line_pressure > 0, "need > 0", "Pa")
        _check("drag.duration", self.duration, _finite(self.duration) and self.duration > 0,
               "need > 0", "s")
        if (self.speed is None) == (self.omega is None):
            raise DutyError("a drag needs exactly one of speed (m/s) and omega (rad/s)")
        v = self.speed if self.speed is not None else self.omega
        _check("drag.speed" if self.speed is not None else "drag.omega", v,
               _finite(v) and v > 0, "need > 0", "m/s" if self.speed is not None else "rad/s")

    @property
    def needs_vehicle(self) -> bool:
        return self.speed is not None

    def check(self, ctx):
        _check_plausible_pressure(self, ctx.where)
        if self.speed is not None and ctx.vehicle is None:
            raise DutyError(f"{ctx.where}: a drag at a vehicle speed needs a vehicle (or give "
                            "the rotor speed omega)")
        return self.duration

    def check_scene(self, vehicle, index):
        return None

    def run(self, brake, index):
        w = self.omega if self.omega is not None else brake.vehicle.rotor_speed(self.speed)
        rec = ApplicationRecord(index, self.name, 0.0, self.duration,
                                line_pressure=self.line_pressure, omega0=w, omega1=w,
                                v0=self.speed, v1=self.speed)
        rec.r_eff = brake.r_eff(brake.solve(self.line_pressure).pressure, self.line_pressure)
        rec.torque = brake_torque(self.line_pressure, brake.mu, brake.clamp_area, rec.r_eff)
        return brake.wear(ConstantSpeed(w), rec)


@register_application
@dataclass(frozen=True)
class Dwell:
    """No contact for a time: a pause, in which the bodies cool.

    A speed-dependent convection (:class:`~brakewear.thermal.SpeedConvection`)
    cools at the speed given; neither given: at rest.

    Parameters
    ----------
    duration
        s; with ``from_start``, until ``duration`` after the previous
        application's start (a stop's length is known only once the brake's
        torque is).
    from_start
        See ``duration``.
    speed
        The car drives on at this speed (m/s; needs a vehicle); or
    omega
        The rotor spins at this speed (rad/s).
    source
        As :class:`Stop`'s.
    """

    duration: float
    from_start: bool = False
    speed: float | None = None
    omega: float | None = None
    source: str = field(default="", compare=False)

    name: ClassVar[str] = "dwell"
    keys: ClassVar[tuple[OptionKey, ...]] = (
        OptionKey("duration", unit="s"), OptionKey("from_start", "bool"),
        OptionKey("speed", unit="km/h", scale=KMH), OptionKey("omega", unit="rad/s"))
    braked: ClassVar[bool] = False

    def __post_init__(self):
        _check("dwell.duration", self.duration, _finite(self.duration) and self.duration > 0,
               "need > 0", "s")
        if self.speed is not None and self.omega is not None:
            raise DutyError("a dwell takes at most one of speed (m/s) and omega (rad/s)")
        for key, unit in (("speed", "m/s"), ("omega", "rad/s")):
            v = getattr(self, key)
            if v is not None:
                _check(f"dwell.{key}", v, _finite(v) and v >= 0, "need >= 0", unit)

    @property
    def needs_vehicle(self) -> bool:
        return self.speed is not None

    def check(self, ctx):
        where, since_start = ctx.where, ctx.since_start
        if self.speed is not None and ctx.vehicle is None:
            raise DutyError(f"{where}: a dwell at a vehicle speed needs a vehicle")
        if self.from_start and since_start is not None:
            _check(f"{where}: dwell.duration", self.duration, self.duration > since_start,
                   f"a dwell from the previous application's start must outlast its "
                   f"{since_start:.4g} s", "s")
        return None if since_start is None or self.from_start else since_start + self.duration

    def check_scene(self, vehicle, index):
        return None

    def run(self, brake, index):
        duration = self.duration - brake.since_start if self.from_start else self.duration
        if duration <= 0:
            raise DutyError(f"{application_name(self, index)}: the interval of "
                            f"{self.duration:g} s is shorter than the application before it "
                            f"({brake.since_start:.4g} s)")
        omega = (self.omega if self.omega is not None else
                 self.speed / brake.vehicle.tyre_radius if self.speed is not None else 0.0)
        return brake.cool(ApplicationRecord(index, self.name, 0.0, duration), omega)


def stop_decelerations(app: Stop, vehicle, mu: float, geometry) -> tuple[float, float]:
    """The least and the largest deceleration (m/s^2) a stop under a line pressure can
    give at its start (where the road load is largest): its whole pressure field at
    the pad's inner, then outer radius."""
    pad = geometry.pad
    return tuple(vehicle.deceleration(brake_torque(app.line_pressure, mu, geometry.clamp_area,
                                                   r), app.v0)
                 for r in (pad.inner_radius, pad.outer_radius))


def _check_plausible_pressure(app, where: str) -> None:
    """A braked application's line pressure is plausible (checked in MPa)."""
    with user_units({f"{where}: line_pressure": ("MPa", 1e6, 0.0, None)}):
        check_plausible(f"{where}: line_pressure", app.line_pressure,
                        "environment.line_pressure", kind=DutyError)
