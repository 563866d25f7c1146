"""Schedules of applications of the brake (SI units throughout).

An application (:mod:`brakewear.duty.applications`) is a :class:`Stop`, a
:class:`Drag`, a :class:`Dwell` or any registered kind.  A schedule is a list
of applications: :func:`repeated_stops` ("20 stops
from 50 km/h at 1.5 m/s^2, 120 s apart"), :func:`schedule_from_table` (the
same from a scene's ``[schedule]`` table, in its units) or
:func:`read_schedule_csv` (a drive cycle: time, speed and line pressure or
deceleration per row).
"""
from __future__ import annotations

import csv
import logging
import math
from dataclasses import replace
from os import PathLike
from pathlib import Path

from ..checks import check_int, check_number, check_order, check_plausible, fail, user_units
from ..errors import DutyError
from .applications import KMH, TABLE_SOURCE, Drag, Dwell, ScheduleCheck, Stop, application_name
from .kinds import application_from_table, application_kinds, is_application
from .vehicle import _check, _finite

logger = logging.getLogger(__name__)

__all__ = ["repeated_stops", "schedule_from_table", "read_schedule_csv", "check_schedule",
           "KMH"]


def check_schedule(schedule, vehicle=None, *, mu: float | None = None,
                   geometry=None) -> list:
    """Check a whole schedule before anything is computed; returns it as a list.

    Every application must be of a registered kind (:class:`Stop`, :class:`Drag`,
    :class:`Dwell`, or one added by :func:`~brakewear.duty.register_application`),
    and each checks itself (:meth:`~brakewear.duty.Application.check`): stops,
    and drags or dwells at a vehicle speed, need ``vehicle``.  A line pressure
    must be plausible (at most 100 MPa).  A stop at a deceleration must be
    within the tyres' grip (``tyre_mu g``) and leave the modelled brake some torque
    (not all regenerated).  With ``mu`` and ``geometry``, a stop under a line
    pressure whose deceleration exceeds the grip even with the pressure at the
    pad's inner radius (the least torque ``2 mu p A_clamp r_in`` of any pressure
    field) is refused; nearer the limit the stop's own pressure field decides,
    when it is run.  A dwell given from the previous application's start must
    outlast it where that application's length is known (a drag, or a stop at a
    deceleration), and outlast the shortest a stop under a line pressure can be
    (its pressure field at the pad's outer radius, with ``mu`` and ``geometry``).
    Errors name the application (:func:`~brakewear.duty.application_name`) and
    its values, line pressures in MPa (a schedule's unit).
    """
    apps = list(schedule)
    since_start = None      # s since the last braked application's start, where known
    for i, app in enumerate(apps):
        where = application_name(app, i)
        if not is_application(app):
            raise DutyError(f"{where}: {app!r} is not an application; registered kinds: "
                            f"{', '.join(application_kinds())} (brakewear.duty.Application)")
        since_start = app.check(ScheduleCheck(vehicle, mu, geometry, i, where, since_start,
                                              apps[i + 1] if i + 1 < len(apps) else None))
    return apps


def repeated_stops(count: int, v0: float, v1: float = 0.0, *, decel: float | None = None,
                   line_pressure: float | None = None, interval: float | None = None,
                   dwell_speed: float | None = None) -> list:
    """Equal stops, each but the last followed by a dwell that fills its interval.

    Parameters
    ----------
    count
        How many stops (1..100000).
    v0, v1, decel, line_pressure
        Each stop's (:class:`~brakewear.duty.Stop`).
    interval
        s from a stop's start to the next one's (longer than a stop); None: no
        dwells.
    dwell_speed
        The speed driven in the dwells (m/s); None: at rest.

    Returns
    -------
    list
        The applications: stops and dwells.
    """
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
               "dwell_speed": "km/h", "file": "path", "applications": "list"}


def schedule_from_table(table: dict, source: str = "scene", base: Path | None = None) -> list:
    """A schedule from a scene's ``[schedule]`` table (its units: km/h, m/s^2, MPa, s).

    Either ``file = "cycle.csv"`` (:func:`read_schedule_csv`, relative to
    ``base``), or ``applications``: a list of tables, each an application by
    its ``kind`` with its fields in the kind's units
    (:func:`~brakewear.duty.application_from_table`: ``{kind = "drag",
    line_pressure = 0.5, duration = 20.0, omega = 40.0}`` in MPa, s, rad/s),
    or repeated stops: ``stops``, ``speed_from``, ``speed_to``
    (default 0), one of ``deceleration`` and ``line_pressure``, and
    optionally ``interval`` (start to start) and ``dwell_speed`` (the speed the
    car drives on at between the stops: the rotor's convection follows it).
    Every key is checked in the table's units, against the others too (a stop's
    end speed below its start, an interval longer than a stop at a deceleration,
    a dwell speed only with an interval); messages name ``schedule.<key>``.
    """
    unknown = sorted(set(table) - set(_TABLE_KEYS))
    if unknown:
        raise DutyError(f"{source}: schedule.{unknown[0]}: unknown key; allowed: "
                        f"{', '.join(f'{k} ({u})' for k, u in _TABLE_KEYS.items())}")
    for key in ("file", "applications"):
        if key in table and len(table) > 1:
            raise DutyError(f"{source}: schedule.{key}: replaces the other keys; give either "
                            "a file, a list of applications or stops")
    if "file" in table:
        if not isinstance(table["file"], str):
            raise DutyError(f"{source}: schedule.file: {table['file']!r} is not a file name")
        path = Path(table["file"])
        return read_schedule_csv(path if base is None or path.is_absolute() else base / path)
    if "applications" in table:
        apps = table["applications"]
        if not isinstance(apps, list) or not apps:
            raise DutyError(f"{source}: schedule.applications: {apps!r}; need a list of "
                            "tables, each with kind = ... and its fields")
        return [application_from_table(a, f"{source}: schedule.applications[{i}]",
                                       TABLE_SOURCE) for i, a in enumerate(apps)]
    try:
        _check_table(table)
    except DutyError as e:
        raise DutyError(f"{source}: {e}") from None
    decel, p, ds = (table.get(k) for k in ("deceleration", "line_pressure", "dwell_speed"))
    apps = repeated_stops(table["stops"], table["speed_from"] * KMH,
                          table.get("speed_to", 0.0) * KMH, decel=decel,
                          line_pressure=None if p is None else p * 1e6,
                          interval=table.get("interval"),
                          dwell_speed=None if ds is None else ds * KMH)
    return [replace(a, source=TABLE_SOURCE) for a in apps]


def _check_table(table: dict) -> None:
    """The keys of a ``[schedule]`` table of stops, in its units, and against each other."""
    for key in ("stops", "speed_from"):
        if key not in table:
            raise fail(f"schedule.{key}", f"missing ({_TABLE_KEYS[key]})", DutyError)
    k = {name: f"schedule.{name}" for name in _TABLE_KEYS}
    check_int(k["stops"], table["stops"], 1, kind=DutyError, hi=100_000)
    v0, v1 = table["speed_from"], table.get("speed_to", 0.0)
    check_number(k["speed_from"], v0, 0.0, 360.0, unit="km/h", kind=DutyError)
    check_number(k["speed_to"], v1, 0.0, lo_open=False, unit="km/h", kind=DutyError)
    check_order(k["speed_to"], v1, k["speed_from"], v0, "km/h", blame=k["speed_to"],
                kind=DutyError, why="a stop slows the vehicle; at a constant speed it is a "
                                    "drag")
    decel, p = table.get("deceleration"), table.get("line_pressure")
    if (decel is None) == (p is None):
        raise fail("schedule.deceleration", "give exactly one of deceleration (m/s^2) and "
                                            "line_pressure (MPa)", DutyError)
    check_number(k["deceleration"], decel, 0.0, unit="m/s^2", allow_none=True, kind=DutyError)
    check_number(k["line_pressure"], p, 0.0, unit="MPa", allow_none=True, kind=DutyError)
    with user_units({k["line_pressure"]: ("MPa", 1e6, 0.0, p)}):
        check_plausible(k["line_pressure"], None if p is None else p * 1e6,
                        "environment.line_pressure", kind=DutyError)
    interval, ds = table.get("interval"), table.get("dwell_speed")
    check_number(k["interval"], interval, 0.0, unit="s", allow_none=True, kind=DutyError)
    if interval is not None and decel is not None:
        check_order(f"the stop's duration ({v0:g} to {v1:g} km/h at {decel:g} m/s^2)",
                    (v0 - v1) * KMH / decel, k["interval"], interval, "s",
                    kind=DutyError, why="the interval runs from one stop's start to the next")
    check_number(k["dwell_speed"], ds, 0.0, lo_open=False, unit="km/h", allow_none=True,
                 kind=DutyError)
    if ds is not None and interval is None:
        raise fail(k["dwell_speed"], f"{ds!r} km/h: the speed between the stops needs "
                                     "schedule.interval (without one the stops run back to "
                                     "back)", DutyError)


_CSV_SPEED = {"speed_kmh": KMH, "speed_m_s": 1.0}
_CSV_UNIT = {"speed_kmh": "km/h", "speed_m_s": "m/s"}
#: Largest vehicle speed (m/s, 360 km/h) and line pressure (Pa) of a drive cycle's rows:
#: a stop's and the plausible bound of a brake line
V_MAX, P_MAX = 100.0, 100e6


def read_schedule_csv(path: str | PathLike) -> list:
    """A drive cycle from a CSV file: one application per interval between rows.

    Parameters
    ----------
    path
        The CSV file.

    Returns
    -------
    list
        The applications, in order.

    Notes
    -----
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
    except (UnicodeDecodeError, csv.Error) as e:
        raise DutyError(f"{path}: the schedule is not a CSV text file ({e})") from None
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
        v_max = f"{V_MAX / _CSV_SPEED[speed_col]:g} {_CSV_UNIT[speed_col]}"
        for key, x, ok, need in (
                ("time_s", t[-1], math.isfinite(t[-1]), "a finite value"),
                (speed_col, row[speed_col], math.isfinite(v[-1]) and 0 <= v[-1] <= V_MAX,
                 f"a value from 0 to {v_max}"),
                ("line_pressure_MPa", row["line_pressure_MPa"],
                 math.isfinite(p[-1]) and 0 <= p[-1] <= P_MAX,
                 f"a value from 0 to {P_MAX / 1e6:g} (MPa)")):
            if not ok:
                raise DutyError(f"{path}, row {i}: {key} = {x!r} is not allowed; need {need}")
        if len(t) > 1 and not t[-1] > t[-2]:
            raise DutyError(f"{path}, row {i}: time_s = {t[-1]:g} does not increase (the row "
                            f"before has {t[-2]:g}); the rows must be in time order")
    apps = _applications(t, v, p, str(path))
    if not any(a.braked for a in apps):
        raise DutyError(f"{path}: no interval brakes (line_pressure_MPa > 0 at a speed that "
                        "falls or holds); the drive cycle gives the brake nothing to do")
    return apps


def _applications(t, v, p, path: str) -> list:
    out: list = []
    first = None                  # the first interval of the dwell being merged (if any)
    for k in range(len(t) - 1):
        dt = t[k + 1] - t[k]
        if p[k] > 0 and v[k + 1] > v[k]:
            logger.warning("%s: line_pressure_MPa = %g while the speed rises: taken as no "
                           "braking (a dwell)", _rows(path, k, k), p[k] / 1e6)
        if p[k] > 0 and v[k + 1] < v[k]:
            app = Stop(v[k], v[k + 1], line_pressure=p[k], source=_rows(path, k, k))
        elif p[k] > 0 and v[k + 1] == v[k] and v[k] > 0:
            app = Drag(p[k], dt, speed=v[k], source=_rows(path, k, k))
        elif first is not None:      # consecutive pauses are one dwell
            out[-1] = Dwell(out[-1].duration + dt, source=_rows(path, first, k))
            continue
        else:
            first, app = k, Dwell(dt, source=_rows(path, k, k))
            out.append(app)
            continue
        first = None
        out.append(app)
    return out


def _rows(path: str, first: int, last: int) -> str:
    """The file's rows of intervals ``first`` to ``last`` (row 1 is the header)."""
    return f"{path}, rows {first + 2}-{last + 3}"
