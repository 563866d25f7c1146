"""The vehicle a brake stops, and the brake's torque against its line pressure.

A stop of a vehicle of mass ``m`` at deceleration ``a`` needs a braking
force ``F = m a`` at the tyres (rolling resistance and drag are left out:
they only help the brakes, so the friction work stated is an upper bound).
The motor regenerates ``F_regen = min(s F, T_regen / R)`` (regeneration
share ``s``, regenerative torque limit ``T_regen`` at the wheels, tyre
radius ``R``); the friction brakes take the rest, of which the modelled
brake's axle takes its share (``front_share`` for the front axle) split
over that axle's brakes.  The modelled brake's torque is
``T = F_brake R`` and its rotor turns at ``omega = v / R``.

The brake gives that torque as ``T = n_f mu p_line A_clamp r_eff``:
``n_f = 2`` friction faces clamped with the same force ``p_line A_clamp``
(``A_clamp`` the hydraulic area of one side's pistons together,
``geometry.clamp_area``), and the effective radius of the current
pressure field, ``r_eff = sum(p A r) / sum(p A)`` over the pad's friction
nodes.  So a deceleration gives a line pressure and a line pressure a
deceleration, both through the brake's own pressure field.

Energy of a stop from ``v0`` to ``v1``: the kinetic energy
``E = m (v0^2 - v1^2) / 2``; the motor takes ``E F_regen / F``; the modelled
brake ``E F_brake / F``, half of it on each face.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..checks import check_choice, check_int, check_number
from ..errors import DutyError

__all__ = ["Vehicle", "effective_radius", "brake_torque", "line_pressure_for_torque",
           "G", "FACES"]

#: Standard gravity (m/s^2): the tyre's adhesion limit is ``tyre_mu G``.
G = 9.80665
#: Friction faces of one brake (a floating caliper: both pads, one clamp force).
FACES = 2


def _check(key: str, value, ok: bool, allowed: str, unit: str = "", source: str = "") -> None:
    if not ok:
        where = f"{source}: " if source else ""
        raise DutyError(f"{where}{key} = {value!r}{' ' + unit if unit else ''} is not allowed; "
                        f"{allowed}")


def _finite(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


@dataclass(frozen=True)
class Vehicle:
    """A vehicle braked by the modelled brake (SI units).

    Parameters
    ----------
    mass : float
        Vehicle mass (kg).
    front_share : float
        The front axle's share of the friction braking force (0..1).
    tyre_radius : float
        Rolling radius of the tyres (m).
    brakes_per_axle : int
        Brakes on the modelled brake's axle.
    regen_share : float
        Share of the braking force the motor regenerates (0..1), up to
    regen_torque_limit : float or None
        the motor's largest braking torque at the wheels (N m, all driven
        wheels together); None: no limit.
    axle : str
        ``"front"`` or ``"rear"``: the axle of the modelled brake.
    tyre_mu : float
        Tyre-road adhesion; a deceleration above ``tyre_mu G`` is refused.
    source : str
        Where the values come from (a scene file), named in errors.
    """

    mass: float
    front_share: float = 0.7
    tyre_radius: float = 0.32
    brakes_per_axle: int = 2
    regen_share: float = 0.0
    regen_torque_limit: float | None = None
    axle: str = "front"
    tyre_mu: float = 1.0
    source: str = ""

    def __post_init__(self):
        try:
            self._check()
        except DutyError as e:
            raise DutyError(f"{self.source}: {e}" if self.source else str(e)) from None

    def _check(self) -> None:
        """Each value in its range, shown in the user's units (a scene file's
        ``[units]`` length for ``tyre_radius``)."""
        key = "vehicle."
        check_number(key + "mass", self.mass, 50.0, 1e5, lo_open=False, unit="kg",
                     kind=DutyError)
        check_number(key + "front_share", self.front_share, 0.0, 1.0, lo_open=False,
                     kind=DutyError)
        check_number(key + "tyre_radius", self.tyre_radius, 0.1, 1.0, lo_open=False,
                     unit="m", kind=DutyError)
        check_int(key + "brakes_per_axle", self.brakes_per_axle, 1, kind=DutyError, hi=8)
        check_number(key + "regen_share", self.regen_share, 0.0, 1.0, lo_open=False,
                     kind=DutyError)
        check_number(key + "regen_torque_limit", self.regen_torque_limit, 0.0, lo_open=False,
                     unit="N m", allow_none=True, kind=DutyError)
        check_choice(key + "axle", self.axle, ("front", "rear"), kind=DutyError)
        check_number(key + "tyre_mu", self.tyre_mu, 0.0, 2.0, kind=DutyError)
        share = self.front_share if self.axle == "front" else 1.0 - self.front_share
        _check("vehicle.front_share", self.front_share, share > 0,
               f"the modelled brake's axle ({self.axle}) takes no braking force")

    # ------------------------------------------------------------------ forces --
    @property
    def axle_share(self) -> float:
        """The modelled brake's axle's share of the friction braking force."""
        return self.front_share if self.axle == "front" else 1.0 - self.front_share

    def check_deceleration(self, decel: float, key: str = "deceleration") -> None:
        """Refuse a deceleration <= 0 or above the tyres' adhesion (``tyre_mu G``)."""
        _check(key, decel, _finite(decel) and 0 < decel <= self.tyre_mu * G,
               f"need 0 < deceleration <= tyre_mu g = {self.tyre_mu * G:.3g} m/s^2 (what the "
               "tyres can give)", "m/s^2", self.source)

    def regen_force(self, decel: float) -> float:
        """Braking force the motor takes at ``decel`` (N)."""
        F = self.mass * decel
        limit = math.inf if self.regen_torque_limit is None else \
            self.regen_torque_limit / self.tyre_radius
        return min(self.regen_share * F, limit)

    def brake_force(self, decel: float) -> float:
        """Braking force at the tyre of the modelled brake's wheel (N)."""
        return ((self.mass * decel - self.regen_force(decel)) * self.axle_share
                / self.brakes_per_axle)

    def brake_torque(self, decel: float) -> float:
        """Torque the modelled brake must give at ``decel`` (N m)."""
        return self.brake_force(decel) * self.tyre_radius

    def deceleration(self, torque: float) -> float:
        """The deceleration the vehicle reaches when the modelled brake gives ``torque`` (N m).

        The inverse of :meth:`brake_torque` (every brake of the axle alike,
        the other axle in its share, the motor regenerating its part).
        """
        friction = torque / self.tyre_radius * self.brakes_per_axle / self.axle_share
        F = friction / (1.0 - self.regen_share) if self.regen_share < 1 else math.inf
        if self.regen_torque_limit is not None and \
                self.regen_share * F > self.regen_torque_limit / self.tyre_radius:
            F = friction + self.regen_torque_limit / self.tyre_radius
        return F / self.mass

    def rotor_speed(self, v: float) -> float:
        """Rotor speed (rad/s) at vehicle speed ``v`` (m/s)."""
        return v / self.tyre_radius

    # ------------------------------------------------------------------ energy --
    def stop_energy(self, v0: float, v1: float, decel: float) -> dict:
        """Energy of a stop from ``v0`` to ``v1`` (m/s) at ``decel`` (J).

        ``kinetic_J`` of the vehicle; ``regenerated_J`` by the motor;
        ``brake_J`` dissipated by the modelled brake, ``face_J`` on each of
        its faces.
        """
        E = 0.5 * self.mass * (v0 * v0 - v1 * v1)
        F = self.mass * decel
        brake = E * self.brake_force(decel) / F
        return {"kinetic_J": E, "regenerated_J": E * self.regen_force(decel) / F,
                "brake_J": brake, "face_J": brake / FACES}


def effective_radius(pressure: np.ndarray, area: np.ndarray, r: np.ndarray) -> float:
    """Effective friction radius of a pressure field, ``sum(p A r) / sum(p A)`` (m)."""
    load = np.maximum(np.asarray(pressure, dtype=float), 0.0) * area
    total = float(load.sum())
    if not total > 0:
        raise DutyError("the pad carries no load: no effective radius (is it out of contact?)")
    return float((load * r).sum() / total)


def brake_torque(line_pressure: float, mu: float, clamp_area: float, r_eff: float,
                 faces: int = FACES) -> float:
    """``T = faces mu p_line A_clamp r_eff`` (N m); ``A_clamp`` (m^2) the hydraulic
    area of one side's pistons together."""
    return faces * mu * line_pressure * clamp_area * r_eff


def line_pressure_for_torque(torque: float, mu: float, clamp_area: float, r_eff: float,
                             faces: int = FACES) -> float:
    """The line pressure (Pa) that gives ``torque`` (N m): the inverse of :func:`brake_torque`."""
    if not mu > 0:
        raise DutyError(f"mu = {mu!r}: a brake without friction gives no torque; need mu > 0 "
                        "for a stop at a given deceleration")
    return torque / (faces * mu * clamp_area * r_eff)
