"""A cleaning routine run stop by stop: the rust law's friction and wear, and the
heat that cones the rotor, entering each stop.

:func:`run_routine` runs a schedule of :class:`~brakewear.duty.Stop` and
:class:`~brakewear.duty.Dwell` applications one at a time through
:func:`brakewear.duty.run_schedule`, each from the wear of the ones before
(exact: the contact problem depends on the wear only through the gap,
docs/duty.md), so that between two stops

* the friction coefficient follows the rust layer (:class:`brakewear.cleaning.rust.RustLayer`:
  the iron's, raised over the load's share on rust by the law's ``mu_factor``),
  and its rotor and pad laws wear each step;
* the heat of the stops cones the rotor: with a full
  :class:`~brakewear.thermal.ThermalModel` (``thermal``) the temperatures load
  every contact solve (the coning is in the elastic rotor's deformation);
  with a :class:`~brakewear.thermal.reduced.ReducedRotorHeat` (``heat``) the
  stop's thermal coning ``kappa_c (T_ring - T_hat)``, its mean over the stop
  (predicted by running the reduced rotor through the stop first, and put back), is added
  to the gap as a coning (:func:`brakewear.cleaning.corrosion.nonconformity_gap`), and
  the reduced rotor then takes the stop's real power and cools in the dwell.

Every contact solve a stop's wear loop starts without a start set starts from
the last set found (the torque iteration's, with the same thermal load).  With
``shift_faces`` each face's gap offset is shifted to touch at zero before
each stop: a uniform gap on a face whose pad is free to move along the axis
(held by tractions) is a rigid motion of that pad, so the answer is the same,
and every face then starts its contact solves with nodes closed.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from .corrosion import nonconformity_gap, outboard_nodes
from ..duty import Dwell, Stop, run_schedule
from ..errors import DutyError
from ..wear.run import Run

logger = logging.getLogger(__name__)

__all__ = ["run_routine", "StopResult"]


@dataclass
class StopResult:
    """One application of a routine: its :class:`~brakewear.duty.ApplicationRecord`
    (wear cumulative over the routine), the friction coefficient it ran with, the
    thermal coning added to its gap (m; reduced heat) and the reduced rotor's ring
    and hat temperatures at its end (K)."""

    record: object
    mu: float
    thermal_coning: float = 0.0
    T_ring: float | None = None
    T_hat: float | None = None
    extra: dict = field(default_factory=dict)


class _WarmStart:
    """An interface whose contact solves without a start set start from the last one it
    found (the runner's torque iteration solves the state a stop's wear loop then
    starts from): the active-set iteration ends on the same set, from a start the
    thermal load has not moved.  Everything else is the wrapped interface's."""

    def __init__(self, itf, memory: dict | None = None):
        self._itf = itf
        self._memory = {"active": None} if memory is None else memory

    def __getattr__(self, name):
        return getattr(self._itf, name)

    def at_line_pressure(self, line_pressure: float) -> "_WarmStart":
        return _WarmStart(self._itf.at_line_pressure(line_pressure), self._memory)

    def solve(self, offset, active, **kw):
        last = self._memory["active"]
        if active is None and last is not None and last.shape == np.shape(offset):
            active = last
        sol = self._itf.solve(offset, active, **kw)
        self._memory["active"] = np.asarray(sol.active, dtype=bool).copy()
        return sol


def _face_shift(offset: np.ndarray, outboard: np.ndarray) -> np.ndarray:
    out = offset.copy()
    for mask in (~outboard, outboard):
        if mask.any():
            out[mask] -= out[mask].min()
    return out


def run_routine(model, interface, schedule, vehicle, rust, mu_iron: float, *, numerics,
                gap0: np.ndarray | None = None, heat=None, coning_per_k: float = 0.66e-6,
                thermal=None, shift_faces: bool = False, on_step=None):
    """Run ``schedule`` (stops and dwells) on ``model`` stop by stop (see the module).

    Parameters
    ----------
    model, interface
        The brake and its interface (an FE or condensed one; ``W``, ``ring``, ``x``).
    schedule
        :class:`~brakewear.duty.Stop` and :class:`~brakewear.duty.Dwell` applications.
    vehicle
        The :class:`~brakewear.duty.Vehicle` (as its controller runs the routine).
    rust
        A :class:`brakewear.cleaning.rust.RustLayer` of ``interface`` (its laws and friction).
    mu_iron
        The friction coefficient on iron.
    numerics
        The wear loop's :class:`~brakewear.wear.Numerics`.
    gap0
        The initial gap per pad friction node (m): the static non-conformity.
    heat, coning_per_k
        A :class:`~brakewear.thermal.reduced.ReducedRotorHeat` and the thermal coning
        across the pad per kelvin of ring over hat (m/K).
    thermal
        A full :class:`~brakewear.thermal.ThermalModel` instead (not with ``heat``).
    shift_faces
        Shift each face's offset to touch at zero before each stop (see the module).
    on_step
        Called as ``on_step(record, step, pad_wear, rotor_wear)`` with the wear since
        the routine's start, after the rust layer has taken it.

    Yields
    ------
    StopResult
        One per application, as it finishes.
    """
    if heat is not None and thermal is not None:
        raise DutyError("run_routine: give heat (a reduced rotor) or thermal (the full "
                        "model), not both")
    itf = _WarmStart(interface)
    g = model.geometry
    n = itf.area.size
    gap0 = np.zeros(n) if gap0 is None else np.asarray(gap0, dtype=float)
    out = outboard_nodes(itf.x, g.rotor.thickness)
    band = (g.pad.inner_radius, g.pad.outer_radius)
    pad_w, rot_w = np.zeros(n), np.zeros(itf.rotor_area.size)
    last_p, t, last_u = None, 0.0, None
    for i, app in enumerate(schedule):
        if not app.braked:              # a pause: the bodies cool
            res = _dwell(app, model, itf, rust, mu_iron, numerics, heat, thermal, vehicle)
        elif isinstance(app, Stop):
            mu = rust.friction(mu_iron, last_p)
            c_th = 0.0 if heat is None else _predicted_coning(heat, app, vehicle, last_u,
                                                              coning_per_k)
            offset = gap0 + pad_w + itf.W @ rot_w
            if c_th:
                offset = offset + nonconformity_gap(itf.x, *band, g.rotor.thickness, c_th)
            if shift_faces:
                offset = _face_shift(offset, out)
            base_p, base_r = pad_w.copy(), rot_w.copy()

            def step(rec, s, pw, rw, base_r=base_r, base_p=base_p):
                rust.update(base_r + rw)
                if on_step is not None:
                    on_step(rec, s, base_p + pw, base_r + rw)
            rec = next(iter(run_schedule(Run(model, pad_law=rust.pad_law, rotor_law=rust.rotor_law, mu=mu, schedule=[app], vehicle=vehicle, numerics=numerics, interface=itf, thermal=thermal, initial_gap=offset), on_step=step)))
            pad_w, rot_w = base_p + rec.pad_wear, base_r + rec.rotor_wear
            rec.pad_wear, rec.rotor_wear = pad_w.copy(), rot_w.copy()
            last_p = rec.pressure
            if heat is not None:
                power = _stop_power(rec, itf, mu, 2 if model.full else 1)
                last_u = heat.ring_powers(itf.r, power, out, mirror=not model.full)
                heat.heat(last_u, rec.duration, rec.omega0, rec.omega1)
            res = StopResult(rec, mu, c_th)
        else:
            raise DutyError(f"application {i}: {app!r} is not a Stop or a Dwell")
        res.record.index, res.record.t_start = i, t
        t += res.record.duration
        if heat is not None:
            res.T_ring, res.T_hat = heat.T_ring, heat.T_hat
        yield res


def _stop_power(rec, itf, mu: float, faces: int) -> np.ndarray:
    """Each pad node's friction power at the stop's start (W), distributed as ``p r A``
    of its end pressure and scaled to its friction work (a power falling linearly to
    zero over the stop: twice the mean at the start); ``faces`` the faces modelled."""
    shape = np.maximum(rec.pressure, 0.0) * itf.r * itf.area
    total = rec.friction_face_J * faces
    return shape / max(shape.sum(), 1e-300) * 2.0 * total / rec.duration


def _predicted_coning(heat, app: Stop, vehicle, last_u, per_k: float) -> float:
    """The reduced rotor's mean thermal coning over the coming stop: a copy run through
    it with the last stop's ring powers scaled to this stop's demand (before any stop:
    spread evenly over the input rings), the coning averaged over its start and end;
    the reduced rotor is put back as it was."""
    start = heat.coning(per_k)
    if app.decel is None:             # its length is known only once its torque is
        return start
    e = vehicle.stop_energy(app.v0, app.v1, app.decel)
    power0 = 2.0 * (2 * e["face_J"]) / e["duration"] * heat.share   # into the rotor, W
    if last_u is None or not last_u.sum() > 0:
        u = np.full(heat.inputs.size, power0 / heat.inputs.size)
    else:
        u = last_u * (power0 / last_u.sum())
    saved = heat.state()
    heat.heat(u, e["duration"], vehicle.rotor_speed(app.v0), vehicle.rotor_speed(app.v1))
    end = heat.coning(per_k)
    heat.restore(saved)
    return 0.5 * (start + end)


def _dwell(app: Dwell, model, itf, rust, mu_iron, numerics, heat, thermal, vehicle):
    omega = (app.omega if app.omega is not None else
             vehicle.rotor_speed(app.speed) if app.speed is not None else 0.0)
    if thermal is not None:
        rec = next(iter(run_schedule(Run(model, pad_law=rust.pad_law, rotor_law=rust.rotor_law, mu=mu_iron, schedule=[app], vehicle=vehicle, numerics=numerics, interface=itf, thermal=thermal))))
    else:
        from ..duty import ApplicationRecord
        rec = ApplicationRecord(0, "dwell", 0.0, app.duration, omega0=omega, omega1=omega)
        if heat is not None:
            heat.cool(app.duration, omega)
    return StopResult(rec, mu_iron)
