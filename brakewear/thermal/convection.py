"""Convection that follows the rotor's speed.

A spinning rotor sheds heat to the air it drags along; the coefficient grows
with speed.  :class:`SpeedConvection` is the power law

    h(omega) = h_static + (h_ref - h_static) (omega / omega_ref)^n,

``h_static`` the still-air value (natural convection and linearised
radiation), ``h_ref`` the value at ``omega_ref``.  The exponent states the
flow: ``n = 0.5`` for the laminar boundary layer of a solid disc spinning in
air (von Karman's rotating disc: ``Nu = 0.33 Re^0.5`` with ``Re = omega
r^2 / nu``, so ``h = 0.33 k_air sqrt(omega / nu)``, uniform over the face),
``n = 0.8`` for the turbulent flow through a vented rotor's vanes (the
Dittus-Boelter form of Limpert's vane correlation, the vane air speed
proportional to omega).  :meth:`SpeedConvection.solid` and
:meth:`SpeedConvection.vented` give such laws with stated, illustrative
magnitudes (calibrate them: measured cooling curves of the rotor are the
usual source).

Radiation (``ThermalModel(emissivity=...)``) adds ``h_rad = eps sigma (T_s^2
+ T_a^2) (T_s + T_a)`` on the same faces, linearised about the mean
temperature ``T_s`` of the body's convective faces at the start of each
step (:func:`radiation_coefficient`): the step stays linear and its heat
balance exact; the lag is that of the staggered coupling.

The thermal model takes ``h`` at each step's mean speed, rounded to an
eighth of an octave (a factor 2^(1/8), at most 4.4 % off) so that a stop's
continuously falling speed factorises the heat matrices a few times, not
once per step; the rounding is part of the model, so a resumed run repeats
the uninterrupted one.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ..errors import ThermalError

logger = logging.getLogger(__name__)

__all__ = ["SpeedConvection", "K_AIR", "NU_AIR", "SIGMA", "radiation_coefficient"]

#: Stefan-Boltzmann constant (W/m^2 K^4).
SIGMA = 5.670374419e-8

#: Thermal conductivity (W/m K) and kinematic viscosity (m^2/s) of air at about 50 C.
K_AIR, NU_AIR = 0.028, 1.8e-5

#: Rounding of the convection scale: 2^(1/ROUNDING) steps.
ROUNDING = 8


@dataclass(frozen=True)
class SpeedConvection:
    """``h(omega) = h_static + (h_ref - h_static) (omega / omega_ref)^exponent`` (W/m^2 K).

    Parameters
    ----------
    h_ref
        Coefficient at ``omega_ref`` (W/m^2 K, > 0).
    omega_ref
        Reference rotor speed (rad/s, > 0).
    exponent
        Speed exponent (0.5 laminar solid disc, 0.8 turbulent vented), in (0, 2].
    h_static
        Coefficient at rest (W/m^2 K, 0 <= h_static <= h_ref).
    """

    h_ref: float
    omega_ref: float
    exponent: float = 0.5
    h_static: float = 0.0

    def __post_init__(self):
        for key, lo in (("h_ref", 0.0), ("omega_ref", 0.0)):
            v = getattr(self, key)
            if not (isinstance(v, (int, float)) and np.isfinite(v) and v > lo):
                raise ThermalError(f"SpeedConvection: {key} = {v!r} is not allowed; need > 0")
        if not (np.isfinite(self.exponent) and 0.0 < self.exponent <= 2.0):
            raise ThermalError(f"SpeedConvection: exponent = {self.exponent!r} is not allowed; "
                               "need 0 < exponent <= 2 (0.5 laminar, 0.8 turbulent)")
        if not (np.isfinite(self.h_static) and 0.0 <= self.h_static <= self.h_ref):
            raise ThermalError(f"SpeedConvection: h_static = {self.h_static!r} W/m^2 K is not "
                               f"allowed; need 0 <= h_static <= h_ref = {self.h_ref!r}")

    @classmethod
    def solid(cls, h_static: float = 10.0) -> SpeedConvection:
        """A solid rotor: von Karman's laminar rotating disc, ``h = 0.33 k_air
        sqrt(omega / nu_air)`` (16.2 W/m^2 K at 55 rad/s), on top of ``h_static``."""
        omega_ref = 55.0
        h = 0.33 * K_AIR * np.sqrt(omega_ref / NU_AIR)
        return cls(h_static + h, omega_ref, 0.5, h_static)

    @classmethod
    def vented(cls, h_ref: float = 100.0, h_static: float = 10.0) -> SpeedConvection:
        """A vented rotor: turbulent vane flow, ``h ~ omega^0.8``, ``h_ref`` at 55 rad/s
        (about 70 km/h on a 0.32 m tyre; illustrative: 50-150 W/m^2 K is the usual
        range over the whole rotor surface at that speed)."""
        return cls(h_ref, 55.0, 0.8, h_static)

    def h(self, omega: float) -> float:
        """The coefficient (W/m^2 K) at rotor speed ``omega`` (rad/s, >= 0)."""
        if not (np.isfinite(omega) and omega >= 0):
            raise ThermalError(f"rotor speed {omega!r} rad/s is not allowed; need >= 0")
        return self.h_static + (self.h_ref - self.h_static) * (omega / self.omega_ref) \
            ** self.exponent

    def scale(self, omega: float) -> float:
        """``h(omega) / h_ref`` rounded to 2^(1/8) (see the module docstring)."""
        return rounded(self.h(omega) / self.h_ref)


def rounded(s: float) -> float:
    """``s`` (>= 0) rounded to the nearest power of 2^(1/8) (0 stays 0)."""
    if s == 0.0:
        return 0.0
    return float(2.0 ** (np.round(ROUNDING * np.log2(s)) / ROUNDING))


def radiation_coefficient(emissivity: float, T_surface: float, T_ambient: float) -> float:
    """Radiation to the surroundings linearised about the surface temperature (W/m^2 K):
    ``eps sigma (T^4 - T_a^4) = h_rad (T - T_a)``, ``h_rad = eps sigma (T^2 + T_a^2)
    (T + T_a)`` (temperatures in K); 5.7 W/m^2 K for eps = 0.6 at 100 C, 45 at 600 C."""
    return float(emissivity * SIGMA * (T_surface ** 2 + T_ambient ** 2)
                 * (T_surface + T_ambient))
