"""Applications of the brake and schedules of them (SI units throughout).

An application is one of

* :class:`Stop` -- the vehicle slows from ``v0`` to ``v1`` at a given
  deceleration, or under a given line pressure (the deceleration then
  follows from the brake's torque); the speed falls linearly within it;
* :class:`Drag` -- constant speed and line pressure for a time;
* :class:`Dwell` -- no contact for a time (the bodies cool when thermal
  coupling is on).

A schedule is a list of applications: :func:`repeated_stops` ("20 stops
from 50 km/h at 1.5 m/s^2, 120 s apart"), :func:`schedule_from_table` (the
same from a scene's ``[schedule]`` table, in its units) or
:func:`read_schedule_csv` (a drive cycle: time, speed and line pressure or
deceleration per row).
"""
from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from os import PathLike
from pathlib import Path

from ..errors import DutyError
from .vehicle import G, _check, _finite, brake_torque

__all__ = ["Stop", "Drag", "Dwell", "repeated_stops", "schedule_from_table",
           "read_schedule_csv", "check_schedule", "KMH"]

#: One km/h in m/s.
KMH = 1.0 / 3.6


@dataclass(frozen=True)
class Stop:
    """Slow from ``v0`` to ``v1`` (m/s) at ``decel`` (m/s^2) or under ``line_pressure`` (Pa)."""

    v0: float
    v1: float = 0.0
    decel: float | None = None
    line_pressure: float | None = None

    def __post_init__(self):
        _check("stop.v0", self.v0, _finite(self.v0) and 0 < self.v0 <= 100,
               "need 0 < v0 <= 100 m/s", "m/s")
        _check("stop.v1", self.v1, _finite(self.v1) and 0 <= self.v1 < self.v0,
               f"need 0 <= v1 < v0 = {self.v0:g} m/s", "m/s")
        if (self.decel is None) == (self.line_pressure is None):
            raise DutyError("a stop needs exactly one of decel (m/s^2) and line_pressure (Pa)")
        if self.decel is not None:
            _check("stop.decel", self.decel, _finite(self.decel) and self.decel > 0,
                   "need a deceleration > 0", "m/s^2")
        else:
            _check("stop.line_pressure", self.line_pressure,
                   _finite(self.line_pressure) and self.line_pressure > 0, "need > 0", "Pa")


@dataclass(frozen=True)
class Drag:
    """Constant ``line_pressure`` (Pa) for ``duration`` (s) at a vehicle speed ``speed``
    (m/s) or, without a vehicle (a dynamometer), a rotor speed ``omega`` (rad/s)."""

    line_pressure: float
    duration: float
    speed: float | None = None
    omega: float | None = None

    def __post_init__(self):
        _check("drag.line_pressure", self.line_pressure,
               _finite(self.line_pressure) and self.line_pressure > 0, "need > 0", "Pa")
        _check("drag.duration", self.duration, _finite(self.duration) and self.duration > 0,
               "need > 0", "s")
        if (self.speed is None) == (self.omega is None):
            raise DutyError("a drag needs exactly one of speed (m/s) and omega (rad/s)")
        v = self.speed if self.speed is not None else self.omega
        _check("drag.speed" if self.speed is not None else "drag.omega", v,
               _finite(v) and v > 0, "need > 0", "m/s" if self.speed is not None else "rad/s")


@dataclass(frozen=True)
class Dwell:
    """No contact for ``duration`` (s); with ``from_start`` until ``duration`` after
    the previous application's start (a stop's length is known only once the
    brake's torque is).  The car drives on at ``speed`` (m/s; needs a vehicle)
    or the rotor spins at ``omega`` (rad/s): a speed-dependent convection
    (:class:`~brakewear.thermal.SpeedConvection`) cools at that speed; neither
    given: at rest."""

    duration: float
    from_start: bool = False
    speed: float | None = None
    omega: float | None = None

    def __post_init__(self):
        _check("dwell.duration", self.duration, _finite(self.duration) and self.duration > 0,
               "need > 0", "s")
        if self.speed is not None and self.omega is not None:
            raise DutyError("a dwell takes at most one of speed (m/s) and omega (rad/s)")
        for key, unit in (("speed", "m/s"), ("omega", "rad/s")):
            v = getattr(self, key)
            if v is not None:
                _check(f"dwell.{key}", v, _finite(v) and v >= 0, "need >= 0", unit)


def check_schedule(schedule, vehicle=None, *, mu: float | None = None,
                   geometry=None) -> list:
    """Check a whole schedule before anything is computed; returns it as a list.

    Every application must be a :class:`Stop`, :class:`Drag` or :class:`Dwell`;
    stops, and drags or dwells at a vehicle speed, need ``vehicle``.  A stop
    at a deceleration must be within the tyres' grip (``tyre_mu g``) and leave
    the modelled brake some torque (not all regenerated).  A stop under a line
    pressure whose deceleration exceeds the grip even with the pressure at the
    pad's inner radius (the least torque ``2 mu p A_clamp r_in`` of any
    pressure field) is refused; nearer the limit the stop's own pressure field
    decides, when it is run.  A dwell given from the previous application's
    start must outlast it where that application's length is known (a drag,
    or a stop at a deceleration).  Errors name the application's index (from
    0) and the value in SI units.
    """
    apps = list(schedule)
    since_start = None      # s since the last braked application's start, where known
    for i, app in enumerate(apps):
        where = f"application {i}"
        if not isinstance(app, (Stop, Drag, Dwell)):
            raise DutyError(f"{where}: {app!r} is not a Stop, Drag or Dwell")
        if isinstance(app, Dwell):
            if app.speed is not None and vehicle is None:
                raise DutyError(f"{where}: a dwell at a vehicle speed needs a vehicle")
            if app.from_start and since_start is not None:
                _check(f"{where}: dwell.duration", app.duration, app.duration > since_start,
                       f"a dwell from the previous application's start must outlast its "
                       f"{since_start:.4g} s", "s")
            since_start = None if since_start is None or app.from_start else \
                since_start + app.duration
            continue
        if isinstance(app, Drag):
            if app.speed is not None and vehicle is None:
                raise DutyError(f"{where}: a drag at a vehicle speed needs a vehicle (or give "
                                "the rotor speed omega)")
            since_start = app.duration
            continue
        if vehicle is None:
            raise DutyError(f"{where}: a stop needs a vehicle (mass, tyre radius, brake share)")
        since_start = None
        if app.decel is not None:
            _check_stop_decel(app, vehicle, where)
            since_start = (app.v0 - app.v1) / app.decel
        elif mu is not None and geometry is not None:
            least = vehicle.deceleration(brake_torque(app.line_pressure, mu,
                                                      geometry.clamp_area,
                                                      geometry.pad.inner_radius))
            limit = vehicle.tyre_mu * G
            if not least <= limit:
                p = app.line_pressure
                raise DutyError(f"{where}: line_pressure = {p:g} Pa ({p / 1e6:g} MPa) is not "
                                f"allowed; it decelerates the vehicle by at least {least:.3g} "
                                f"m/s^2 (the least torque it can give: its whole pressure field at "
                                f"the pad's inner radius, {geometry.pad.inner_radius * 1e3:g} "
                                f"mm), beyond tyre_mu g = "
                                f"{limit:.3g} m/s^2 (what the tyres can give)")
    return apps


def _check_stop_decel(app: Stop, vehicle, where: str) -> None:
    vehicle.check_deceleration(app.decel, f"{where}: deceleration")
    if not vehicle.brake_torque(app.decel) > 0:
        raise DutyError(f"{where}: at deceleration = {app.decel!r} m/s^2 the motor takes all "
                        f"the braking (regen_share = {vehicle.regen_share:g}): the modelled "
                        "brake gives no torque")


def repeated_stops(count: int, v0: float, v1: float = 0.0, *, decel: float | None = None,
                   line_pressure: float | None = None, interval: float | None = None,
                   dwell_speed: float | None = None) -> list:
    """``count`` equal stops; with ``interval`` (s, start to start) a dwell after each
    but the last fills the rest of the interval (which must exceed the stop's time),
    driven at ``dwell_speed`` (m/s; None: at rest)."""
    _check("stops", count, isinstance(count, int) and not isinstance(count, bool)
           and 1 <= count <= 100_000, "need a whole number 1..100000")
    stop = Stop(v0, v1, decel, line_pressure)
    out: list = []
    for i in range(count):
        out.append(stop)
        if interval is not None and i < count - 1:
            if decel is not None:
                t_stop = (v0 - v1) / decel
                _check("interval", interval, _finite(interval) and interval > t_stop,
                       f"need more than the stop's {t_stop:.3g} s", "s")
                out.append(Dwell(interval - t_stop, speed=dwell_speed))
            else:   # the stop's time is known only from the brake's torque
                out.append(Dwell(interval, from_start=True, speed=dwell_speed))
    return out


_TABLE_KEYS = {"stops": "count", "speed_from": "km/h", "speed_to": "km/h",
               "deceleration": "m/s^2", "line_pressure": "MPa", "interval": "s",
               "dwell_speed": "km/h", "file": "path"}


def schedule_from_table(table: dict, source: str = "scene", base: Path | None = None) -> list:
    """A schedule from a scene's ``[schedule]`` table (its units: km/h, m/s^2, MPa, s).

    Either ``file = "cycle.csv"`` (:func:`read_schedule_csv`, relative to
    ``base``) or repeated stops: ``stops``, ``speed_from``, ``speed_to``
    (default 0), one of ``deceleration`` and ``line_pressure``, and
    optionally ``interval`` (start to start) and ``dwell_speed`` (the speed the
    car drives on at between the stops: the rotor's convection follows it).
    """
    where = f"{source} [schedule]"
    unknown = sorted(set(table) - set(_TABLE_KEYS))
    if unknown:
        raise DutyError(f"{where}: unknown key(s) {', '.join(unknown)}; allowed: "
                        f"{', '.join(f'{k} ({u})' for k, u in _TABLE_KEYS.items())}")
    if "file" in table:
        if len(table) > 1:
            raise DutyError(f"{where}: 'file' replaces the other keys; give either a file or "
                            "stops")
        path = Path(table["file"])
        return read_schedule_csv(path if base is None or path.is_absolute() else base / path)
    for key in ("stops", "speed_from"):
        if key not in table:
            raise DutyError(f"{where}: missing key {key!r} ({_TABLE_KEYS[key]})")
    try:
        decel = table.get("deceleration")
        p = table.get("line_pressure")
        ds = table.get("dwell_speed")
        return repeated_stops(table["stops"], table["speed_from"] * KMH,
                              table.get("speed_to", 0.0) * KMH, decel=decel,
                              line_pressure=None if p is None else p * 1e6,
                              interval=table.get("interval"),
                              dwell_speed=None if ds is None else ds * KMH)
    except TypeError:
        raise DutyError(f"{where}: every value must be a number ({table!r})") from None
    except DutyError as e:
        raise DutyError(f"{where}: {e} (the table's units: km/h, m/s^2, MPa, s)") from None


_CSV_SPEED = {"speed_kmh": KMH, "speed_m_s": 1.0}


def read_schedule_csv(path: str | PathLike) -> list:
    """A drive cycle from a CSV file: one application per interval between rows.

    Columns: ``time_s``; the speed as ``speed_kmh`` or ``speed_m_s``; and
    ``line_pressure_MPa`` (the brake's pressure over the interval from that
    row to the next; 0 or empty: not braking).  Time must increase.  An
    interval with braking and falling speed is a :class:`Stop` under that
    pressure (its deceleration follows from the brake, so the file's times
    within a stop are not used), braking at constant speed a :class:`Drag`,
    anything else a :class:`Dwell` (consecutive dwells merged).
    """
    path = Path(path)
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            rows = list(csv.DictReader(fh))
            header = list(rows[0]) if rows else []
    except OSError as e:
        raise DutyError(f"{path}: cannot read the schedule ({e.strerror})") from None
    speed_col = next((c for c in _CSV_SPEED if c in header), None)
    missing = [c for c, ok in (("time_s", "time_s" in header),
                               ("speed_kmh or speed_m_s", speed_col is not None),
                               ("line_pressure_MPa", "line_pressure_MPa" in header)) if not ok]
    if missing:
        raise DutyError(f"{path}: missing column(s) {', '.join(missing)}; the header is "
                        f"{', '.join(header) or '(empty file)'}")
    if len(rows) < 2:
        raise DutyError(f"{path}: a schedule needs at least two rows (one interval)")
    t, v, p = [], [], []
    for i, row in enumerate(rows, start=2):           # row 1 is the header
        try:
            t.append(float(row["time_s"]))
            v.append(float(row[speed_col]) * _CSV_SPEED[speed_col])
            p.append(float(row["line_pressure_MPa"] or 0.0) * 1e6)
        except (TypeError, ValueError):
            raise DutyError(f"{path}, row {i}: not a number in {dict(row)!r}") from None
        for key, x, ok in (("time_s", t[-1], math.isfinite(t[-1])),
                           (speed_col, row[speed_col], math.isfinite(v[-1]) and v[-1] >= 0),
                           ("line_pressure_MPa", row["line_pressure_MPa"],
                            math.isfinite(p[-1]) and p[-1] >= 0)):
            if not ok:
                raise DutyError(f"{path}, row {i}: {key} = {x!r} is not allowed; need a "
                                "finite value >= 0")
        if len(t) > 1 and not t[-1] > t[-2]:
            raise DutyError(f"{path}, row {i}: time_s = {t[-1]:g} does not increase (the row "
                            f"before has {t[-2]:g}); the rows must be in time order")
    return _applications(t, v, p)


def _applications(t, v, p) -> list:
    out: list = []
    for k in range(len(t) - 1):
        dt = t[k + 1] - t[k]
        if p[k] > 0 and v[k + 1] < v[k]:
            app = Stop(v[k], v[k + 1], line_pressure=p[k])
        elif p[k] > 0 and v[k + 1] == v[k] and v[k] > 0:
            app = Drag(p[k], dt, speed=v[k])
        else:
            if out and isinstance(out[-1], Dwell):
                out[-1] = Dwell(out[-1].duration + dt)
                continue
            app = Dwell(dt)
        out.append(app)
    return out
