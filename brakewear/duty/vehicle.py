"""The vehicle a brake stops: its road load, its controller's regenerative blending,
and the brake's torque against its line pressure.

Forces at the tyres, ``v`` the vehicle speed (SI units):

* **demand** -- decelerating the car at ``a`` takes ``lambda m a``
  (``lambda`` = ``inertia_factor``: the wheels, motor and driveline turn too);
* **road load** -- ``F_road(v) = C_rr m g + F_dt + rho CdA v^2 / 2`` (rolling
  resistance, drivetrain drag at the wheels, aerodynamic drag) helps the
  brakes, which supply ``F_b(v) = lambda m a - F_road(v)``; where the road load
  alone decelerates the car harder than ``a``, the motor must drive
  (``propulsion_J``) and the brakes give nothing;
* **regeneration**, as the controller blends it --
  ``F_regen = fade(v) min(s F_b, T_regen / R, P_regen / v, m a_regen)``: the
  share ``s`` of the braking it asks of the motor (``regen_share``), limited by
  the motor's torque at the wheels, its power and the deceleration up to which
  the controller blends, and faded out linearly below ``regen_full_speed`` to
  nothing at ``regen_cutoff_speed``;
* **friction** -- ``F_f = F_b - F_regen``, the modelled brake's axle its share
  (``front_share`` for the front axle), split over that axle's brakes:
  ``T = F_f axle_share R / brakes_per_axle``, rotor speed ``omega = v / R``.

A *cleaning routine* is what the controller must command: friction-only stops
(``with_friction_share(1.0)``: no regeneration) or a friction share.

A stop at a constant deceleration from ``v0`` to ``v1`` integrates these
forces over its speed (:meth:`Vehicle.stop_energy`): ``kinetic + propulsion =
road + regenerated + friction`` exactly; the brake's torque held over the stop
is its friction work over its rotor angle (:meth:`Vehicle.stop_torque`).  A
stop under a constant brake torque decelerates as ``(F_f + F_regen + F_road) /
(lambda m)`` at each speed, integrated for its distance and time.

The brake gives its torque as ``T = n_f mu p_line A_clamp r_eff``: ``n_f = 2``
friction faces clamped with the same force ``p_line A_clamp`` (``A_clamp`` the
hydraulic area of one side's pistons together, ``geometry.clamp_area``), and
the effective radius of the current pressure field, ``r_eff = sum(p A r) /
sum(p A)`` over the pad's friction nodes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..checks import check_choice, check_int, check_number, check_order
from ..errors import DutyError

__all__ = ["Vehicle", "study_car", "effective_radius", "brake_torque",
           "line_pressure_for_torque", "G", "FACES"]

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


#: (key, lower bound, upper bound, unit) of the road-load and blending inputs
_RANGES = (("inertia_factor", 1.0, 1.5, ""), ("rolling_resistance", 0.0, 0.05, ""),
           ("drag_area", 0.0, 20.0, "m^2"), ("air_density", 0.5, 1.5, "kg/m^3"),
           ("drivetrain_drag", 0.0, 1e4, "N"), ("regen_cutoff_speed", 0.0, 50.0, "m/s"),
           ("regen_full_speed", 0.0, 50.0, "m/s"))


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
        Share of the braking force the controller asks of the motor (0..1;
        1: regeneration first, the friction brakes take what it cannot), up to
    regen_torque_limit : float or None
        the motor's largest braking torque at the wheels (N m, all driven
        wheels together); None: no limit;
    regen_power_limit : float or None
        its largest regenerative power (W); None: no limit;
    regen_decel_limit : float or None
        the deceleration (m/s^2) up to which the controller blends: the motor
        takes at most ``mass regen_decel_limit``; None: no limit.
    regen_cutoff_speed, regen_full_speed : float
        Below ``regen_cutoff_speed`` (m/s) no regeneration, full above
        ``regen_full_speed``, linear between (0, 0: no fade-out).
    axle : str
        ``"front"`` or ``"rear"``: the axle of the modelled brake.
    tyre_mu : float
        Tyre-road adhesion; a deceleration above ``tyre_mu G`` is refused.
    inertia_factor : float
        Equivalent mass of the turning parts over the mass (>= 1): the demand is
        ``inertia_factor mass a``, the kinetic energy ``inertia_factor mass v^2 / 2``.
    rolling_resistance : float
        Rolling-resistance coefficient ``C_rr`` (the force ``C_rr mass G``).
    drag_area : float
        Aerodynamic drag area ``C_d A`` (m^2).
    air_density : float
        Density of the air (kg/m^3).
    drivetrain_drag : float
        Drag of the driveline and of the brakes' residual drag at the wheels (N).
    source : str
        Where the values come from (a scene file), named in errors.

    Notes
    -----
    The road-load and blending inputs default to none (no road load, no fade-out,
    no power limit): the brakes then take all of the kinetic energy the motor
    does not, an upper bound.  :func:`study_car` is a car with all of them.
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
    regen_power_limit: float | None = None
    regen_decel_limit: float | None = None
    regen_cutoff_speed: float = 0.0
    regen_full_speed: float = 0.0
    inertia_factor: float = 1.0
    rolling_resistance: float = 0.0
    drag_area: float = 0.0
    air_density: float = 1.2
    drivetrain_drag: float = 0.0

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
        for name, unit in (("regen_torque_limit", "N m"), ("regen_power_limit", "W"),
                           ("regen_decel_limit", "m/s^2")):
            check_number(key + name, getattr(self, name), 0.0, lo_open=False, unit=unit,
                         allow_none=True, kind=DutyError)
        check_choice(key + "axle", self.axle, ("front", "rear"), kind=DutyError)
        check_number(key + "tyre_mu", self.tyre_mu, 0.0, 2.0, kind=DutyError)
        for name, lo, hi, unit in _RANGES:
            check_number(key + name, getattr(self, name), lo, hi, lo_open=False, unit=unit,
                         kind=DutyError)
        check_order(key + "regen_cutoff_speed", self.regen_cutoff_speed,
                    key + "regen_full_speed", self.regen_full_speed, "m/s", strict=False,
                    kind=DutyError, why="regeneration fades out below the full speed")
        share = self.front_share if self.axle == "front" else 1.0 - self.front_share
        _check("vehicle.front_share", self.front_share, share > 0,
               f"the modelled brake's axle ({self.axle}) takes no braking force")

    # ------------------------------------------------------------------ forces --
    @property
    def axle_share(self) -> float:
        """The modelled brake's axle's share of the friction braking force."""
        return self.front_share if self.axle == "front" else 1.0 - self.front_share

    @property
    def speed_dependent(self) -> bool:
        """Whether a force depends on the speed (road load, regeneration's power
        limit or fade-out): the force calls then need the speed."""
        return bool(self.road_force(0.0) > 0 or self.drag_area > 0 or
                    (self.regen_share > 0 and (self.regen_power_limit is not None or
                                               self.regen_full_speed > 0)))

    def with_friction_share(self, share: float) -> Vehicle:
        """The vehicle as its controller runs a routine that gives the friction brakes at
        least ``share`` (0..1) of the braking: ``regen_share`` at most ``1 - share``
        (``share = 1``: friction-only stops)."""
        check_number("friction_share", share, 0.0, 1.0, lo_open=False, kind=DutyError)
        return replace(self, regen_share=min(self.regen_share, 1.0 - share))

    def check_deceleration(self, decel: float, key: str = "deceleration") -> None:
        """Refuse a deceleration <= 0 or above the tyres' adhesion (``tyre_mu G``)."""
        _check(key, decel, _finite(decel) and 0 < decel <= self.tyre_mu * G,
               f"need 0 < deceleration <= tyre_mu g = {self.tyre_mu * G:.3g} m/s^2 (what the "
               "tyres can give)", "m/s^2", self.source)

    def _speed(self, v):
        if v is None:
            if self.speed_dependent:
                raise DutyError("this vehicle's road load or regeneration depends on the speed: "
                                "give the speed v (m/s)")
            return 0.0
        return v

    def road_force(self, v) -> np.ndarray | float:
        """Road load at speed ``v`` (m/s): rolling resistance, drivetrain drag and
        aerodynamic drag (N)."""
        return (self.rolling_resistance * self.mass * G + self.drivetrain_drag
                + 0.5 * self.air_density * self.drag_area * np.square(v))

    def braking_demand(self, decel: float, v=None):
        """Braking force the brakes (motor and friction) supply at ``decel`` and speed
        ``v``: ``lambda m a - F_road(v)``, at least 0 (N)."""
        v = self._speed(v)
        return np.maximum(self.inertia_factor * self.mass * decel - self.road_force(v), 0.0)

    def _regen_cap_and_fade(self, v):
        """The motor's largest braking force and the fade factor at speed ``v``."""
        v = np.asarray(v, dtype=float)
        cap = np.full(v.shape, np.inf)
        if self.regen_torque_limit is not None:
            cap = np.minimum(cap, self.regen_torque_limit / self.tyre_radius)
        if self.regen_decel_limit is not None:
            cap = np.minimum(cap, self.mass * self.regen_decel_limit)
        if self.regen_power_limit is not None:
            cap = np.minimum(cap, self.regen_power_limit / np.maximum(v, 1e-300))
        lo, hi = self.regen_cutoff_speed, self.regen_full_speed
        fade = np.ones(v.shape) if hi <= 0 else (
            np.clip((v - lo) / (hi - lo), 0.0, 1.0) if hi > lo else (v >= hi).astype(float))
        return cap, fade

    def _regen_of_demand(self, demand, v):
        cap, fade = self._regen_cap_and_fade(v)
        return fade * np.minimum(self.regen_share * demand, cap)

    def regen_force(self, decel: float, v=None):
        """Braking force the motor takes at ``decel`` and speed ``v`` (N)."""
        v = self._speed(v)
        return self._regen_of_demand(self.braking_demand(decel, v), v)

    def friction_force(self, decel: float, v=None):
        """Braking force of all the friction brakes at ``decel`` and speed ``v`` (N)."""
        v = self._speed(v)
        demand = self.braking_demand(decel, v)
        return demand - self._regen_of_demand(demand, v)

    def brake_force(self, decel: float, v=None):
        """Braking force at the tyre of the modelled brake's wheel (N)."""
        return self.friction_force(decel, v) * self.axle_share / self.brakes_per_axle

    def brake_torque(self, decel: float, v=None):
        """Torque the modelled brake must give at ``decel`` and speed ``v`` (N m)."""
        return self.brake_force(decel, v) * self.tyre_radius

    def deceleration(self, torque: float, v=None) -> float:
        """The deceleration the vehicle has at speed ``v`` when the modelled brake gives
        ``torque`` (N m): the inverse of :meth:`brake_torque` (every brake of the axle
        alike, the other axle in its share, the motor blending its part, the road load)."""
        v = self._speed(v)
        friction = torque / self.tyre_radius * self.brakes_per_axle / self.axle_share
        cap, fade = (float(x) for x in self._regen_cap_and_fade(v))
        s = fade * self.regen_share          # F_f = F_b (1 - s) until the motor's cap
        demand = friction / (1.0 - s) if s < 1 else math.inf
        if self.regen_share * demand > cap:
            demand = friction + fade * cap
        return float((demand + self.road_force(v)) / (self.inertia_factor * self.mass))

    def rotor_speed(self, v: float) -> float:
        """Rotor speed (rad/s) at vehicle speed ``v`` (m/s)."""
        return v / self.tyre_radius

    # ------------------------------------------------------------------ energy --
    def stop_energy(self, v0: float, v1: float, decel: float | None = None, *,
                    torque: float | None = None) -> dict:
        """Energy of a stop from ``v0`` to ``v1`` (m/s) at the constant deceleration
        ``decel`` (m/s^2) or under the modelled brake's constant ``torque`` (N m).

        Returns (J unless named) ``kinetic_J`` (with the turning parts),
        ``road_J`` taken by the road load, ``regenerated_J`` by the motor,
        ``friction_J`` of all the friction brakes, ``brake_J`` of the modelled
        brake and ``face_J`` of each of its faces, ``propulsion_J`` the motor
        must add where the road load alone decelerates more than ``decel``
        (``kinetic + propulsion = road + regenerated + friction``); ``decel``
        (the constant one, or under a torque the one of a linear speed profile
        with the stop's distance: the rotor angle is the stop's), ``decel_max``,
        ``duration`` (s), ``distance`` (m) and ``rotor_angle`` (rad).
        """
        if (decel is None) == (torque is None):
            raise DutyError("stop_energy needs exactly one of decel (m/s^2) and torque (N m)")
        _check("v0", v0, _finite(v0) and v0 > 0, "need a speed > 0", "m/s")
        _check("v1", v1, _finite(v1) and 0 <= v1 < v0, f"need 0 <= v1 < v0 = {v0:g}", "m/s")
        out = self._decel_stop(v0, v1, decel) if torque is None else \
            self._torque_stop(v0, v1, torque)
        out["brake_J"] = out["friction_J"] * self.axle_share / self.brakes_per_axle
        out["face_J"] = out["brake_J"] / FACES
        out["rotor_angle"] = out["distance"] / self.tyre_radius
        return out

    def stop_torque(self, v0: float, v1: float, decel: float) -> float:
        """The modelled brake's torque held over a stop at ``decel`` (N m): its friction
        work over the stop's rotor angle (the torque whose work is the stop's)."""
        e = self.stop_energy(v0, v1, decel)
        return e["brake_J"] / e["rotor_angle"]

    def _kinetic(self, v0: float, v1: float) -> float:
        return 0.5 * self.inertia_factor * self.mass * (v0 * v0 - v1 * v1)

    def _breaks(self, v1: float, v0: float, extra=()) -> list:
        """Speeds inside (v1, v0) where a force changes its form (for the quadrature)."""
        pts = [self.regen_cutoff_speed, self.regen_full_speed, *extra]
        caps = [c for c in (self.regen_torque_limit and self.regen_torque_limit / self.tyre_radius,
                            self.regen_decel_limit and self.mass * self.regen_decel_limit) if c]
        if self.regen_power_limit:
            pts += [self.regen_power_limit / c for c in caps]
        return sorted(p for p in pts if v1 < p < v0)

    def _decel_stop(self, v0: float, v1: float, a: float) -> dict:
        _check("decel", a, _finite(a) and a > 0, "need a deceleration > 0", "m/s^2")
        c0 = self.rolling_resistance * self.mass * G + self.drivetrain_drag
        c2 = 0.5 * self.air_density * self.drag_area
        need = self.inertia_factor * self.mass * a
        cross = [math.sqrt((need - c0) / c2)] if c2 > 0 and need > c0 else []
        pts = self._breaks(v1, v0, cross)
        road = (c0 * (v0 ** 2 - v1 ** 2) / 2 + c2 * (v0 ** 4 - v1 ** 4) / 4) / a
        propulsion = _integral(lambda v: max(float(self.road_force(v)) - need, 0.0) * v / a,
                               v1, v0, pts)
        regen = 0.0 if self.regen_share == 0 else _integral(
            lambda v: float(self.regen_force(a, v)) * v / a, v1, v0, pts)
        kinetic = self._kinetic(v0, v1)
        return {"kinetic_J": kinetic, "road_J": road, "propulsion_J": propulsion,
                "regenerated_J": regen, "friction_J": kinetic + propulsion - road - regen,
                "decel": a, "decel_max": a, "duration": (v0 - v1) / a,
                "distance": (v0 * v0 - v1 * v1) / (2 * a)}

    def _torque_stop(self, v0: float, v1: float, torque: float) -> dict:
        _check("torque", torque, _finite(torque) and torque > 0, "need a torque > 0", "N m")
        friction = torque / self.tyre_radius * self.brakes_per_axle / self.axle_share
        acc = np.vectorize(lambda v: self.deceleration(torque, v))
        pts = self._breaks(v1, v0)
        distance = _integral(lambda v: v / acc(v), v1, v0, pts)
        road = _integral(lambda v: float(self.road_force(v)) * v / acc(v), v1, v0, pts)
        kinetic = self._kinetic(v0, v1)
        grid = np.linspace(v1, v0, 65)
        return {"kinetic_J": kinetic, "road_J": road, "propulsion_J": 0.0,
                "regenerated_J": kinetic - road - friction * distance,
                "friction_J": friction * distance,
                "decel": (v0 * v0 - v1 * v1) / (2 * distance),
                "decel_max": float(max([acc(grid).max(), *(acc(p) for p in pts)])),
                "duration": _integral(lambda v: 1.0 / acc(v), v1, v0, pts),
                "distance": distance}


def _integral(f, a: float, b: float, points: list) -> float:
    """``int_a^b f(v) dv`` to 1e-12 of its size, broken at ``points`` (kinks)."""
    from scipy.integrate import quad

    edges = [a, *points, b]
    return float(sum(quad(f, lo, hi, epsabs=0.0, epsrel=1e-12, limit=200)[0]
                     for lo, hi in zip(edges[:-1], edges[1:]) if hi > lo))


def study_car(**changes) -> Vehicle:
    """The cleaning studies' car (docs/references.md, "The study's car", gives each
    value's source or marks it as an assumption, with its range): a 1.8 t
    electric mid-size car, 70 % of the friction braking on the front axle, 0.32 m
    tyres; road load ``C_rr`` 0.009, ``C_d A`` 0.60 m^2, air at 1.2 kg/m^3,
    30 N of drivetrain drag, turning parts 4 % of the mass; series blending
    (regeneration first) up to 2500 N m at the wheels, 60 kW and 2 m/s^2, faded
    out between 12 and 5 km/h.  ``changes`` replace any of these.
    """
    base = dict(mass=1800.0, front_share=0.7, tyre_radius=0.32, brakes_per_axle=2,
                inertia_factor=1.04, rolling_resistance=0.009, drag_area=0.60,
                air_density=1.2, drivetrain_drag=30.0, regen_share=1.0,
                regen_torque_limit=2500.0, regen_power_limit=60e3, regen_decel_limit=2.0,
                regen_cutoff_speed=5.0 / 3.6, regen_full_speed=12.0 / 3.6)
    return Vehicle(**{**base, **changes})


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
