"""What a run can hold, checked before its first solve: its duration and its fixed steps.

Two bounds follow from the model and the laws at the start (the nominal contact
pressure ``p_n`` -- the clamp force over the pad face --, the start's speed and
temperatures), each refused with a :class:`~brakewear.wear.numerics.NumericsError`
(exit code 2) that shows it in the scene file's units:

* **the wear-through horizon.**  The pad's mean worn depth grows at ``sum_i A_i
  k_i p_i^a v_i^b / sum_i A_i``; the pressures carry the clamp force
  (``sum_i A_i p_i = p_n sum_i A_i``) and every node slides at least at the inner
  radius, so for ``a >= 1`` (Jensen) the mean depth after the run's sliding is at
  least ``k_min p_n^a r_in^b integral(omega^b dt)``.  The deepest node is at least
  as deep: once that bound reaches the pad's wear limit the pad has certainly
  worn through.  A duration past that time cannot be the history of this brake
  (the run ends at the wear-through, exit code 4, when it comes first);
  ``k_min`` is the law's smallest coefficient (a map's smallest value; a law of
  temperature is at its least at the start).
* **fixed steps** (``numerics.steps``): one step must not wear more than the
  limit at the start's peak rate, and in the explicit scheme the step must lie
  within explicit Euler's stability bound ``2 / lambda_max(C S)`` (``C`` the
  slope of the wear rates with the pressure, ``S`` the contact's pressure response
  to a gap change): first the row-sum bound ``2 / max_i(c_i s_i / A_i)`` of the
  step control (:mod:`brakewear.wear.control`; ``s_i`` the contact's normal
  stiffness at the node), which lies below the sharp one; a step past it has the
  sharp bound computed by power iteration (a contact solve per iteration).  Beyond
  it the wear oscillates and grows from step to step: a wrong answer with exit
  code 0.  The loop checks the bound again at every fixed explicit step (the
  row-sum bound at the step's state, scaled by the start's ratio of the two: a
  coefficient that rises with temperature lowers it), and stops with a
  :class:`~brakewear.errors.StepSizeError`.
"""
from __future__ import annotations

import math

import numpy as np

from ..checks import shown_in, user_scale
from .limits import WearLimits
from .nodal import NodalLaws
from .numerics import NumericsError

__all__ = ["check_run_bounds", "check_explicit_step", "explicit_bound", "explicit_eigen_bound",
           "shown_time"]


def shown_time(seconds: float) -> str:
    """A time (s) in the scene file's unit of time (4 digits), else in s."""
    return shown_in("time", seconds)


def _shown_depth(metres: float) -> str:
    return shown_in("length", metres)


def explicit_bound(laws: NodalLaws, p, v, stiffness, area, active=None) -> float:
    """Explicit Euler's stability bound on the step (s): ``2 / max(c s / A)`` over the
    nodes in contact (``active``; None: all), ``c`` the wear rates' slope in the
    pressure (pad and rotor, :class:`~brakewear.wear.nodal.NodalLaws` taken)."""
    c = laws.pad_slope(p, v) + laws.rotor_slope(p, v)
    lam = c * stiffness / area
    if active is not None:
        lam = lam[active]
    w = float(lam.max()) if lam.size else 0.0
    return 2.0 / w if w > 0 else math.inf


def explicit_eigen_bound(itf, laws: NodalLaws, v, offset, mu, *, load=None,
                         rtol: float = 1e-4) -> float:
    """Explicit Euler's stability bound on the step (s) at the start's contact, sharp:
    ``2 / lambda_max(C S)``, ``C`` the wear rates' slope in the pressure and ``S`` the
    contact's pressure response to a gap change on its active set (``S = A^-1 K``,
    ``K`` the nodal forces' response; one contact solve, its active set held, per
    product).  ``C S`` is similar to ``(C/A)^1/2 K (C/A)^1/2``, symmetric without
    friction: its largest eigenvalue by Lanczos (``scipy.sparse.linalg.eigsh``),
    taken 1 % up (a Ritz value approaches it from below)."""
    from scipy.sparse.linalg import ArpackNoConvergence, LinearOperator, eigsh

    sol = itf.solve(offset, None, load=load, mu=mu)
    p0, act = sol.pressure, sol.active
    area = np.asarray(itf.area, dtype=float)
    c = np.where(act, laws.pad_slope(p0, v) + laws.rotor_slope(p0, v), 0.0)
    idx = np.flatnonzero(c > 0)
    if idx.size == 0:
        return math.inf
    w = np.sqrt(c[idx] / area[idx])
    stiff = float(np.max((itf.normal_stiffness / area)[idx]))
    eps = 1e-3 * float(np.max(p0)) / stiff          # a gap change far inside the linear range

    def apply(x):
        u = np.zeros(p0.size)
        u[idx] = w * np.ravel(x)
        h = eps / max(float(np.abs(u).max()), 1e-300)
        dp = p0 - itf.solve(offset + h * u, act, load=load, mu=mu).pressure
        return w * area[idx] * dp[idx] / h

    if idx.size == 1:
        lam = float(apply(np.ones(1))[0])
    else:
        op = LinearOperator((idx.size, idx.size), matvec=apply, dtype=float)
        v0 = np.random.default_rng(0).standard_normal(idx.size)
        try:
            lam = float(eigsh(op, k=1, which="LA", tol=rtol, v0=v0,
                              ncv=min(idx.size, 12), maxiter=200,
                              return_eigenvectors=False)[0])
        except ArpackNoConvergence as e:
            lam = float(np.max(e.eigenvalues)) if len(e.eigenvalues) else 0.0
    return 2.0 / (1.01 * lam) if lam > 0 else math.inf


def _least_coefficient(law, k_start) -> float:
    table = getattr(law, "table", None)
    if table is not None:
        return float(np.min(table.values))
    return float(np.min(k_start))


def check_run_bounds(run) -> float:
    """Refuse a drag ``run`` (a resolved :class:`~brakewear.wear.Run`; a schedule is
    bounded per application) whose duration passes the wear-through horizon or
    whose fixed steps wear through in one step or are explicitly unstable (see the
    module).  Returns how far the sharp stability bound lies above the row-sum one
    at the start (1 where the sharp one was not needed): the loop's check of each
    fixed explicit step scales the row-sum bound by it."""
    if run.schedule or run.duration is None:
        return 1.0
    itf, model, n = run.interface, run.model, run.numerics
    area, r = np.asarray(itf.area, dtype=float), np.asarray(itf.r, dtype=float)
    p = np.full(area.size, run.line_pressure * model.geometry.clamp_area / area.sum())
    speed = run.speed
    v = speed.at(0.0) * r
    th = run.thermal
    T_pad = th.face_temperature("pad") if th is not None else None
    T_rot = th.rotor_temperature_under_pad() if th is not None else None
    mu_law = run.mu_law
    laws = NodalLaws(run.pad_law, run.rotor_law, mu_law, 0.0 if mu_law else float(run.mu))
    laws.take(p, v, T_pad, T_rot)
    limits = run.limits or WearLimits.for_model(model, update=n.update)
    law = run.pad_law
    duration = float(run.duration)
    if limits.pad is not None and law.a >= 1.0:
        k_min = _least_coefficient(law, laws.k_pad)
        r_in = float(r.min())
        t = np.linspace(0.0, duration, 401)
        w_b = np.array([speed.at(x) for x in t]) ** law.b
        # the mean depth's least growth, integrated over the run (trapezoids)
        depth = k_min * p[0] ** law.a * r_in ** law.b * np.concatenate(
            [[0.0], np.cumsum(0.5 * (w_b[1:] + w_b[:-1]) * np.diff(t))])
        if depth[-1] > limits.pad:
            t_through = float(np.interp(limits.pad, depth, t))
            rate = k_min * p[0] ** law.a * (speed.at(0.0) * r_in) ** law.b
            key = "environment.duration" if user_scale("units.time") else "duration"
            raise NumericsError(
                f"{key} = {shown_time(duration)} is not allowed: the pad's "
                f"wear limit ({_shown_depth(limits.pad)}) is reached by t = "
                f"{shown_time(t_through)} at the latest -- the start's wear rate over the "
                f"pad face, at least {rate * 3.6e9:.4g} um/h at its mean (the clamp force "
                f"over the face, {p[0] / 1e6:.4g} MPa, at the inner radius), wears its mean "
                f"depth to the limit by then; allowed: a duration up to "
                f"{shown_time(t_through)} (the run ends at the wear-through, exit code 4, "
                "if it comes first)")
    if n.steps is None:
        return 1.0
    dt = duration / n.steps if not hasattr(speed, "omega0") else \
        float(speed.time_at_angle(speed.angle(duration) / n.steps))
    peak = float((laws.pad_rate(p, v) + laws.rotor_rate(p, v)).max())
    if limits.pad is not None and peak * dt > limits.pad:
        need = math.ceil(n.steps * peak * dt / limits.pad)
        raise NumericsError(
            f"numerics.steps = {n.steps}: each fixed step ({shown_time(dt)}) wears "
            f"{_shown_depth(peak * dt)} at the start's fastest node (the nominal pressure "
            f"{p[0] / 1e6:.4g} MPa), past the pad's limit {_shown_depth(limits.pad)}: the "
            f"first step would wear it through; allowed: steps >= {need}, or the automatic "
            "step control (no steps)")
    if n.scheme != "explicit":
        return 1.0
    rows = explicit_bound(laws, p, v, itf.normal_stiffness, area)
    if dt <= rows:              # within the row-sum bound: stable, no solve needed
        return 1.0
    offset = np.zeros(area.size) if run.initial_gap is None else run.initial_gap
    bound = explicit_eigen_bound(itf, laws, v, offset, laws.mu(p, v, T_pad),
                                 load=None if th is None else th.thermal_load())
    if dt > bound:
        need = math.ceil(n.steps * dt / bound * (1 + 1e-9))
        raise NumericsError(
            f"numerics.steps = {n.steps}: the fixed step {shown_time(dt)} is beyond the "
            f"explicit scheme's stability bound {shown_time(bound)} (2 / the largest "
            "eigenvalue of the wear rates' slope in the pressure times the contact's "
            "stiffness, at the start); beyond it the wear oscillates and grows from step "
            f"to step; allowed: steps >= {need}, scheme = 'implicit' (stable at any "
            "step), or the automatic step control (no steps)")
    return bound / rows


def check_explicit_step(loop, state, dt: float, p, act) -> None:
    """Raise :class:`~brakewear.errors.StepSizeError` if the fixed explicit step ``dt``
    (s) from ``state`` of the wear ``loop`` is past the stability bound at that state:
    the row-sum bound there, scaled by ``loop.stability_ratio`` (the sharp bound over
    it, from the start; computed here, at this state, the first time the row-sum
    bound is passed when the start did not need it)."""
    from ..errors import StepSizeError

    w = loop.worst(p, act)
    bound = 2.0 * loop.stability_ratio / w if w > 0 else math.inf
    if dt > bound * (1 + 1e-9) and loop.stability_ratio == 1.0:
        offset = (state.pad_wear - loop.applied[0]) + loop.W @ (state.rotor_wear
                                                                 - loop.applied[1])
        if loop.initial_gap is not None:
            offset = offset + loop.initial_gap
        sharp = explicit_eigen_bound(loop.itf, loop.laws, loop.v, offset, loop.mu,
                                     load=loop.load)
        loop.stability_ratio = max(sharp * w / 2.0, 1.0 + 1e-12)
        bound = 2.0 * loop.stability_ratio / w
    if dt > bound * (1 + 1e-9):
        raise StepSizeError(
            f"step {state.step + 1}: the fixed step dt = {shown_in('time', dt)} is beyond "
            f"the explicit scheme's stability bound {shown_in('time', bound)} at this state "
            "(the wear coefficients have risen since the start); beyond it the wear "
            "oscillates and grows: use more steps, scheme = 'implicit' or the automatic "
            "step control", figures={"dt_s": dt, "bound_s": bound})
