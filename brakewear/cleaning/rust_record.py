"""A dynamometer record of rust removal: the CSV file that
:func:`brakewear.cleaning.rust_fit.calibrate` fits.

A record is a CSV file with one row per stop (lines starting with ``#`` are
comments): ``contact_pressure_MPa`` (the pad's mean contact pressure, the
clamp force over the pad's area), ``sliding_distance_m`` (the rotor's
sliding distance at the pad's mean radius in the stop) and what was
measured -- ``friction`` (the stop's mean friction coefficient) and/or
``oxide_removed_um`` (the mean depth of oxide the stop removed, from
profilometry or the disc's mass loss); an empty cell is not measured.
A file that is not such a table (not text, a row with more or fewer cells
than the header, a column named twice) is refused naming the file and the row.
"""
from __future__ import annotations

from dataclasses import dataclass
from os import PathLike
from pathlib import Path

import numpy as np

from ..checks import read_csv_rows
from ..errors import WearError

__all__ = ["DynoRecord", "read_dyno_record", "write_dyno_record", "RECORD_COLUMNS"]

#: the record's columns: the two inputs and the two observables
RECORD_COLUMNS = ("contact_pressure_MPa", "sliding_distance_m", "friction", "oxide_removed_um")


@dataclass(frozen=True)
class DynoRecord:
    """One dynamometer record: per stop the contact pressure (Pa), the sliding
    distance (m) and the measured friction coefficient and removed oxide depth (m;
    NaN where not measured, None where never)."""

    pressure: np.ndarray
    distance: np.ndarray
    friction: np.ndarray | None = None
    removed: np.ndarray | None = None
    source: str = ""

    @property
    def stops(self) -> int:
        """Number of stops."""
        return int(self.pressure.size)


def read_dyno_record(path: str | PathLike) -> DynoRecord:
    """A record from a CSV file (see the module); errors name the file and the row."""
    path = Path(path)
    rows, header = read_csv_rows(path, "the dynamometer record", WearError)
    missing = [c for c in RECORD_COLUMNS[:2] if c not in header]
    if missing or not any(c in header for c in RECORD_COLUMNS[2:]):
        raise WearError(f"{path}: need the columns {RECORD_COLUMNS[0]}, {RECORD_COLUMNS[1]} and "
                        f"one or both of {RECORD_COLUMNS[2]}, {RECORD_COLUMNS[3]} (the header is "
                        f"{', '.join(header) or '(empty file)'})")
    cols = {c: [] for c in RECORD_COLUMNS if c in header}
    limits = {"contact_pressure_MPa": (0.0, 50.0), "sliding_distance_m": (0.0, 1e5),
              "friction": (0.0, 2.0), "oxide_removed_um": (-100.0, 1000.0)}
    for i, row in enumerate(rows, start=2):
        for c in cols:
            text = (row.get(c) or "").strip()
            try:
                x = float(text) if text or c in RECORD_COLUMNS[:2] else np.nan
            except ValueError:
                raise WearError(f"{path}, row {i}: {c} = {text!r} is not a number") from None
            lo, hi = limits[c]
            if not (np.isnan(x) and c in RECORD_COLUMNS[2:]) and not (
                    np.isfinite(x) and lo <= x <= hi and (x > 0 or c == "oxide_removed_um")):
                raise WearError(f"{path}, row {i}: {c} = {text} is not allowed; need "
                                f"{'a number in' if c == 'oxide_removed_um' else '>'} {lo:g} "
                                f"{'..' if c == 'oxide_removed_um' else 'and <='} {hi:g}")
            cols[c].append(x)
    if len(rows) < 3:
        raise WearError(f"{path}: a record needs at least three stops")
    def get(c, scale):       # a column never filled in is not measured
        x = None if c not in cols else np.array(cols[c]) * scale
        return None if x is None or np.isnan(x).all() else x

    return DynoRecord(get("contact_pressure_MPa", 1e6), get("sliding_distance_m", 1.0),
                      get("friction", 1.0), get("oxide_removed_um", 1e-6), str(path))


def write_dyno_record(path: str | PathLike, record: DynoRecord, header: str = "") -> Path:
    """Write ``record`` in the CSV form :func:`read_dyno_record` reads (``header``:
    comment lines put first)."""
    path = Path(path)
    out = [f"# {ln}" for ln in header.splitlines()]
    out.append(",".join(RECORD_COLUMNS))
    for n in range(record.stops):
        f = "" if record.friction is None or np.isnan(record.friction[n]) else \
            f"{record.friction[n]:.5f}"
        r = "" if record.removed is None or np.isnan(record.removed[n]) else \
            f"{record.removed[n] * 1e6:.4f}"
        out.append(f"{record.pressure[n] / 1e6:.4f},{record.distance[n]:.3f},{f},{r}")
    path.write_text("\n".join(out) + "\n")
    return path


