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
from types import SimpleNamespace

import numpy as np

from ..errors import ConvergenceError, DutyError, SolverError
from ..mesh.surface import face_nodes
from ..wear.records import HeatTally, thermal_state
from ..wear.run import Run
from ..wear.stepper import wear_history
from .applications import ApplicationRecord
from .schedule import check_schedule
from .states import check_states, state_changes
from .vehicle import FACES, effective_radius, line_pressure_for_torque

logger = logging.getLogger(__name__)

__all__ = ["run_schedule"]

#: Longest implicit-Euler step of the cooling in a dwell (s).
DWELL_STEP = 5.0


class _Brake:
    """The brake of a schedule, as its applications see it
    (:meth:`~brakewear.duty.Application.run`): its contact state between
    applications (``run``: the schedule's :class:`~brakewear.wear.Run`, its
    interface built), the vehicle, the time since the last braked application
    started, and the two things an application does to it: wear it
    (:meth:`wear`) or let it cool (:meth:`cool`)."""

    def __init__(self, run: Run, on_step=None):
        model, itf, initial_gap = run.model, run.interface, run.initial_gap
        self.run, self.model, self.itf, self.mu = run, model, itf, run.mu
        self.thermal = run.thermal
        self.vehicle, self.on_step = run.vehicle, on_step
        self.t = self.last_start = 0.0          # s: now, and the last braked start
        self.clamp_area = model.geometry.clamp_area     # one side's pistons together
        self.faces = FACES if getattr(model, "full", False) else 1    # friction faces modelled
        n = itf.area.size       # the initial gap's size is checked with the schedule
        self.gap0 = np.zeros(n) if initial_gap is None else np.asarray(initial_gap, dtype=float)
        self.pad_wear, self.rotor_wear = np.zeros(n), np.zeros(itf.rotor_area.size)
        self.active = None
        self.states = run.states
        self.base_mu = run.mu                   # the states' factors multiply it
        self.extra = np.zeros(n)                # the states' gap for this application

    @property
    def since_start(self) -> float:
        """s since the last braked application started (the schedule's start before any)."""
        return self.t - self.last_start

    @property
    def mean_radius(self) -> float:
        """The pad's area-weighted mean radius (m): a first guess of ``r_eff``."""
        return float(np.average(self.itf.r, weights=self.itf.area))

    def offset(self) -> np.ndarray:
        return self.gap0 + self.pad_wear + self.itf.W @ self.rotor_wear + self.extra

    def begin(self, app, index: int) -> None:
        """Ask the run's states (:mod:`brakewear.duty.states`) what ``app`` changes:
        its friction coefficient and its extra gap."""
        self.extra = np.zeros(self.extra.size)
        if not self.states:
            return
        context = {"index": index, "vehicle": self.vehicle, "mu": self.base_mu,
                   "offset": self.offset()}
        factor, self.extra = state_changes(self.states, app, context, self.extra.size)
        self.mu = self.base_mu * factor

    def end(self, rec: ApplicationRecord) -> None:
        """The states' reports on the application's record."""
        for s in self.states:
            report = s.after(rec)
            if report is not None:
                rec.states[s.name] = report
        self.extra = np.zeros(self.extra.size)
        self.mu = self.base_mu

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
                            max_iter: int = 80) -> tuple[float, float]:
        """Line pressure giving ``torque`` with the effective radius of its own
        pressure field: the root of ``h(p) = p - g(p)``, ``g(p)`` the pressure of
        the torque at ``p``'s radius.  Fixed-point steps ``p <- g(p)`` while they
        contract (the field moves little with the load), secant steps once they
        do not, always within the bracket the evaluated signs of ``h`` give, and
        bisection when a step leaves it or when the bracket has not halved in
        two steps (secant steps across a jump shorten one side only): a radius
        that jumps with the load (a pad rocking onto its other edge) is bracketed
        instead of oscillated around, and the bracket closes at least as fast as
        by bisection every other step."""
        p, lo, hi = guess, None, None        # (p, h(p)) with h < 0 and h > 0
        last = None                          # the previous (p, h)
        widths: list = []                    # the bracket's width after each step
        for _ in range(1, max_iter + 1):
            r = self.r_eff(self.solve(p).pressure, p)
            g = line_pressure_for_torque(torque, self.mu, self.clamp_area, r)
            h = p - g
            change = abs(h) / g
            if change <= rtol:
                return g, r
            if h < 0:
                lo = (p, h) if lo is None or p > lo[0] else lo
            else:
                hi = (p, h) if hi is None or p < hi[0] else hi
            nxt = g                          # the fixed-point step
            if last is not None and abs(h) > 0.5 * abs(last[1]):
                # not contracting: the secant of the last two evaluations
                dh = h - last[1]
                nxt = p - h * (p - last[0]) / dh if dh != 0 else g
            if lo is not None and hi is not None:
                a, b = lo[0], hi[0]
                if abs(b - a) <= rtol * max(abs(a), abs(b)):
                    # the bracket has closed on a jump of the radius: the pressure where
                    # the torque crosses its target, to the tolerance
                    return 0.5 * (a + b), r
                width = abs(b - a)
                if not min(a, b) < nxt < max(a, b) or (len(widths) >= 2
                                                       and width > 0.5 * widths[-2]):
                    nxt = 0.5 * (a + b)
                widths.append(width)
            last = (p, h)
            p = nxt
        raise ConvergenceError(f"the line pressure for a brake torque of {torque:.4g} N m did "
                               f"not settle in {max_iter} contact solves (last {p:.6g} Pa, "
                               f"r_eff {r:.6g} m, last change {change:.2e} of it, tolerance "
                               f"{rtol:.0e})",
                               figures={"iterations": max_iter, "line_pressure": p,
                                        "relative_change": change, "r_eff": r})

    def wear(self, speed, rec: ApplicationRecord) -> ApplicationRecord:
        """Run the braked application ``rec`` (its line pressure and duration
        resolved) at ``speed`` (a speed profile): one wear history from the wear
        so far; ``rec`` completed with its friction work, wear and heat."""
        self.last_start = self.t
        rec.rotor_angle = speed.angle(rec.duration)
        run = self.run.at(line_pressure=rec.line_pressure, omega=speed, duration=rec.duration,
                          initial_gap=self.offset(), schedule=(), vehicle=None, mu=self.mu,
                          states=())
        last, tally, r_sum = None, HeatTally(), 0.0
        for s in wear_history(run):
            rec.friction_face_J += s.friction_work / self.faces
            r_sum += self.r_eff(s.pressure, rec.line_pressure) * (speed.angle(s.time)
                                                                  - speed.angle(s.time - s.dt))
            tally.add(s, s.dt)
            pad_w, rot_w = self.pad_wear + s.pad_wear, self.rotor_wear + s.rotor_wear
            for state in self.states:
                state.step(pad_w, rot_w)
            if self.on_step is not None:
                self.on_step(rec, s, pad_w, rot_w)
            last = s
        self.pad_wear = self.pad_wear + last.pad_wear
        self.rotor_wear = self.rotor_wear + last.rotor_wear
        self.active = last.active_end
        rec.pad_volume_m3, rec.rotor_volume_m3 = last.pad_volume, last.rotor_volume
        rec.steps = last.step
        rec.r_eff_mean = r_sum / rec.rotor_angle
        rec.pressure, rec.active = last.pressure_end, last.active_end
        if run.thermal is not None:
            _heat(rec, last, tally)
        if rec.target_face_J is None:        # a drag: the model's torque over its angle
            rec.target_face_J = rec.torque * rec.rotor_angle / FACES
        return rec

    def cool(self, rec: ApplicationRecord, omega: float) -> ApplicationRecord:
        """A pause ``rec`` (no contact) of ``rec.duration``, the rotor turning at
        ``omega`` (rad/s): the bodies cool (with thermal coupling)."""
        rec.braked = False
        rec.omega0 = rec.omega1 = omega
        thermal = self.run.thermal
        if thermal is not None:
            thermal.set_speed(omega)
            n = int(np.ceil(rec.duration / DWELL_STEP))
            tally = HeatTally()
            for _ in range(n):
                thermal.step(np.zeros(self.itf.area.size), rec.duration / n)
                last = SimpleNamespace(**thermal_state(thermal))
                tally.add(last, rec.duration / n)
            _heat(rec, last, tally)
        return rec


def run_schedule(run: Run, *, on_step=None):
    """Run a schedule of applications (:class:`Stop`, :class:`Drag`, :class:`Dwell`).

    Parameters
    ----------
    run : brakewear.wear.Run
        A run with a ``schedule`` (and the ``vehicle`` its stops need).  Of
        the run: the wear laws and friction coefficient as for
        :func:`~brakewear.wear.wear_history` (``mu`` a number: the torque
        equation needs it); the wear loop's
        :class:`~brakewear.wear.Numerics` (gap-offset update only); the
        interface (default: FE contact, built at the first braked
        application's line pressure); thermal coupling (heat in the
        applications, cooling in the dwells, temperatures carried over); the
        extra gap per pad friction node before any wear (m): coning, taper;
        the schedule states (:mod:`brakewear.duty.states`), asked before and
        after each application and told of each wear step: the friction
        coefficient of each application and an extra gap come from them,
        their reports go to ``record.states``.
    on_step
        Called as ``on_step(record, step, pad_wear, rotor_wear)`` with each
        accepted :class:`~brakewear.wear.WearStep` of a braked application
        and the wear since the schedule's start (e.g. to update a
        :class:`~brakewear.cleaning.corrosion.CorrodedRotor`).

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
        value named); a state that is not a registered schedule state.
    """
    if not isinstance(run, Run):
        raise DutyError(f"run = {type(run).__name__}: need a brakewear.Run with a schedule "
                        "(run_schedule(Run(model, pad_law=..., mu=..., schedule=[...], "
                        "vehicle=...)))")
    apps = _check_run(run.model, run.schedule, run.mu, run.vehicle, run.numerics,
                      run.interface, run.initial_gap)
    check_states(run.states)
    return _run(run, apps, on_step)


def _check_run(model, schedule, mu, vehicle, numerics, interface, initial_gap) -> list:
    """The checks of a schedule's run; its applications as a list."""
    if numerics.update != "gap":
        raise DutyError(f"numerics.update = {numerics.update!r}: schedules run in gap-offset "
                        "mode (update = 'gap'), which carries the wear from one application "
                        "to the next exactly")
    if not (isinstance(mu, (int, float)) and np.isfinite(mu) and mu > 0):
        raise DutyError(f"mu = {mu!r} is not allowed; a schedule needs a friction "
                        "coefficient > 0 (the brake's torque)")
    apps = check_schedule(schedule, vehicle, mu=mu, geometry=getattr(model, "geometry", None))
    _check_initial_gap(model, None if isinstance(interface, str) else interface, initial_gap)
    return apps


def _run(run: Run, apps, on_step):
    """The applications of a checked schedule, one record each (:func:`run_schedule`)."""
    first = next((a for a in apps if a.braked), None)
    p_ref = (first.line_pressure if getattr(first, "line_pressure", None) else 1e6)
    brake = _Brake(run.resolved(p_ref), on_step)
    for i, app in enumerate(apps):
        t0 = _time.perf_counter()
        with SolverError.located(application=f"{i} ({app.name})"):
            brake.begin(app, i)
            rec = app.run(brake, i)
            rec.mu = brake.mu
            brake.end(rec)
        rec.t_start, rec.run_s = brake.t, _time.perf_counter() - t0
        rec.pad_wear, rec.rotor_wear = brake.pad_wear.copy(), brake.rotor_wear.copy()
        brake.t += rec.duration
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


def _heat(rec: ApplicationRecord, last, tally: HeatTally) -> None:
    """The thermal figures of ``rec``: the face temperatures of its ``last`` step
    (the fields of :func:`~brakewear.wear.records.thermal_state`) and its tally."""
    rec.pad_temperature_max = last.pad_temperature_max
    rec.rotor_temperature_max = last.rotor_temperature_max
    rec.heat = tally.columns()
