"""The wear loop: contact -> pressure -> wear of pad and rotor -> new gap -> ...

:func:`wear_history` is a generator of :class:`WearStep` records.  Each step

1. takes the pressure the last step left (:class:`~brakewear.wear.WearState`);
2. chooses its length (:class:`~brakewear.wear.StepControl`);
3. wears pad and rotor over it: the explicit scheme with the starting pressure,
   the implicit (backward Euler) one with the end pressure, solved as contact
   through the step's wear compliance of both surfaces (``implicit_pad``: the
   pad's); the rotor wears by the revolution average of its rings;
4. solves the contact of the worn state (the :class:`~brakewear.interfaces.Interface`),
   with the thermal load when coupled, and accepts the step or retries it smaller;
5. in geometry-update mode moves the worn faces (:class:`~brakewear.motion.brake.BrakeMotion`),
   which gives a new model, and solves the contact of the moved geometry.

In *gap-offset* mode the meshes stay, and the worn depths of pad and rotor
are added to the contact gap (valid while wear is far below the element size).
"""
from __future__ import annotations

import logging
import os
import time as _time
from collections.abc import Iterator

import numpy as np

from ..errors import (
    ActiveSetError,
    ContactLostError,
    ConvergenceError,
    SolverError,
    StepSizeError,
    WearError,
)
from ..interfaces import StepCompliance
from ..laws.base import friction_power
from ..mesh.rings import RingAverage, ring_coupling
from .bounds import check_explicit_step, check_run_bounds
from .control import StepControl
from .limits import WearLimits, check_temperature
from .nodal import NodalLaws
from .records import WearStep, thermal_state
from .run import Run
from .state import WearState, check_fingerprint, fingerprint

logger = logging.getLogger(__name__)

__all__ = ["WearStep", "wear_history", "check_resume"]


def wear_history(run: Run, *, checkpoint: str | os.PathLike | None = None, every: int = 10,
                 resume: bool = False) -> Iterator[WearStep]:
    """Run a wear history of the brake under constant line pressure.

    Parameters
    ----------
    run : Run
        A drag: the model, its line pressure, speed and duration, the laws,
        the interface, the thermal coupling, the initial gap, the limits and
        the numerics (:class:`~brakewear.wear.Run`).
    checkpoint : str or os.PathLike, optional
        ``.npz`` file written every ``every`` accepted steps (and at the end),
        each time once the step has been yielded and the caller has asked for
        the next (so that whatever the caller records of a step is written
        before a checkpoint past it).
    every : int
        Accepted steps between checkpoints.
    resume : bool
        Continue from ``checkpoint`` (with a freshly built model), after
        checking that every input is the one it was written with
        (:meth:`Run.settings`, :mod:`brakewear.wear.state`).

    Yields
    ------
    WearStep
        One record per accepted step.

    Notes
    -----
    How the loop takes the run's parts:

    * speed: each step runs at its mean speed, so wear and heat are
      integrated exactly over ``omega(t)`` (:mod:`brakewear.wear.speed`);
    * wear laws: ``k(p, v, T)`` per node, taken at the start of each step
      (:mod:`brakewear.wear.nodal`); ``rotor_law=None``: the rotor does not
      wear;
    * friction: a number, or a law ``mu(p, v, T)`` at each pad node, updated
      every step (a law of temperature needs thermal coupling);
    * thermal coupling: staggered, one thermal update per step: the frictional
      heat of the step's starting pressure heats the bodies over ``dt``
      (implicit Euler), then the contact is solved with the thermal-strain
      load of the new temperatures, and the wear laws use ``k(T)`` at the pad
      face and the rotor under it; its state goes into the checkpoints;
    * initial gap: extra gap (m) at each pad friction node before any wear (a
      non-conformal start: coning, taper, thickness variation, or the worn
      state ``pad_wear + W @ rotor_wear`` of an earlier history); it never
      wears;
    * limits: the step that wears a surface past its limit is yielded, then
      :class:`~brakewear.errors.WornThroughError` is raised (naming the time,
      the node and the depth); with ``update = "geometry"`` the meshes are not
      moved by that step.
    """
    loop = _checked_loop(run, checkpoint, every, resume)
    run, duration = loop.run, loop.run.duration
    loop.stability_ratio = check_run_bounds(run)
    control = StepControl(loop.numerics, duration, loop.dh_limit(), loop.speed, loop.A_pad)
    prints = loop.fingerprint()
    n_pad, n_rot = loop.A_pad.size, loop.A_rot.size
    extra: dict = {}
    if resume:
        state, extra = WearState.load(checkpoint, prints, n_pad, n_rot,
                                      run.model.geometry.units)
    else:
        state = WearState.fresh(n_pad, n_rot, control.initial_dt())
    with SolverError.located(step=f"{state.step} (the contact solve of the start)"):
        first_s = loop.start(state, extra)
    while state.time < duration * (1 - 1e-12):
        t_before = state.time
        with SolverError.located(step=state.step + 1, t=f"{t_before:.6g} s"):
            record = loop.step(state, control)
            control.check_progress(state.step, t_before, state.time)
        if first_s is not None:       # the first solve of a fresh run counts in step 1
            record.contact_solves += 1
            record.solve_s += first_s
            first_s = None
        # the step is yielded before it is checkpointed: what the caller writes of it
        # (a history row) is on disk before a checkpoint that is past it
        # (a step that wore a surface through is not checkpointed: a resume ends there again)
        yield record
        if loop.worn is not None:
            raise loop.worn
        if checkpoint is not None and (state.step % every == 0
                                       or state.time >= duration * (1 - 1e-12)):
            state.save(checkpoint, prints, loop.thermal.state_arrays() if loop.thermal else None)


def check_resume(run: Run, *, checkpoint: str | os.PathLike, every: int = 10) -> None:
    """The check :func:`wear_history` makes before it resumes, without running.

    Refuses ``checkpoint`` (a :class:`~brakewear.errors.WearError` naming what
    changed) unless it was written with the inputs of ``run``.  A run that has
    already finished is checked this way before it is reported as done.

    Parameters
    ----------
    run : Run
        The drag to be resumed.
    checkpoint : str or os.PathLike
        Its checkpoint file.
    every : int
        Accepted steps between checkpoints (checked as :func:`wear_history` does).
    """
    loop = _checked_loop(run, checkpoint, every, True)
    check_fingerprint(checkpoint, loop.fingerprint(), loop.model.geometry.units)


def _checked_loop(run: Run, checkpoint, every, resume) -> _WearLoop:
    """The runner's own inputs checked, and the loop of ``run`` (a drag)."""
    if not isinstance(run, Run):
        raise WearError(f"run = {type(run).__name__}: need a brakewear.Run (the model, the "
                        "load, the laws and the numerics in one object: "
                        "wear_history(Run(model, line_pressure, omega, duration, pad_law, ...)))")
    if run.schedule:
        raise WearError("this Run is a schedule; run it with brakewear.duty.run_schedule")
    if resume and checkpoint is None:
        raise WearError("resume=True needs a checkpoint file")
    if resume and not os.path.exists(checkpoint):
        raise WearError(f"resume=True but the checkpoint {checkpoint} does not exist")
    if isinstance(every, bool) or int(every) != every or every < 1:
        raise WearError(f"every = {every!r} is not allowed; need a whole number >= 1")
    return _WearLoop(run.resolved())


class _WearLoop:
    """The parts of one history that do not change from step to step (laws,
    speeds, areas) and the ones the loop replaces (the model and its interface
    after a geometry update, the thermal load and mu(T) of the temperatures)."""

    def __init__(self, run: Run):
        model, numerics = run.model, run.numerics
        self.run, self.model, self.line_pressure, self.speed = run, model, run.line_pressure, \
            run.speed
        self.omega = self.speed.at(0.0)          # the speed of the step being taken
        self.limits = (WearLimits.for_model(model, update=numerics.update)
                       if run.limits is None else run.limits)
        self.worn = None
        self.stability_ratio = 1.0     # the sharp explicit bound over the row-sum one
        mu_law = run.mu_law
        self.pad_law, self.rotor_law, self.mu_law = run.pad_law, run.rotor_law, mu_law
        self.mu = 0.0 if mu_law is not None else float(run.mu)
        self.laws = NodalLaws(run.pad_law, run.rotor_law, mu_law, self.mu)
        self.numerics, self.thermal = numerics, run.thermal
        self.itf = run.interface
        self.motion = None
        if numerics.update == "geometry":
            from ..motion.brake import BrakeMotion
            self.motion = BrakeMotion(model)
        self.A_pad, self.ring, self.A_rot = self.itf.area, self.itf.ring, self.itf.rotor_area
        self.W = self.itf.W
        self._rings = None          # the rings' coupling of an implicit step, built once
        self.ring_rate = RingAverage(self.W, self.ring, self.A_rot)    # rotor_wear_rate
        initial_gap = run.initial_gap
        if initial_gap is not None and np.shape(initial_gap) != self.A_pad.shape:
            raise WearError(f"initial_gap has {np.size(initial_gap)} values; the pad has "
                            f"{self.A_pad.size} friction nodes")
        self.initial_gap = initial_gap
        self.v = self.omega * self.itf.r                    # sliding speed at each pad node
        # the uniform pressure of the clamp force: a friction law's state before any solve
        self.p_nominal = np.full(self.A_pad.size, run.line_pressure
                                 * model.geometry.clamp_area / self.A_pad.sum())
        g = model.geometry
        self.r_mean = 0.5 * (g.pad.inner_radius + g.pad.outer_radius)
        self.applied = (np.zeros(self.A_pad.size), np.zeros(self.A_rot.size))  # in the meshes
        self.load = None     # thermal-strain load of the current temperatures
        self.last_u = None   # displacement of the latest solve (if any)
        self.took_explicit = False   # the last trial step was explicit

    def dh_limit(self) -> np.ndarray:
        """Largest wear per step at each pad node (m)."""
        n = self.numerics
        if n.max_dh is not None:
            return np.full(self.A_pad.size, float(n.max_dh))
        from ..motion.brake import surface_element_height
        return n.dh_fraction * surface_element_height(self.model.meshes["pad"], "friction")

    def fingerprint(self) -> dict:
        """Every resolved input of this run (a checkpoint is resumed only by the same)."""
        return fingerprint(**self.run.settings(self.limits))

    def start(self, state: WearState, extra: dict) -> float | None:
        """Bring the loop to ``state`` (a fresh or a resumed one); returns the time
        of the first contact solve, when a fresh run makes one."""
        th = self.thermal
        if th is not None:
            if extra:
                th.load_state({k: v for k, v in extra.items()
                               if k.startswith("T_") or k == "thermal_time"})
            elif state.step > 0:
                raise WearError("the checkpoint has no thermal state; it was written by a run "
                                "without thermal coupling")
            self.couple(state.pressure)
        elif self.mu_law is not None:
            self.mu = self.laws.mu(self.p_now(state.pressure), self.v, None)
        if self.motion is not None and state.step > 0:
            self.move(state.pad_wear, state.rotor_wear, state.step)
        if state.pressure is not None:
            return None
        sol, s = self.solve(state, state.pad_wear, state.rotor_wear, None)
        state.pressure, state.active = sol.pressure, sol.active
        return s

    def p_now(self, p):
        return self.p_nominal if p is None else p

    def couple(self, p) -> None:
        """Thermal strain and the friction law at the current temperatures (and the
        pressure ``p``, None: the nominal one), for the next solves."""
        self.load = self.thermal.thermal_load()
        if self.mu_law is not None:
            self.mu = self.laws.mu(self.p_now(p), self.v,
                                   self.thermal.face_temperature("pad"))

    def set_speed(self, t: float, dt: float | None) -> bool:
        """Take the next step at the mean speed over ``[t, t + dt]`` (at ``t``'s
        speed while ``dt`` is not chosen); True if the speed changed."""
        w = self.speed.at(t) if dt is None else self.speed.mean(t, dt)
        if w == self.omega:
            return False
        self.omega, self.v = w, w * self.itf.r
        return True

    def temperatures(self):
        if self.thermal is None:
            return None, None
        return self.thermal.face_temperature("pad"), self.thermal.rotor_temperature_under_pad()

    def move(self, pad_w, rot_w, step) -> None:
        """Move the worn faces: a new model, and its interface."""
        self.motion.apply(pad_w, rot_w if self.model.rotor == "elastic" else None, step=step)
        self.itf = self.itf.rebuilt(self.motion.model,
                                    opening=float(pad_w.max() + rot_w.max()))
        self.applied = (pad_w.copy(), rot_w.copy())
        if self.thermal is not None:
            # the temperatures ride on the moved nodes; conduction, capacity and the
            # thermal-strain load are those of the moved meshes
            self.thermal.follow(self.motion.model)
            self.load = self.thermal.thermal_load()

    def solve(self, state, pad_w, rot_w, active, eps=None, dt=None):
        """Contact of the worn state: ``(InterfaceSolution, seconds)``.  The implicit
        step starts its Krylov solves from the displacement extrapolated over
        ``dt`` from the last two accepted steps (in the checkpoints, so a resumed
        run repeats the uninterrupted one)."""
        t0 = _time.perf_counter()
        offset = (pad_w - self.applied[0]) + self.W @ (rot_w - self.applied[1])
        if self.initial_gap is not None:
            offset = offset + self.initial_gap
        x0 = state.start_guess(dt) if dt is not None else state.u
        sol = self.itf.solve(offset, active, compliance=eps, x0=x0, load=self.load, mu=self.mu)
        self.last_u = sol.u
        return sol, _time.perf_counter() - t0

    def rates(self, p, T_pad, T_rot):
        """Pad wear rate (m/s per pad node), rotor wear flux per pad node (m^3/s) and
        the rotor's ring-averaged wear rate (m/s per rotor wear node), with the laws'
        coefficients (and a friction law's mu) taken at ``p``, the speed and the
        temperatures (:mod:`brakewear.wear.nodal`)."""
        self.laws.take(p, self.v, T_pad, T_rot)
        if self.mu_law is not None:
            self.mu = self.laws.mu(p, self.v, T_pad)
        rate_pad = self.laws.pad_rate(p, self.v)
        q_rot = self.laws.rotor_rate(p, self.v) * self.A_pad
        return rate_pad, q_rot, self.ring_rate(q_rot)

    def worst(self, p, act) -> float:
        """The largest ``c_i s_i / A_i`` over the contact: d(rate)/dp of both laws
        times the normal stiffness per area (the explicit scheme's bound)."""
        slope = self.laws.pad_slope(p, self.v) + self.laws.rotor_slope(p, self.v)
        return float((slope * self.itf.normal_stiffness / self.A_pad)[act].max()) \
            if act.any() else 0.0

    def worst_rotor(self, p, act) -> float:
        """The largest ring rate per unit gap of the rotor's ring wear (1/s): per
        ring, ``sum_i c_i s_i / A_ring`` over the pad nodes in contact above it."""
        if self.rotor_law is None or not act.any():
            return 0.0
        q = np.where(act, self.laws.rotor_slope(p, self.v) * self.itf.normal_stiffness, 0.0)
        return float(self.ring_rate(q).max())

    def step(self, state: WearState, control: StepControl) -> WearStep:
        """One accepted step from ``state`` (updated in place); its record."""
        T_pad, T_rot = self.temperatures()
        p, act = state.pressure, state.active
        self.set_speed(state.time, None)
        rate_pad, q_rot, rate_rot = self.rates(p, T_pad, T_rot)
        mu_step = self.mu
        dt, limit = control.propose(
            state.dt_next,
            control.duration - state.time,
            rate_pad + self.W @ rate_rot,
            lambda: self.worst(p, act),
            lambda: self.worst_rotor(p, act),
            lambda: self.explicit_below(p),
        )
        if control.fixed and self.numerics.scheme == "explicit":
            check_explicit_step(self, state, dt, p, act)
        rejected, solve_s, changes = 0, 0.0, []
        saved = self.thermal.state_arrays() if self.thermal is not None else None
        while True:
            if self.set_speed(state.time, dt):
                rate_pad, q_rot, rate_rot = self.rates(p, T_pad, T_rot)
                mu_step = self.mu
            if self.thermal is not None:
                self.thermal.load_state(saved)
                self.thermal.set_speed(self.omega)
                self.thermal.step(self.thermal.flux(p, mu_step, self.omega), dt)
                self.couple(p)
            try:
                sol, pad_w, rot_w, p_rate, q_used, s = self.attempt(state, dt, rate_pad,
                                                                    q_rot, rate_rot, act)
                solve_s += s
                change = control.pressure_change(p, sol.pressure)
                est = control.wear_error(dt, self.rate_change(sol.pressure, rate_pad, rate_rot)) \
                    if control.on_wear_error else np.nan
                ok = control.accepts(change, est)
            except ContactLostError:
                if control.fixed:
                    raise StepSizeError(
                        f"step {state.step + 1}: the fixed step dt = {dt:.3e} s wears the "
                        "surfaces apart (no node left in contact); use more steps or the "
                        "automatic step control, which retries smaller") from None
                change, est, ok = np.inf, np.inf, False
            except (ActiveSetError, ConvergenceError) as e:
                # an implicit step's set cycles when its wear changes the contact a lot (a
                # corrosion layer worn through), and on a long step its soft springs hold a
                # pad free to tilt weakly: a shorter step is better posed
                if control.fixed or self.numerics.scheme == "explicit":
                    raise
                logger.info("step %d: %s; retrying with dt/2", state.step + 1, e)
                change, est, ok = np.inf, np.inf, False
            changes.append(change)
            if ok:
                break
            if control.spans_jump(changes):
                logger.warning("step %d: the pressure changes by %.2f however short the step "
                               "(%.3g s after %d halvings): a jump of the contact state, "
                               "taken in the shortest step", state.step + 1, change, dt,
                               rejected)
                limit = "jump"
                break
            rejected += 1
            dt, new_limit = control.retry(dt, est, rejected, state.step + 1, change)
            limit = new_limit or limit
        state.pad_wear, state.rotor_wear = pad_w, rot_w
        state.pad_archard += float((self.laws.pad_rate(p_rate, self.v) * self.A_pad).sum() * dt)
        state.rotor_archard += float(q_used.sum() * dt)
        state.time += dt
        state.step += 1
        state.dt_next = control.next_dt(dt, change, est, now=state.time)
        record = self.record(state, dt, p, act, rejected, solve_s, limit,
                             NodalLaws.effective(mu_step, p, self.A_pad), T_rot)
        record.explicit = self.took_explicit
        record.mu_nodes = None if np.ndim(mu_step) == 0 else mu_step
        record.friction_work = friction_power(p, self.v, mu_step, self.A_pad) * dt
        self.worn = self.limits.check(record, self.itf)      # a WornThroughError or None
        record.worn_through = self.worn is not None
        if self.thermal is not None:
            check_temperature(record, self.thermal)     # a TemperatureLimitError
        self.finish(state, record, sol, dt)
        return record

    def explicit_below(self, p) -> float:
        """The step (s) under which the pad's wear compliance is below ``implicit_floor``."""
        lam = float((self.laws.pad_slope(p, self.v) * self.itf.normal_stiffness / self.A_pad).max())
        return self.numerics.implicit_floor / lam if lam > 0 else np.inf

    def attempt(self, state, dt, rate_pad, q_rot, rate_rot, act):
        """A trial step: ``(solution, pad and rotor wear, the p and rotor m^3/s it wore
        with, s)``."""
        p0, scheme = state.pressure, self.numerics.scheme
        self.took_explicit = scheme == "explicit" or dt < self.explicit_below(p0)
        rings = not self.took_explicit and scheme == "implicit" and self.rotor_law is not None
        rot_w = state.rotor_wear if rings else state.rotor_wear + rate_rot * dt
        if self.took_explicit:
            pad_w = state.pad_wear + rate_pad * dt
            sol, s = self.solve(state, pad_w, rot_w, act)
            return sol, pad_w, rot_w, p0, q_rot, s
        eps = dt * self.laws.pad_slope(p0, self.v)    # backward Euler, a = 1: k v^b
        comp = StepCompliance(eps, dt * self.laws.rotor_slope(p0, self.v),   # and the rings
                              *self.ring_coupling()) if rings else eps
        sol, s = self.solve(state, state.pad_wear, rot_w, act, comp, dt)
        if rings:
            q_rot = self.laws.rotor_rate(sol.pressure, self.v) * self.A_pad
            rot_w = rot_w + self.ring_rate(q_rot) * dt
        return sol, state.pad_wear + eps * sol.pressure, rot_w, sol.pressure, q_rot, s

    def ring_coupling(self):
        """``(ring_gap, ring_area)`` of the rings (:func:`~brakewear.rings.ring_coupling`
        of the loop's coupling, built once: the rings do not move)."""
        if self._rings is None:
            self._rings = ring_coupling(self.W, self.ring, self.A_rot)
        return self._rings

    def rate_change(self, p_new, rate_pad, rate_rot) -> np.ndarray:
        """The change over the step of the wear rate each pad node sees (pad + rotor, m/s):
        the embedded local wear error's (:meth:`StepControl.wear_error`)."""
        d_rate = self.laws.pad_rate(p_new, self.v) - rate_pad
        if self.rotor_law is not None:
            q_new = self.laws.rotor_rate(p_new, self.v) * self.A_pad
            d_rate = d_rate + self.W @ (self.ring_rate(q_new)
                                        - rate_rot)
        return d_rate

    def record(self, state, dt, p, act, rejected, solve_s, limit, mu_step, T_rot) -> WearStep:
        rec = WearStep(state.step, state.time, dt, self.speed.angle(state.time) * self.r_mean,
                       p, act, state.pad_wear.copy(), state.rotor_wear.copy(),
                       float((state.pad_wear * self.A_pad).sum()),
                       float((state.rotor_wear * self.A_rot).sum()),
                       state.pad_archard, state.rotor_archard, rejected, rejected + 1,
                       solve_s, limit, mu_step)
        if self.thermal is not None:
            for k, v in thermal_state(self.thermal, T_rot).items():
                setattr(rec, k, v)
        return rec

    def finish(self, state: WearState, record: WearStep, sol, dt: float) -> None:
        """The contact state the next step starts from (after moving the worn faces,
        in geometry-update mode) and the displacements its start is taken from."""
        if self.motion is not None and self.worn is None:
            self.move(state.pad_wear, state.rotor_wear, state.step)
            sol, s = self.solve(state, state.pad_wear, state.rotor_wear, sol.active)
            record.contact_solves += 1
            record.solve_s += s
        record.pressure_end, record.active_end = sol.pressure, sol.active
        state.pressure, state.active = sol.pressure, sol.active
        if self.last_u is not None and self.motion is None:
            state.u_prev, state.dt_last = state.u, dt
        state.u = self.last_u

