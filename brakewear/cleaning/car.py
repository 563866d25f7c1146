"""A car file: the vehicle a cleaning routine stops, its road load and its blending.

A TOML file of three tables, each key in a fixed unit (the packaged
``study`` car, ``brakewear/data/cars/study_car.toml``, shows them all):

* ``[vehicle]`` -- ``mass`` (kg), ``front_share``, ``tyre_radius`` (m),
  ``brakes_per_axle``, ``axle`` (``"front"`` or ``"rear"``),
  ``inertia_factor``, ``tyre_mu``;
* ``[road]`` -- ``rolling_resistance``, ``drag_area`` (m^2), ``air_density``
  (kg/m^3), ``drivetrain_drag`` (N);
* ``[blending]`` -- ``regen_share``, ``regen_torque_limit`` (N m at the
  wheels), ``regen_power_limit`` (kW), ``regen_decel_limit`` (m/s^2),
  ``regen_cutoff_speed`` and ``regen_full_speed`` (km/h).

:func:`read_car` reads and checks it before anything runs: an unknown table
or key, a value of the wrong type or out of range is refused by a
:class:`~brakewear.errors.DutyError` naming the file, the key, the value in
the file's unit and what is allowed.  A cleaning routine brakes by friction
alone (:meth:`~brakewear.duty.Vehicle.with_friction_share`); the blending is
what the car's ordinary braking (its bedding) goes through.
"""
from __future__ import annotations

import logging
from importlib import resources
from os import PathLike
from pathlib import Path

from ..duty import KMH, Vehicle
from ..errors import DutyError

logger = logging.getLogger(__name__)

__all__ = ["read_car", "packaged_car", "car_file", "read_toml", "CAR_KEYS", "CARS"]

#: packaged car files: name -> file in brakewear/data/cars
CARS = {"study": "study_car.toml"}

#: table -> key -> (unit, SI per unit, lower bound, upper bound, required)
CAR_KEYS = {
    "vehicle": {"mass": ("kg", 1.0, 100.0, 1e5, True),
                "front_share": ("", 1.0, 0.0, 1.0, False),
                "tyre_radius": ("m", 1.0, 0.1, 1.5, False),
                "brakes_per_axle": ("", 1, 1, 4, False),
                "axle": ("", None, None, None, False),
                "inertia_factor": ("", 1.0, 1.0, 1.5, False),
                "tyre_mu": ("", 1.0, 0.05, 2.0, False)},
    "road": {"rolling_resistance": ("", 1.0, 0.0, 0.05, False),
             "drag_area": ("m^2", 1.0, 0.0, 20.0, False),
             "air_density": ("kg/m^3", 1.0, 0.5, 1.5, False),
             "drivetrain_drag": ("N", 1.0, 0.0, 1e4, False)},
    "blending": {"regen_share": ("", 1.0, 0.0, 1.0, False),
                 "regen_torque_limit": ("N m", 1.0, 0.0, 1e5, False),
                 "regen_power_limit": ("kW", 1e3, 0.0, 1e4, False),
                 "regen_decel_limit": ("m/s^2", 1.0, 0.0, 20.0, False),
                 "regen_cutoff_speed": ("km/h", KMH, 0.0, 180.0, False),
                 "regen_full_speed": ("km/h", KMH, 0.0, 180.0, False)},
}


def car_file(name: str | PathLike) -> Path:
    """The file of a packaged car (``"study"``) or the path given."""
    if str(name) in CARS:
        return Path(str(resources.files("brakewear") / "data" / "cars" / CARS[str(name)]))
    return Path(name)


def packaged_car(name: str = "study") -> Vehicle:
    """A packaged car (:data:`CARS`)."""
    if name not in CARS:
        raise DutyError(f"car = {name!r} is not a packaged car; packaged: {', '.join(CARS)}")
    return read_car(car_file(name))


def _value(path: Path, table: str, key: str, v):
    unit, si, lo, hi, _ = CAR_KEYS[table][key]
    where = f"{path}: {table}.{key}"
    if key == "axle":
        if v not in ("front", "rear"):
            raise DutyError(f"{where} = {v!r} is not allowed; allowed: 'front', 'rear'")
        return v
    if key == "brakes_per_axle":
        if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
            raise DutyError(f"{where} = {v!r} is not allowed; need a whole number {lo}..{hi}")
        return v
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not (lo <= v <= hi):
        shown = f"{v!r} {unit}".strip()
        raise DutyError(f"{where} = {shown} is not allowed; need a number from {lo:g} to "
                        f"{hi:g}{' ' + unit if unit else ''}")
    return float(v) * si


def read_toml(path: Path, what: str, kind=DutyError) -> dict:
    """The tables of a TOML file; ``kind`` (an input error) names the file and ``what``
    it is when it cannot be read or is not TOML."""
    import tomllib

    try:
        return tomllib.loads(Path(path).read_text())
    except OSError as e:
        raise kind(f"{path}: cannot read {what} ({e.strerror})") from None
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
        raise kind(f"{path}: {what} is not a TOML file ({e})") from None


def read_car(path: str | PathLike) -> Vehicle:
    """The :class:`~brakewear.duty.Vehicle` of a car file (see the module)."""
    path = Path(path)
    data = read_toml(path, "the car file")
    unknown = sorted(set(data) - set(CAR_KEYS))
    if unknown:
        raise DutyError(f"{path}: unknown table [{unknown[0]}]; allowed: "
                        f"{', '.join(f'[{t}]' for t in CAR_KEYS)}")
    kw = {}
    for table, keys in CAR_KEYS.items():
        given = data.get(table, {})
        if not isinstance(given, dict):
            raise DutyError(f"{path}: {table} must be a table [{table}]")
        bad = sorted(set(given) - set(keys))
        if bad:
            raise DutyError(f"{path}: {table}.{bad[0]}: unknown key; allowed: "
                            + ", ".join(f"{k} ({u or '-'})" for k, (u, *_) in keys.items()))
        for key, (*_, required) in keys.items():
            if key in given:
                kw[key] = _value(path, table, key, given[key])
            elif required:
                raise DutyError(f"{path}: {table}.{key}: missing ({keys[key][0]})")
    try:
        return Vehicle(**kw, source=str(path))
    except DutyError as e:
        raise DutyError(f"{path}: {e}") from None
