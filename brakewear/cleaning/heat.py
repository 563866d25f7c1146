"""The heat of a schedule's stops as the gap it cones: a schedule state.

A routine of stops heats the hat rotor's ring; the ring, hotter than the
hat, cones, and the coning opens the gap at the outer radius of one face
and at the inner radius of the other (:func:`~brakewear.cleaning.corrosion.
nonconformity_gap`).  :class:`RotorHeat` carries the rotor's temperatures
from application to application by its reduced model
(:class:`~brakewear.thermal.reduced.ReducedRotorHeat`) and, as a schedule
state (:mod:`brakewear.duty.states`), gives each stop the mean thermal
coning it will see -- predicted by running a copy of the reduced rotor
through the stop first with the last stop's ring powers scaled to this
stop's demand, averaged over its start and end, then put back -- as an
extra gap; after the stop the reduced rotor takes the stop's own heat (its
friction work, distributed as ``p r A`` of its end pressure), and in a
pause it cools at the rotor's speed.
"""
from __future__ import annotations

import logging
from typing import ClassVar

import numpy as np

from ..duty.states import register_state
from ..errors import ThermalError
from .corrosion import nonconformity_gap, outboard_nodes

logger = logging.getLogger(__name__)

__all__ = ["RotorHeat", "stop_ring_powers"]


def stop_ring_powers(heat, record, itf, faces: int, outboard: np.ndarray) -> np.ndarray:
    """The ring powers (W, :meth:`~brakewear.thermal.reduced.ReducedRotorHeat.ring_powers`)
    of a braked application's start: each pad node's friction power distributed as
    ``p r A`` of its end pressure and scaled to its friction work (a power falling
    linearly to zero over the stop: twice the mean at the start); ``faces`` the
    faces modelled (1: the inboard nodes stand for both)."""
    shape = np.maximum(record.pressure, 0.0) * itf.r * itf.area
    total = record.friction_face_J * faces
    power = shape / max(shape.sum(), 1e-300) * 2.0 * total / record.duration
    return heat.ring_powers(itf.r, power, outboard, mirror=faces == 1)


@register_state
class RotorHeat:
    """The rotor's heat over a schedule and the thermal coning it gives each stop.

    Parameters
    ----------
    heat
        A :class:`~brakewear.thermal.reduced.ReducedRotorHeat` of the brake's rotor
        (its state is the schedule's start; it is changed as the schedule runs).
    interface
        The schedule's interface (``x``, ``r``, ``area`` of the pad friction nodes).
    band, thickness
        The friction band ``(r_in, r_out)`` (m) and the rotor's thickness (m).
    per_kelvin
        The thermal coning across the pad per kelvin of ring over hat (m/K).
    faces
        The friction faces the interface models (2: both; 1: the inboard pad stands
        for both).
    """

    name: ClassVar[str] = "rotor_heat"

    def __init__(self, heat, interface, band: tuple[float, float], thickness: float,
                 per_kelvin: float, faces: int = 2):
        if not (np.isfinite(per_kelvin) and per_kelvin >= 0):
            raise ThermalError(f"per_kelvin = {per_kelvin!r} m/K is not allowed; need >= 0")
        self.heat, self.itf, self.band, self.thickness = heat, interface, band, thickness
        self.per_kelvin, self.faces = float(per_kelvin), int(faces)
        self.outboard = outboard_nodes(interface.x, thickness)
        self.last_powers = None
        self.coning = 0.0

    def before(self, app, context: dict) -> dict | None:
        """The stop's mean thermal coning as a gap (a pause: none)."""
        self.coning = 0.0
        if not app.braked:
            return None
        self.coning = self._predicted(app, context["vehicle"])
        if self.coning == 0.0:
            return None
        return {"gap": nonconformity_gap(self.itf.x, *self.band, self.thickness, self.coning)}

    def step(self, pad_wear, rotor_wear) -> None:
        """Nothing: the heat enters once the stop's friction work is known."""

    def after(self, record) -> dict:
        """Heat the reduced rotor with the stop's work, or cool it over a pause; its
        ring and hat temperatures (K) and the coning the stop ran with (m)."""
        if record.braked:
            self.last_powers = stop_ring_powers(self.heat, record, self.itf, self.faces,
                                                self.outboard)
            self.heat.heat(self.last_powers, record.duration, record.omega0, record.omega1)
        else:
            self.heat.cool(record.duration, record.omega0)
        return {"thermal_coning": self.coning, "T_ring": self.heat.T_ring,
                "T_hat": self.heat.T_hat}

    def _predicted(self, app, vehicle) -> float:
        """The mean coning over the coming stop (see the module); the coning now where
        its length is not known before it runs (a stop under a line pressure)."""
        heat = self.heat
        start = heat.coning(self.per_kelvin)
        if getattr(app, "decel", None) is None or vehicle is None:
            return start
        e = vehicle.stop_energy(app.v0, app.v1, app.decel)
        power0 = 2.0 * (2 * e["face_J"]) / e["duration"] * heat.share   # into the rotor, W
        last = self.last_powers
        if last is None or not last.sum() > 0:
            u = np.full(heat.inputs.size, power0 / heat.inputs.size)
        else:
            u = last * (power0 / last.sum())
        saved = heat.state()
        heat.heat(u, e["duration"], vehicle.rotor_speed(app.v0), vehicle.rotor_speed(app.v1))
        end = heat.coning(self.per_kelvin)
        heat.restore(saved)
        return 0.5 * (start + end)
