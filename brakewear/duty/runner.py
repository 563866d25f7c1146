"""Run a schedule of applications on a brake: wear, heat and energy per application.

Each braked application is one :func:`brakewear.wear.wear_history` in
gap-offset mode, started from the wear of the ones before (their worn
depths enter as the gap, which is exact in gap-offset mode: the contact
problem depends on the wear only through the gap).  The thermal model, when
given, carries its temperatures from one application to the next and cools
through the dwells.

Per application: the line pressure and the deceleration (one from the other
through the vehicle and the brake's torque, ``T = 2 mu p_line A_clamp
r_eff`` with the effective radius of the pressure field at the
application's start, times the share of the clamp force that reaches the
faces where the caliper's friction takes some; solved with the thermal load
of the temperatures it starts from), the rotor speeds, the kinetic energy,
the part regenerated, the friction work the vehicle asks of each face and
the one the model dissipated (the steps' ``friction_work``: ``mu sum(p A r)
Delta theta`` at each step's start pressure, the heat the thermal model
takes in; in the full
model the mean of its two faces), the worn volumes (of every modelled pad).
The line pressure is held over an application, so the two friction works
differ by how much the effective radius moves within it: ``torque_drift`` is
``r_eff_mean / r_eff - 1`` (docs/duty.md).
"""
from __future__ import annotations

import logging
import time as _time
from dataclasses import dataclass, field
from types import SimpleNamespace

import numpy as np

from ..errors import ConvergenceError, DutyError, SolverError
from ..interfaces.fe import FEInterface
from ..wear.numerics import Numerics
from ..wear.records import HeatTally, thermal_state
from ..wear.speed import ConstantSpeed, LinearSpeed
from ..wear.stepper import wear_history
from ..mesh.surface import face_nodes
from .schedule import Drag, Dwell, Stop, application_name, check_schedule
from .vehicle import (FACES, Vehicle, brake_torque, effective_radius,
                      line_pressure_for_torque)

logger = logging.getLogger(__name__)

__all__ = ["ApplicationRecord", "run_schedule"]


@dataclass
class ApplicationRecord:
    """What one application did (SI units; energies per face unless named otherwise)."""

    index: int
    kind: str                      # "stop", "drag", "dwell"
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
    road_J: float | None = None    # taken by the road load (less what the motor drove)
    target_face_J: float | None = None    # the vehicle's demand on each face
    friction_face_J: float = 0.0          # the model's dissipation per face (full model: mean)
    pad_volume_m3: float = 0.0            # worn in this application
    rotor_volume_m3: float = 0.0
    steps: int = 0
    pad_temperature_max: float | None = None     # K, pad face, at the end
    rotor_temperature_max: float | None = None   # K, rotor face (a rigid one's: the ambient)
    run_s: float = 0.0
    pad_wear: np.ndarray | None = field(default=None, repr=False)    # cumulative, m
    rotor_wear: np.ndarray | None = field(default=None, repr=False)
    pressure: np.ndarray | None = field(default=None, repr=False)    # at the end, Pa
    active: np.ndarray | None = field(default=None, repr=False)
    #: thermal only: the face temperatures at the end and their peaks (C), the heat into
    #: and convected from each body (J) and the largest balance error of its steps
    #: (:class:`~brakewear.wear.records.HeatTally`)
    heat: dict | None = field(default=None, repr=False)

    @property
    def torque_drift(self) -> float | None:
        """Relative difference of the model's friction work from the vehicle's demand."""
        if not self.target_face_J:
            return None
        return self.friction_face_J / self.target_face_J - 1.0


class _Brake:
    """The brake's contact state between applications."""

    def __init__(self, model, itf, mu, initial_gap, thermal=None):
        self.model, self.itf, self.mu, self.thermal = model, itf, mu, thermal
        self.clamp_area = model.geometry.clamp_area     # one side's pistons together
        self.faces = FACES if getattr(model, "full", False) else 1    # friction faces modelled
        n = itf.area.size       # the initial gap's size is checked with the schedule
        self.gap0 = np.zeros(n) if initial_gap is None else np.asarray(initial_gap, dtype=float)
        self.pad_wear, self.rotor_wear = np.zeros(n), np.zeros(itf.rotor_area.size)
        self.active = None

    def offset(self) -> np.ndarray:
        return self.gap0 + self.pad_wear + self.itf.W @ self.rotor_wear

    def solve(self, line_pressure):
        # with the thermal load of the current temperatures, as the application's
        # first step solves it: the torque equation's r_eff is that of its start
        load = None if self.thermal is None else self.thermal.thermal_load()
        sol = self.itf.at_line_pressure(line_pressure).solve(self.offset(), self.active,
                                                              mu=self.mu, load=load)
        self.active = sol.active
        return sol

    def r_eff(self, pressure, line_pressure: float) -> float:
        """The radius of ``T = 2 mu p_line A_clamp r_eff``: the friction radius of the
        pressure field times the share of the clamp force its faces carry (1 but
        for what the caliper's own friction takes, :class:`~brakewear.CaliperInterface`)."""
        load = float((np.maximum(pressure, 0.0) * self.itf.area).sum())
        share = load / (self.faces * line_pressure * self.clamp_area)
        return effective_radius(pressure, self.itf.area, self.itf.r) * share

    def pressure_for_torque(self, torque: float, guess: float, rtol: float = 1e-10,
                            max_iter: int = 30) -> tuple[float, float]:
        """Line pressure giving ``torque`` with the effective radius of its own
        pressure field (a fixed point: the field moves little with the load)."""
        p = guess
        for _ in range(max_iter):
            r = self.r_eff(self.solve(p).pressure, p)
            p_new = line_pressure_for_torque(torque, self.mu, self.clamp_area, r)
            change = abs(p_new - p) / p_new
            if change <= rtol:
                return p_new, r
            p = p_new
        raise ConvergenceError(f"the line pressure for a brake torque of {torque:.4g} N m did "
                               f"not settle in {max_iter} contact solves (last {p:.6g} Pa, "
                               f"r_eff {r:.6g} m, last change {change:.2e} of it, tolerance "
                               f"{rtol:.0e})",
                               figures={"iterations": max_iter, "line_pressure": p,
                                        "relative_change": change, "r_eff": r})


def _resolve(app, vehicle: Vehicle | None, brake: _Brake, index: int):
    """(line pressure, speed profile, duration, record) of a braked application."""
    rec = ApplicationRecord(index, "stop" if isinstance(app, Stop) else "drag", 0.0, 0.0)
    if isinstance(app, Drag):
        w = app.omega if app.omega is not None else vehicle.rotor_speed(app.speed)
        rec.line_pressure, rec.duration, rec.omega0 = app.line_pressure, app.duration, w
        rec.omega1, rec.v0 = w, app.speed
        rec.v1 = app.speed
        rec.r_eff = brake.r_eff(brake.solve(app.line_pressure).pressure, app.line_pressure)
        rec.torque = brake_torque(app.line_pressure, brake.mu, brake.clamp_area, rec.r_eff)
        return ConstantSpeed(w), rec
    if app.decel is not None:          # checked with the schedule (check_schedule)
        rec.torque = vehicle.stop_torque(app.v0, app.v1, app.decel)
        guess = line_pressure_for_torque(rec.torque, brake.mu, brake.clamp_area,
                                         float(np.average(brake.itf.r, weights=brake.itf.area)))
        rec.line_pressure, rec.r_eff = brake.pressure_for_torque(rec.torque, guess)
        rec.decel = app.decel
    else:
        rec.line_pressure = app.line_pressure
        rec.r_eff = brake.r_eff(brake.solve(app.line_pressure).pressure, app.line_pressure)
        rec.torque = brake_torque(app.line_pressure, brake.mu, brake.clamp_area, rec.r_eff)
        energy = vehicle.stop_energy(app.v0, app.v1, torque=rec.torque)
        vehicle.check_deceleration(
            energy["decel_max"], f"{application_name(app, index)}: the deceleration of line "
                                 f"pressure {app.line_pressure / 1e6:g} MPa")
        # a linear speed profile with the stop's distance: its rotor angle and energy
        rec.decel = energy["decel"]
    rec.v0, rec.v1 = app.v0, app.v1
    rec.duration = (app.v0 - app.v1) / rec.decel
    rec.omega0, rec.omega1 = vehicle.rotor_speed(app.v0), vehicle.rotor_speed(app.v1)
    if app.decel is not None:
        energy = vehicle.stop_energy(app.v0, app.v1, rec.decel)
    rec.kinetic_J, rec.regenerated_J = energy["kinetic_J"], energy["regenerated_J"]
    rec.road_J = energy["road_J"] - energy["propulsion_J"]
    rec.target_face_J = energy["face_J"]
    return LinearSpeed(rec.omega0, rec.omega1, rec.duration), rec


def run_schedule(model, schedule, pad_law, rotor_law=None, mu: float = 0.4, *,
                 vehicle: Vehicle | None = None, numerics: Numerics | None = None,
                 interface: FEInterface | None = None, thermal=None,
                 initial_gap: np.ndarray | None = None, on_step=None):
    """Run ``schedule`` (a list of :class:`Stop`, :class:`Drag`, :class:`Dwell`) on the brake.

    Parameters
    ----------
    model
        A :class:`brakewear.model.BrakeModel`.
    schedule
        The applications, in order (:mod:`brakewear.duty.schedule`).
    pad_law, rotor_law, mu
        Wear laws and friction coefficient, as for :func:`~brakewear.wear.wear_history`
        (``mu`` a number: the torque equation needs it).
    vehicle
        The :class:`Vehicle` (needed by stops and by drags given a vehicle speed).
    numerics
        The wear loop's :class:`~brakewear.wear.Numerics` (gap-offset update only).
    interface
        An :class:`~brakewear.interfaces.FEInterface` of ``model`` (default: built).
    thermal
        A :class:`brakewear.thermal.ThermalModel` of ``model``: heat in the
        applications, cooling in the dwells, temperatures carried over.
    initial_gap
        Extra gap per pad friction node before any wear (m): coning, taper.
    on_step
        Called as ``on_step(record, step, pad_wear, rotor_wear)`` with each
        accepted :class:`~brakewear.wear.WearStep` of a braked application
        and the wear since the schedule's start (e.g. to update a
        :class:`~brakewear.cleaning.CorrodedRotor`).

    Returns
    -------
    iterator of ApplicationRecord
        One per application, with the cumulative wear and the end pressure;
        each application runs when its record is asked for.

    Raises
    ------
    DutyError
        At the call, before the interface is built or anything is solved: a
        bad numerics, ``mu`` or initial gap, or any application of the schedule
        that cannot run (:func:`~brakewear.duty.check_schedule`: its index and
        value named).
    """
    numerics = Numerics() if numerics is None else numerics
    if numerics.update != "gap":
        raise DutyError(f"numerics.update = {numerics.update!r}: schedules run in gap-offset "
                        "mode (update = 'gap'), which carries the wear from one application "
                        "to the next exactly")
    if not (isinstance(mu, (int, float)) and np.isfinite(mu) and mu > 0):
        raise DutyError(f"mu = {mu!r} is not allowed; a schedule needs a friction "
                        "coefficient > 0 (the brake's torque)")
    apps = check_schedule(schedule, vehicle, mu=mu, geometry=getattr(model, "geometry", None))
    _check_initial_gap(model, interface, initial_gap)
    return _run(model, apps, pad_law, rotor_law, mu, vehicle, numerics, interface, thermal,
                initial_gap, on_step)


def _run(model, apps, pad_law, rotor_law, mu, vehicle, numerics, interface, thermal,
         initial_gap, on_step):
    """The applications of a checked schedule, one record each (:func:`run_schedule`)."""
    first = next((a for a in apps if not isinstance(a, Dwell)), None)
    p_ref = (first.line_pressure if getattr(first, "line_pressure", None) else 1e6)
    itf = FEInterface(model, p_ref, mu, numerics.tol) if interface is None else interface
    brake = _Brake(model, itf, mu, initial_gap, thermal)
    t, last_start = 0.0, 0.0
    for i, app in enumerate(apps):
        t0 = _time.perf_counter()
        with SolverError.located(application=f"{i} ({type(app).__name__.lower()})"):
            if isinstance(app, Dwell):
                rec = _dwell(app, i, t, last_start, thermal, brake.itf.area.size, vehicle)
            else:
                last_start = t
                rec = _braked(app, i, t, model, brake, vehicle, pad_law, rotor_law, numerics,
                              thermal, on_step)
        rec.t_start, rec.run_s = t, _time.perf_counter() - t0
        rec.pad_wear, rec.rotor_wear = brake.pad_wear.copy(), brake.rotor_wear.copy()
        t += rec.duration
        logger.info("application %d (%s): %.3g s, %.3g MPa, friction %.4g J per face",
                    i, rec.kind, rec.duration, rec.line_pressure / 1e6, rec.friction_face_J)
        yield rec


def _check_initial_gap(model, interface, initial_gap) -> None:
    """Refuse an initial gap that is not one finite value per pad friction node."""
    if initial_gap is None:
        return
    gap = np.asarray(initial_gap, dtype=float)
    n = (interface.area.size if interface is not None else
         face_nodes(model.meshes["pad"], "friction").size)
    if gap.shape != (n,) or not np.all(np.isfinite(gap)):
        raise DutyError(f"initial_gap: {gap.size} value(s) of shape {gap.shape}; need {n} "
                        "finite values (m), one per pad friction node")


#: Longest implicit-Euler step of the cooling in a dwell (s).
DWELL_STEP = 5.0


def _dwell(app: Dwell, i: int, t: float, last_start: float, thermal,
           n_pad: int, vehicle) -> ApplicationRecord:
    duration = app.duration - (t - last_start) if app.from_start else app.duration
    if duration <= 0:
        raise DutyError(f"{application_name(app, i)}: the interval of {app.duration:g} s is "
                        f"shorter than the application before it ({t - last_start:.4g} s)")
    rec = ApplicationRecord(i, "dwell", t, duration)
    if thermal is not None:
        omega = (app.omega if app.omega is not None else
                 app.speed / vehicle.tyre_radius if app.speed is not None else 0.0)
        thermal.set_speed(omega)
        n = int(np.ceil(duration / DWELL_STEP))
        tally = HeatTally()
        for _ in range(n):
            thermal.step(np.zeros(n_pad), duration / n)
            last = SimpleNamespace(**thermal_state(thermal))
            tally.add(last, duration / n)
        _heat(rec, last, tally)
    return rec


def _heat(rec: ApplicationRecord, last, tally: HeatTally) -> None:
    """The thermal figures of ``rec``: the face temperatures of its ``last`` step
    (the fields of :func:`~brakewear.wear.records.thermal_state`) and its tally."""
    rec.pad_temperature_max = last.pad_temperature_max
    rec.rotor_temperature_max = last.rotor_temperature_max
    rec.heat = tally.columns()


def _braked(app, i, t, model, brake: _Brake, vehicle, pad_law, rotor_law, numerics, thermal,
            on_step) -> ApplicationRecord:
    speed, rec = _resolve(app, vehicle, brake, i)
    rec.rotor_angle = speed.angle(rec.duration)
    itf = brake.itf.at_line_pressure(rec.line_pressure)
    last, tally, r_sum = None, HeatTally(), 0.0
    for s in wear_history(model, rec.line_pressure, speed, rec.duration, pad_law, rotor_law,
                          brake.mu, numerics=numerics, interface=itf, thermal=thermal,
                          initial_gap=brake.offset()):
        rec.friction_face_J += s.friction_work / brake.faces
        r_sum += brake.r_eff(s.pressure, rec.line_pressure) * (speed.angle(s.time)
                                                               - speed.angle(s.time - s.dt))
        tally.add(s, s.dt)
        if on_step is not None:
            on_step(rec, s, brake.pad_wear + s.pad_wear, brake.rotor_wear + s.rotor_wear)
        last = s
    brake.pad_wear = brake.pad_wear + last.pad_wear
    brake.rotor_wear = brake.rotor_wear + last.rotor_wear
    brake.active = last.active_end
    rec.pad_volume_m3, rec.rotor_volume_m3 = last.pad_volume, last.rotor_volume
    rec.steps = last.step
    rec.r_eff_mean = r_sum / rec.rotor_angle
    rec.pressure, rec.active = last.pressure_end, last.active_end
    if thermal is not None:
        _heat(rec, last, tally)
    if rec.target_face_J is None:        # a drag: the model's torque over its angle
        rec.target_face_J = rec.torque * rec.rotor_angle / FACES
    return rec
