"""The wear loop: contact -> pressure -> wear of pad and rotor -> new gap -> ...

:func:`wear_history` is a generator of :class:`WearStep` records.  The
geometry is updated in *gap-offset* mode: the meshes stay, and the worn
depths of pad and rotor are added to the contact gap (valid while wear is
far below the element size).

Time integration is explicit Euler.  The step is the smallest of

- ``max_dh``: no pad node wears more than this in one step (pad + rotor);
- the stability bound: explicit Euler on the wear ODE ``dg/dt = c p(g)`` is
  monotone (no oscillating short-wavelength modes) while ``dt c_i dp_i/dg``
  stays below one; the pressure's response to a local gap change is bounded
  by the row sums of the friction face's normal stiffness (Gershgorin, see
  docs/theory.md), so ``dt <= stability / max_i(c_i s_i / A_i)``;
- twice the last accepted step;

and a step after which the contact pressure changes by more than ``dp_tol``
(relative to its maximum), or the contact is lost, is rejected and retried
at half the size.
With ``wear_tol`` (m) the step control works on the local wear error
instead: a step whose embedded estimate ``dt/2 max|rate(p_end) -
rate(p_start)|`` exceeds ``wear_tol`` is retried smaller, and the next step
aims at ``0.9 wear_tol`` (docs/theory.md, "Step control on the wear error").

Checkpoints (``.npz``) hold the whole state; a run resumed from one repeats
the uninterrupted run exactly, because every step is solved from the stored
state alone (active set of the previous step, a hierarchy that depends only
on the stiffness).
"""
from __future__ import annotations

import logging
import os
import time as _time
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

import numpy as np

from ..errors import ContactLostError, StepSizeError, WearError
from ..interfaces.fe import FEInterface
from ..laws import WearLaw
from ..rings import rotor_wear_rate
from .limits import WearLimits

logger = logging.getLogger(__name__)

__all__ = ["WearStep", "wear_history"]


@dataclass
class WearStep:
    """State after an accepted step (cumulative quantities)."""

    step: int
    time: float                 # s
    dt: float                   # s, of this step
    sliding_distance: float     # m, at the pad's mean radius, since the start
    pressure: np.ndarray        # Pa at the pad's friction nodes, at the start of the step
    active: np.ndarray          # contact status at the start of the step
    pad_wear: np.ndarray        # m, cumulative, per pad friction node
    rotor_wear: np.ndarray      # m, cumulative, per rotor wear node (face node or ring)
    pad_volume: float           # m^3 worn from the pad (sum of depth x area)
    rotor_volume: float         # m^3 worn from the rotor
    pad_archard: float          # m^3, sum over steps of k_pad int p v dA dt
    rotor_archard: float        # m^3, the same with k_rotor
    rejected: int               # retries before this step was accepted
    contact_solves: int         # contact solves of this step (1 + rejected)
    solve_s: float              # s spent in contact solves in this step
    limit: str                  # what set the step: max_dh, stability, growth, wear_tol,
                                # first, end, fixed
    mu: float = 0.0             # friction coefficient in this step (mu(T) with a friction law)
    pad_temperature_max: float = float("nan")    # K, pad face, end of step (thermal only)
    rotor_temperature_max: float = float("nan")  # K, rotor face, end of step (thermal only)
    heat_balance_error: float = float("nan")     # |heat in - friction power| / power, this step
    pressure_end: np.ndarray | None = None       # Pa, at the end of the step (= next start)
    active_end: np.ndarray | None = None


#: Largest growth of the step from one step to the next under ``wear_tol``
#: control (measured, docs/wear.md "Step convergence": 2, 4 and 8 give the same
#: runs within one step; 4 saves the step after the first guess, adds no retry).
WEAR_TOL_GROWTH = 4.0


_STATE_KEYS = ("step", "time", "pad_wear", "rotor_wear", "pad_archard", "rotor_archard",
               "pressure", "active", "dt_next", "u", "u_prev", "dt_last")


def wear_history(model, line_pressure: float, omega: float, duration: float,
                 pad_law: WearLaw, rotor_law: WearLaw | None = None, mu: float = 0.0,
                 steps: int | None = None, max_dh: float | None = None,
                 dh_fraction: float = 0.1, dp_tol: float = 0.05,
                 wear_tol: float | None = None,
                 stability: float | None = 1.0, scheme: str = "explicit", update: str = "gap",
                 checkpoint: str | os.PathLike | None = None, every: int = 10,
                 resume: bool = False, tol: float = 1e-9, max_halvings: int = 12,
                 interface=None, initial_gap: np.ndarray | None = None,
                 thermal=None, limits=None) -> Iterator[WearStep]:
    """Run a wear history of the brake under constant line pressure and speed.

    Parameters
    ----------
    model
        A :class:`brakewear.model.BrakeModel` (elastic or rigid rotor).
    line_pressure, omega, duration
        Pa, rad/s (rotor speed, > 0), s.
    pad_law, rotor_law
        Wear laws of pad and rotor (``rotor_law=None``: the rotor does not wear).
    mu
        Friction coefficient (sliding friction drags the pad along the rotor),
        or a :class:`brakewear.laws.FrictionLaw` (``mu(T)`` at the pad
        face's mean temperature, updated every step; needs ``thermal``).
    steps
        Fixed number of equal steps (no step control, no stability bound);
        default: automatic step control.
    max_dh, dh_fraction
        Largest wear (pad + rotor seen by the pad) per step at a pad node:
        ``max_dh`` (m) everywhere, or by default ``dh_fraction`` times the
        height of the pad element under the node.
    dp_tol
        Largest accepted change of the pressure field per step, relative to
        its maximum (automatic control only; not used with ``wear_tol``).
    wear_tol
        Local wear error per step (m) of the automatic control, instead of
        ``dp_tol`` (default None: ``dp_tol`` control).  The error of a step
        in the wear depth is estimated from the change of the wear rate over
        it: ``est = dt/2 max_i |(rate(p_end) - rate(p_start))_i|`` (pad rate
        plus the rotor's rate seen by the pad node ``i``).  A step is
        accepted if ``est <= wear_tol``, else retried with
        ``dt * max(0.2, 0.9 sqrt(wear_tol/est))``; the next step is
        ``dt * clip(0.9 sqrt(wear_tol/est), 0.25, 4)``.  This equidistributes
        the local wear error, ``dt ~ |dp/dt|^(-1/2)`` (``dp_tol`` gives
        ``dt ~ 1/|dp/dt|``).  On long running-in histories it reaches a
        given error over the history with fewer solves than ``dp_tol`` or
        equal steps; for the wear at the end time alone equal implicit steps
        are as cheap or cheaper, because the wear error is damped
        (docs/theory.md, "Step control on the wear error"; docs/wear.md,
        "Step convergence").  The other limits (``max_dh``, ``stability``,
        the end, halving after a lost contact) still apply.
    stability
        Explicit scheme: fraction of the monotone explicit-Euler bound on the
        step (None switches it off).  1 keeps every mode of the wear ODE from
        overshooting; 2 is the stability limit.
    scheme
        ``"explicit"`` (Euler: the pressure at the start of the step) or
        ``"implicit"`` (backward Euler for the pad: the pressure at the end of
        the step, solved as contact through the step's wear compliance,
        :mod:`brakewear.contact.compliant`; unconditionally stable; the rotor's
        ring-averaged wear stays explicit).  Implicit needs a pad law with a = 1.
    update
        ``"gap"`` (the worn depths offset the contact gap; meshes stay) or
        ``"geometry"`` (after every accepted step both worn faces move and the
        layers beneath follow, :class:`brakewear.motion.BrakeMotion`; a
        degenerate element raises :class:`~brakewear.errors.MeshQualityError`
        naming the step).  Elastic rotor, or rigid rotor (pad moves only).
    checkpoint, every, resume
        ``.npz`` file written every ``every`` accepted steps (and at the end);
        ``resume=True`` continues from it (with a freshly built model).
    interface
        The interface model (default: :class:`FEInterface` of ``model``); any
        object with the same attributes (``area``, ``r``, ``W``, ``ring``,
        ``rotor_area``, ``normal_stiffness``) and ``solve(offset, active)``.
    thermal
        A :class:`brakewear.thermal.ThermalModel` of ``model`` (default None:
        nothing thermal is built or computed).  Staggered, one thermal update
        per step: the frictional heat of the step's starting pressure heats
        the bodies over ``dt`` (implicit Euler), then the contact is solved
        with the thermal-strain load of the new temperatures, and the wear
        laws use ``k(T)`` at the pad face and the rotor under it.  Its state
        goes into the checkpoints.
    initial_gap
        Extra gap (m) at each pad friction node before any wear (a non-conformal
        start: rotor coning, pad taper, thickness variation, or the worn state
        ``pad_wear + W @ rotor_wear`` of an earlier history); it never wears.
    limits
        A :class:`brakewear.wear.limits.WearLimits` (default: the model's,
        :meth:`~brakewear.wear.limits.WearLimits.for_model`).  The step that
        wears a surface past its limit is yielded, then
        :class:`~brakewear.errors.WornThroughError` is raised (naming the
        time, the node and the depth); with ``update = "geometry"`` the
        meshes are not moved by that step.
    """
    if not (np.isfinite(omega) and omega > 0):
        raise WearError(f"omega = {omega!r} rad/s is not allowed; need a rotor speed > 0")
    if not (np.isfinite(duration) and duration > 0):
        raise WearError(f"duration = {duration!r} s is not allowed; need > 0")
    if steps is not None and (int(steps) != steps or steps < 1):
        raise WearError(f"steps = {steps!r} is not allowed; need a whole number >= 1")
    if resume and checkpoint is None:
        raise WearError("resume=True needs a checkpoint file")
    if resume and not Path(checkpoint).exists():
        raise WearError(f"resume=True but the checkpoint {checkpoint} does not exist")
    if not (np.isfinite(dp_tol) and dp_tol > 0):
        raise WearError(f"dp_tol = {dp_tol!r} is not allowed; need > 0")
    if wear_tol is not None and not (isinstance(wear_tol, (int, float, np.number))
                                     and not isinstance(wear_tol, bool)
                                     and np.isfinite(wear_tol) and wear_tol > 0):
        raise WearError(f"wear_tol = {wear_tol!r} m is not allowed; need a finite local wear "
                        "error per step > 0 (m), or None for the dp_tol control")
    if not (np.isfinite(dh_fraction) and dh_fraction > 0):
        raise WearError(f"dh_fraction = {dh_fraction!r} is not allowed; need > 0")
    if stability is not None and not (np.isfinite(stability) and stability > 0):
        raise WearError(f"stability = {stability!r} is not allowed; need > 0 (or None)")
    if int(every) != every or every < 1:
        raise WearError(f"every = {every!r} is not allowed; need a whole number >= 1")
    if scheme not in ("explicit", "implicit"):
        raise WearError(f"scheme = {scheme!r} is not allowed; allowed: 'explicit', 'implicit'")
    if update not in ("gap", "geometry"):
        raise WearError(f"update = {update!r} is not allowed; allowed: 'gap', 'geometry'")
    for name, law in (("pad_law", pad_law), ("rotor_law", rotor_law)):
        if law is not None and not isinstance(law, WearLaw):
            raise WearError(f"{name} = {law!r} is not a WearLaw")
    if scheme == "implicit" and pad_law.a != 1.0:
        raise WearError(f"scheme = 'implicit' needs a pad wear law linear in p (a = 1); "
                        f"got a = {pad_law.a}")
    if max_dh is not None and not (np.isfinite(max_dh) and max_dh > 0):
        raise WearError(f"max_dh = {max_dh!r} m is not allowed; need > 0")
    if initial_gap is not None:
        initial_gap = np.asarray(initial_gap, dtype=float)
        if initial_gap.ndim != 1 or not np.all(np.isfinite(initial_gap)):
            raise WearError("initial_gap must be a finite 1-D array (m), one value per pad "
                            "friction node")
    mu_law = None
    if hasattr(mu, "mu") and callable(mu.mu):       # a friction law mu(T)
        if thermal is None:
            raise WearError("a temperature-dependent friction law needs thermal=ThermalModel")
        mu_law, mu = mu, float(mu.mu(None))
    elif not (np.isfinite(mu) and mu >= 0):
        raise WearError(f"mu = {mu!r} is not allowed; need a friction coefficient >= 0")
    if thermal is not None:
        for attr in ("step", "flux", "thermal_load", "face_temperature", "state_arrays"):
            if not hasattr(thermal, attr):
                raise WearError(f"thermal = {thermal!r} is not a ThermalModel (no {attr!r})")
        if thermal.model is not model:
            raise WearError("thermal belongs to another BrakeModel; build it with "
                            "ThermalModel(model) for this model")
        if update == "geometry":
            raise WearError("thermal coupling with update = 'geometry' is not supported (the "
                            "thermal meshes would not follow the worn faces); use update = 'gap'")
    if update == "geometry" and interface is not None and not (
            isinstance(interface, FEInterface) and interface.model is model):
        raise WearError("update = 'geometry' rebuilds the FE interface; it needs the "
                        "FEInterface of this model (or none)")

    itf = FEInterface(model, line_pressure, mu, tol) if interface is None else interface
    limits = WearLimits.for_model(model, update=update) if limits is None else limits
    motion = None
    if update == "geometry":
        from ..motion import BrakeMotion
        motion = BrakeMotion(model)
    A_pad, ring, A_rot = itf.area, itf.ring, itf.rotor_area
    if initial_gap is not None and initial_gap.shape != A_pad.shape:
        raise WearError(f"initial_gap has {initial_gap.size} values; the pad has {A_pad.size} "
                        "friction nodes")
    gap_start = 0.0 if initial_gap is None else initial_gap
    v = omega * itf.r                                  # sliding speed at each pad node
    r_mean = 0.5 * (model.geometry.pad.inner_radius + model.geometry.pad.outer_radius)
    if max_dh is None:
        from ..motion import surface_element_height
        dh_limit = dh_fraction * surface_element_height(model.meshes["pad"], "friction")
    else:
        dh_limit = np.full(A_pad.size, float(max_dh))

    state = {"step": 0, "time": 0.0, "pad_wear": np.zeros(A_pad.size),
             "rotor_wear": np.zeros(A_rot.size), "pad_archard": 0.0, "rotor_archard": 0.0,
             "pressure": None, "active": None, "dt_next": duration / steps if steps else None,
             "u": None, "u_prev": None, "dt_last": np.nan}
    if resume:
        with np.load(checkpoint) as d:
            for k in _STATE_KEYS:
                if k not in d:          # "u": checkpoints of earlier versions lack it
                    continue
                state[k] = d[k].copy() if d[k].ndim else d[k].item()
            if thermal is not None:
                if "T_pad" not in d:
                    raise WearError(f"checkpoint {checkpoint} has no thermal state; it was "
                                    "written by a run without thermal coupling")
                thermal.load_state({k: d[k] for k in d.files
                                    if k.startswith("T_") or k == "thermal_time"})
        if state["pad_wear"].shape != (A_pad.size,) or state["rotor_wear"].shape != (A_rot.size,):
            raise WearError(f"checkpoint {checkpoint} holds {state['pad_wear'].size} pad and "
                            f"{state['rotor_wear'].size} rotor wear nodes; this model has "
                            f"{A_pad.size} and {A_rot.size}: it belongs to another model")
        if np.isnan(state["dt_next"]):
            state["dt_next"] = None
        for k in ("u", "u_prev"):
            if state[k] is not None and np.size(state[k]) == 0:
                state[k] = None
        logger.info("resumed at step %d, t = %.6g s", state["step"], state["time"])
    applied = (np.zeros(A_pad.size), np.zeros(A_rot.size))   # wear the meshes already show

    def move(pad_w, rot_w, step):
        nonlocal applied
        motion.apply(pad_w, rot_w if model.rotor == "elastic" else None, step=step)
        itf.rebuild(opening=float(pad_w.max() + rot_w.max()))
        applied = (pad_w.copy(), rot_w.copy())

    def solve(pad_w, rot_w, active, eps=None, dt=None):
        """Contact solve of the worn state.  The implicit step starts its Krylov
        solves from the displacement extrapolated over ``dt`` from the last two
        accepted steps (``state["u"]``, ``state["u_prev"]``: in the checkpoints,
        so a resumed run repeats the uninterrupted one)."""
        nonlocal last_u
        t0 = _time.perf_counter()
        offset = gap_start + (pad_w - applied[0]) + itf.W @ (rot_w - applied[1])
        x0 = state["u"]
        if x0 is not None and state["u_prev"] is not None and dt is not None:
            x0 = x0 + (dt / state["dt_last"]) * (x0 - state["u_prev"])
        p, act, info = itf.solve(offset, active, compliance=eps, x0=x0)
        last_u = info.get("u") if isinstance(info, dict) else None
        return p, act, _time.perf_counter() - t0

    def temperatures():
        if thermal is None:
            return None, None
        return thermal.face_temperature("pad"), thermal.rotor_temperature_under_pad()

    def couple():
        """Thermal strain and mu(T) of the current temperatures into the interface."""
        nonlocal mu
        itf.extra_load = thermal.thermal_load()
        if mu_law is not None:
            mu = float(np.mean(mu_law.mu(thermal.face_temperature("pad"))))
            itf.set_mu(mu)

    if thermal is not None:
        couple()
    if motion is not None and state["step"] > 0:
        move(state["pad_wear"], state["rotor_wear"], state["step"])
    last_u = None                      # displacement of the latest solve (if any)
    first_solve = None                 # counted in the first record of a fresh run
    if state["pressure"] is None:
        p, act, first_s = solve(state["pad_wear"], state["rotor_wear"], None)
        first_solve = first_s
    else:
        p, act = state["pressure"], state["active"].astype(bool)
    while state["time"] < duration * (1 - 1e-12):
        T_pad, T_rot = temperatures()
        mu_step = mu
        rate_pad = pad_law.rate(p, v, T_pad)
        q_rot = rotor_law.rate(p, v, T_rot) * A_pad if rotor_law is not None else np.zeros_like(p)
        rate_rot = rotor_wear_rate(q_rot, itf.W, ring, A_rot)
        remaining = duration - state["time"]
        if steps:
            dt, limit = min(state["dt_next"], remaining), "fixed"
        else:
            cands = {"end": remaining}
            seen = rate_pad + itf.W @ rate_rot
            if np.any(seen > 0):
                cands["max_dh"] = float(np.min(dh_limit[seen > 0] / seen[seen > 0]))
            first = state["dt_next"] is None
            if (stability is not None and scheme == "explicit") or first:
                # d(rate)/dp of both laws at the current pressure (a p^(a-1) k v^b)
                slope = _rate_slope(pad_law, p, v, T_pad) + (
                    _rate_slope(rotor_law, p, v, T_rot) if rotor_law is not None else 0.0)
                worst = float((slope * itf.normal_stiffness / A_pad)[act].max()) \
                    if act.any() else 0.0
                if worst > 0 and scheme == "explicit" and stability is not None:
                    cands["stability"] = stability / worst
                elif worst > 0 and scheme == "implicit":
                    # no bound, but the explicit one is the time scale on which the
                    # pressure starts to move: a first guess that saves halvings
                    cands["first"] = 1.0 / worst
            if state["dt_next"] is not None:
                cands["growth" if wear_tol is None else "wear_tol"] = state["dt_next"]
            limit = min(cands, key=cands.get)
            dt = cands[limit]
        rejected, solve_s = 0, 0.0
        saved = thermal.state_arrays() if thermal is not None else None
        while True:
            rot_w = state["rotor_wear"] + rate_rot * dt
            if thermal is not None:
                thermal.load_state(saved)
                thermal.step(thermal.flux(p, mu_step, omega), dt)
                couple()
            try:
                if scheme == "explicit":
                    pad_w = state["pad_wear"] + rate_pad * dt
                    p_new, act_new, s = solve(pad_w, rot_w, act)
                    p_rate = p
                else:   # backward Euler: the pad wears with the end-of-step pressure
                    eps = dt * pad_law.rate(1.0, v, T_pad)
                    p_new, act_new, s = solve(state["pad_wear"], rot_w, act, eps, dt)
                    pad_w = state["pad_wear"] + eps * p_new
                    p_rate = p_new
                solve_s += s
                change = np.abs(p_new - p).max() / max(p.max(), 1e-300)
                if wear_tol is not None and steps is None:
                    # embedded local error of the wear depth: dt/2 x the change of
                    # the rate over the step (the dt^2/2 h'' of both Euler schemes)
                    d_rate = pad_law.rate(p_new, v, T_pad) - rate_pad
                    if rotor_law is not None:
                        q_new = rotor_law.rate(p_new, v, T_rot) * A_pad
                        d_rate = d_rate + itf.W @ (rotor_wear_rate(q_new, itf.W, ring, A_rot)
                                                   - rate_rot)
                    est = 0.5 * dt * float(np.abs(d_rate).max())
                    ok = est <= wear_tol
                else:
                    ok = steps is not None or change <= dp_tol
            except ContactLostError:
                if steps is not None:
                    raise StepSizeError(
                        f"step {state['step'] + 1}: the fixed step dt = {dt:.3e} s wears the "
                        "surfaces apart (no node left in contact); use more steps or the "
                        "automatic step control, which retries smaller") from None
                change, est, ok = np.inf, np.inf, False
            if ok:
                break
            rejected += 1
            if rejected > max_halvings:
                what = (f"pressure change {change:.2f} > dp_tol {dp_tol}" if wear_tol is None
                        else f"wear error estimate {est:.3e} m > wear_tol {wear_tol:.3e} m")
                raise StepSizeError(
                    f"step {state['step'] + 1}: no acceptable wear step after {rejected} "
                    f"{'halvings' if wear_tol is None else 'retries'} (last dt {dt:.3e} s, "
                    f"{what})")
            if wear_tol is not None and np.isfinite(est):
                dt *= max(0.2, 0.9 * np.sqrt(wear_tol / est))
                limit = "wear_tol"
            else:               # contact lost, or the dp_tol control: halve
                dt *= 0.5
        state["pad_wear"], state["rotor_wear"] = pad_w, rot_w
        state["pad_archard"] += float((pad_law.rate(p_rate, v, T_pad) * A_pad).sum() * dt)
        state["rotor_archard"] += float(q_rot.sum() * dt)
        state["time"] += dt
        state["step"] += 1
        # next step: aim at 0.7 dp_tol (first-order change), never more than doubling;
        # or at 0.9 wear_tol (second-order error: the square root of the ratio)
        if steps:
            state["dt_next"] = duration / steps
        elif wear_tol is None:
            state["dt_next"] = dt * float(np.clip(0.7 * dp_tol / max(change, 1e-300), 0.25, 2.0))
        else:
            state["dt_next"] = dt * float(np.clip(0.9 * np.sqrt(wear_tol / max(est, 1e-300)),
                                                  0.25, WEAR_TOL_GROWTH))
        record = WearStep(state["step"], state["time"], dt, omega * r_mean * state["time"],
                          p, act, pad_w.copy(), rot_w.copy(),
                          float((pad_w * A_pad).sum()), float((rot_w * A_rot).sum()),
                          state["pad_archard"], state["rotor_archard"], rejected,
                          rejected + 1, solve_s, limit, mu_step)
        if first_solve is not None:
            record.contact_solves += 1
            record.solve_s += first_solve
            first_solve = None
        if thermal is not None:
            record.pad_temperature_max = float(thermal.face_temperature("pad").max())
            record.rotor_temperature_max = float(T_rot.max() if "rotor" not in thermal.bodies
                                                 else thermal.face_temperature("rotor").max())
            record.heat_balance_error = float(thermal.heat_balance()["relative_error"])
        worn = limits.check(record, itf)          # a WornThroughError or None
        if motion is not None and worn is None:
            # the worn faces move; the contact of the moved geometry gives the
            # pressure the next step starts from
            move(pad_w, rot_w, state["step"])
            p_new, act_new, s = solve(pad_w, rot_w, act_new)
            record.contact_solves += 1
            record.solve_s += s
        p, act = p_new, act_new
        record.pressure_end, record.active_end = p, act
        state["pressure"], state["active"] = p, act
        if last_u is not None and motion is None:
            state["u_prev"] = state["u"]
            state["dt_last"] = dt
        state["u"] = last_u
        if checkpoint is not None and (state["step"] % every == 0
                                       or state["time"] >= duration * (1 - 1e-12)):
            _write_checkpoint(checkpoint, {**{k: state[k] for k in _STATE_KEYS},
                                           **(thermal.state_arrays() if thermal else {})})
        yield record
        if worn is not None:
            raise worn


def _rate_slope(law: WearLaw, p: np.ndarray, v: np.ndarray, T=None) -> np.ndarray:
    """d(rate)/dp of ``law`` at ``p`` (for a = 1 simply k(T) v^b)."""
    if law.a == 1.0:
        return law.rate(1.0, v, T)
    pp = np.maximum(p, 1e-300)
    return law.a * law.rate(pp, v, T) / pp


def _write_checkpoint(path, arrays: dict) -> None:
    """Write atomically: a kill during the write leaves the previous checkpoint intact."""
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp.npz")
    out = {}
    for k, val in arrays.items():
        if val is None:
            val = np.nan if k == "dt_next" else np.zeros(0)
        out[k] = np.asarray(val)
    np.savez(tmp, **out)
    os.replace(tmp, path)
