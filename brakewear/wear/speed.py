"""Rotor speed over a wear history: constant (a drag) or falling linearly (a stop).

The wear loop needs, for a step from ``t`` to ``t + dt``, the rotor angle
swept, ``theta(t + dt) - theta(t)``: with a wear rate linear in the sliding
speed (Archard, ``b = 1``) and a contact pressure that does not depend on
the speed, the wear of a step is ``k p r`` times that angle, whatever the
speed did within the step, and the frictional heat is ``mu p r`` times it.
So the loop takes each step at its *mean* speed, ``Delta theta / dt``, and
wear and heat are integrated exactly over ``omega(t)``.

With fixed steps (``Numerics(steps=N)``) a profile's steps are equal in
*angle*, not in time: a stop and a drag over the same angle then take the
same ``N`` steps of the same sliding distance, and with isothermal Archard
wear they wear identically (to round-off).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import WearError

__all__ = ["ConstantSpeed", "LinearSpeed", "as_speed"]


@dataclass(frozen=True)
class ConstantSpeed:
    """A rotor turning at a constant speed.

    Parameters
    ----------
    omega
        The speed (rad/s), > 0.
    """

    omega: float

    def __post_init__(self):
        if not (math.isfinite(self.omega) and self.omega > 0):
            raise WearError(f"omega = {self.omega!r} rad/s is not allowed; need a rotor "
                            "speed > 0")

    def at(self, t: float) -> float:
        """Speed at time ``t`` (rad/s)."""
        return self.omega

    def angle(self, t: float) -> float:
        """Angle turned from 0 to ``t`` (rad)."""
        return self.omega * t

    def mean(self, t: float, dt: float) -> float:
        """Mean speed over ``[t, t + dt]`` (rad/s)."""
        return self.omega

    def time_at_angle(self, theta: float) -> float:
        """When the rotor has turned ``theta`` (s)."""
        return theta / self.omega


@dataclass(frozen=True)
class LinearSpeed:
    """A speed falling (or rising) linearly from ``omega0`` to ``omega1`` over ``duration``.

    A stop at constant deceleration: ``omega(t) = omega0 + (omega1 - omega0) t / duration``.

    Parameters
    ----------
    omega0, omega1
        The speeds at the start and the end (rad/s), both >= 0, not both zero.
    duration
        Its length (s), > 0.
    """

    omega0: float
    omega1: float
    duration: float

    def __post_init__(self):
        for name in ("omega0", "omega1"):
            w = getattr(self, name)
            if not (math.isfinite(w) and w >= 0):
                raise WearError(f"{name} = {w!r} rad/s is not allowed; need a rotor speed >= 0")
        if self.omega0 + self.omega1 <= 0:
            raise WearError("omega0 = omega1 = 0: the rotor does not turn; need a speed > 0")
        if not (math.isfinite(self.duration) and self.duration > 0):
            raise WearError(f"duration = {self.duration!r} s is not allowed; need > 0")

    @property
    def _slope(self) -> float:
        return (self.omega1 - self.omega0) / self.duration

    def at(self, t: float) -> float:
        return self.omega0 + self._slope * t

    def angle(self, t: float) -> float:
        return t * (self.omega0 + 0.5 * self._slope * t)

    def mean(self, t: float, dt: float) -> float:
        # exact for a linear speed: the speed at the middle of the step
        return self.omega0 + self._slope * (t + 0.5 * dt)

    def time_at_angle(self, theta: float) -> float:
        """When the rotor has turned ``theta`` (s); the end of the profile for the whole
        angle, exactly.

        The root of ``theta = omega0 t + slope t^2 / 2`` taken from the nearer end:
        near the end of a stop to rest the speed goes to zero, and the root from the
        start would lose half the digits (``b^2 - 4ac`` cancels: the last of ``N``
        equal angles ended ``1e-8`` of the stop short of its end, where the next fixed
        step was zero long).  From the end, ``phi = theta(T) - theta`` is the angle
        left and ``tau = T - t`` solves ``omega1 tau - slope tau^2 / 2 = phi``
        without cancellation.
        """
        total = self.angle(self.duration)
        if self._slope < 0 and theta > 0.5 * total:
            phi = max(total - theta, 0.0)
            c = self.omega1 + math.sqrt(self.omega1 ** 2 - 2.0 * self._slope * phi)
            return self.duration - (2.0 * phi / c if c > 0 else 0.0)
        a, b = 0.5 * self._slope, self.omega0
        disc = max(b * b + 4.0 * a * theta, 0.0)
        return 2.0 * theta / (b + math.sqrt(disc)) if b + math.sqrt(disc) > 0 else 0.0


def as_speed(omega) -> ConstantSpeed | LinearSpeed:
    """A speed profile from a number (rad/s) or a profile."""
    if isinstance(omega, (ConstantSpeed, LinearSpeed)):
        return omega
    try:
        w = float(omega)
    except (TypeError, ValueError):
        raise WearError(f"omega = {omega!r} is neither a rotor speed (rad/s) nor a speed "
                        "profile (ConstantSpeed, LinearSpeed)") from None
    return ConstantSpeed(w)
