"""A drive cycle replayed through the vehicle's blending: the friction work that
ordinary driving gives the rotor.

A speed trace (time, speed; linear between its rows, so each interval is a
constant acceleration) is read by :func:`read_speed_trace` or taken from the
package (:func:`packaged_cycle`: ``"nedc"``, the New European Driving Cycle of
UN ECE Regulation No. 83).  :func:`replay_cycle` takes every interval in which
the car slows, and splits its kinetic energy as the car does
(:meth:`brakewear.duty.Vehicle.stop_energy`): the road load's part, the
motor's (the controller's blending: its share, torque, power and
deceleration limits and its fade-out at low speed), and the friction brakes'.
Intervals in which the road load alone slows the car as fast as the trace
asks brake nothing.
"""
from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from os import PathLike
from pathlib import Path

import numpy as np

from ..checks import read_csv_rows
from ..errors import DutyError
from .schedule import KMH

__all__ = ["SpeedTrace", "read_speed_trace", "packaged_cycle", "replay_cycle", "CYCLES"]

#: packaged drive cycles: name -> file in brakewear/data/cycles
CYCLES = {"nedc": "nedc.csv"}
_SPEED = {"speed_kmh": KMH, "speed_m_s": 1.0}


@dataclass(frozen=True)
class SpeedTrace:
    """A drive cycle: times (s, increasing) and speeds (m/s, 0..100), linear between."""

    time: np.ndarray
    speed: np.ndarray
    name: str = ""

    @property
    def distance(self) -> float:
        """Distance driven (m)."""
        return float(np.sum(0.5 * (self.speed[1:] + self.speed[:-1]) * np.diff(self.time)))


def read_speed_trace(path: str | PathLike, name: str | None = None) -> SpeedTrace:
    """A speed trace from a CSV file: ``time_s`` and ``speed_kmh`` or ``speed_m_s``
    (lines starting with ``#`` are comments).  Errors name the file, the row and
    the value as the file writes it."""
    path = Path(path)
    rows, header = read_csv_rows(path, "the drive cycle", DutyError)
    col = next((c for c in _SPEED if c in header), None)
    if "time_s" not in header or col is None:
        raise DutyError(f"{path}: need the columns time_s and speed_kmh or speed_m_s (the "
                        f"header is {', '.join(header) or '(empty file)'})")
    t, v = [], []
    for i, row in enumerate(rows, start=2):
        try:
            ti, vi = float(row["time_s"]), float(row[col])
        except (TypeError, ValueError):
            raise DutyError(f"{path}, row {i}: not a number in {dict(row)!r}") from None
        if not (np.isfinite(ti) and np.isfinite(vi) and 0 <= vi * _SPEED[col] <= 100.0):
            raise DutyError(f"{path}, row {i}: {col} = {row[col]} is not allowed; need 0 .. "
                            f"{100 / _SPEED[col]:.4g}")
        if t and not ti > t[-1]:
            raise DutyError(f"{path}, row {i}: time_s = {row['time_s']} is not after the row "
                            f"before ({t[-1]:g}); time must increase")
        t.append(ti)
        v.append(vi * _SPEED[col])
    if len(t) < 2:
        raise DutyError(f"{path}: a drive cycle needs at least two rows")
    return SpeedTrace(np.array(t), np.array(v), path.stem if name is None else name)


def packaged_cycle(name: str = "nedc") -> SpeedTrace:
    """A drive cycle shipped with brakewear (:data:`CYCLES`)."""
    if name not in CYCLES:
        raise DutyError(f"cycle = {name!r} is not allowed; packaged: {', '.join(CYCLES)}")
    ref = resources.files("brakewear") / "data" / "cycles" / CYCLES[name]
    with resources.as_file(ref) as p:
        return read_speed_trace(p, name)


def replay_cycle(trace: SpeedTrace, vehicle) -> dict:
    """The energies of ``trace`` driven by ``vehicle`` (a
    :class:`~brakewear.duty.Vehicle`), over the intervals in which it slows.

    Returns (J unless named) ``kinetic_J`` the car gives up in them (with its
    turning parts), ``road_J``, ``propulsion_J`` (where the road load slows it
    faster than the trace), ``regenerated_J``, ``friction_J`` of all friction
    brakes, ``brake_J`` of the modelled brake and ``face_J`` of each of its
    faces; ``distance_km``, ``face_J_per_km``; ``events``: per interval that
    brakes with friction its start time, speeds (km/h), deceleration and
    ``face_J``; ``largest_face_J``, the most one interval gives a face.
    """
    keys = ("kinetic_J", "road_J", "propulsion_J", "regenerated_J", "friction_J", "brake_J",
            "face_J")
    total = dict.fromkeys(keys, 0.0)
    events = []
    t, v = trace.time, trace.speed
    for i in range(t.size - 1):
        if not v[i + 1] < v[i]:
            continue
        a = (v[i] - v[i + 1]) / (t[i + 1] - t[i])
        e = vehicle.stop_energy(float(v[i]), float(v[i + 1]), float(a))
        for k in keys:
            total[k] += e[k]
        if e["face_J"] > 1e-9 * e["kinetic_J"]:
            events.append({"t_s": float(t[i]), "from_kmh": v[i] / KMH, "to_kmh": v[i + 1] / KMH,
                           "decel": float(a), "face_J": e["face_J"]})
    km = trace.distance / 1e3
    return {**total, "distance_km": km, "face_J_per_km": total["face_J"] / km,
            "events": events,
            "largest_face_J": max((ev["face_J"] for ev in events), default=0.0)}
