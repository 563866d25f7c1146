"""The CSV file of a friction or wear map: its columns, units and checks.

One row per grid point (long format), axis columns with their unit in the
header and one value column::

    # source: tribometer, pad A against grey cast iron
    p_MPa,v_m_s,T_C,mu,k_mm3_Nm
    0.5,1,20,0.42,5.0e-6
    ...

Lines starting with ``#`` are comments.  The rows must fill a full tensor
grid: the axes are each column's sorted distinct values and each of their
combinations stands on exactly one row.  Every refusal names the file, the
row (its line number in the file, comments counted) and the column.
:func:`brakewear.laws.maps.read_map` makes a :class:`~brakewear.laws.maps.TableMap` of it.
"""
from __future__ import annotations

import csv
import logging
import os
from pathlib import Path

import numpy as np

from ..errors import MapError

logger = logging.getLogger(__name__)

__all__ = ["AXES", "AXIS_UNITS", "VALUE_UNITS", "BOUNDS", "read_table", "parse_table",
           "check_range"]

#: the axes a map may vary along: pressure, sliding speed, temperature
AXES = ("p", "v", "T")

#: axis -> column suffix -> (unit shown, factor to SI, offset): SI = value * factor + offset
AXIS_UNITS: dict[str, dict[str, tuple[str, float, float]]] = {
    "p": {"Pa": ("Pa", 1.0, 0.0), "kPa": ("kPa", 1e3, 0.0), "MPa": ("MPa", 1e6, 0.0),
          "bar": ("bar", 1e5, 0.0)},
    "v": {"m_s": ("m/s", 1.0, 0.0), "km_h": ("km/h", 1.0 / 3.6, 0.0)},
    "T": {"K": ("K", 1.0, 0.0), "C": ("C", 1.0, 273.15)},
}

#: quantity -> column suffix -> (unit shown, factor to SI, offset); ``mu`` has no unit
VALUE_UNITS: dict[str, dict[str, tuple[str, float, float]]] = {
    "mu": {"": ("", 1.0, 0.0)},
    "k": {"m2_N": ("m^2/N", 1.0, 0.0), "mm3_Nm": ("mm^3/Nm", 1e-9, 0.0)},
}

#: axis or quantity -> (lowest, highest, why) in SI: the values a map may hold
BOUNDS: dict[str, tuple[float, float, str]] = {
    "p": (0.0, 1e9, "brake contact pressures stay below about 20 MPa; beyond 1000 MPa the "
                    "values are likely in another unit than the column's"),
    "v": (0.0, 200.0, "brake sliding speeds stay below about 100 m/s (a 300 km/h train's "
                      "disc); beyond 200 m/s the values are likely in another unit than "
                      "the column's"),
    "T": (173.15, 1473.15, "brake temperatures lie between -100 C and 1200 C; outside, the "
                           "values are likely in another unit than the column's"),
    "mu": (0.0, 2.0, "friction coefficients of brake pairs lie between 0.2 and 0.7; above "
                     "2 (the bound of a scene's interface.mu) a value is a percentage or "
                     "another quantity"),
    "k": (0.0, 1e-10, "specific wear rates of brake materials lie between about 1e-16 and "
                      "1e-12 m^2/N (1e-7 to 1e-3 mm^3/Nm); beyond 1e-10 m^2/N the values "
                      "are likely in another unit than the column's"),
}

#: below this largest pressure (Pa) a map's pressure column is in another unit
_P_LOWEST_MAX = 1e3


def check_range(label: str, kind: str, value: float, unit: str) -> None:
    """Raise a :class:`MapError` ``"label = value unit ..."`` unless ``value`` (SI) is
    finite and within :data:`BOUNDS` of ``kind``."""
    lo, hi, why = BOUNDS[kind]
    if not np.isfinite(value):
        raise MapError(f"{label} = {value!r} is not allowed; need a finite number")
    if not lo <= value <= hi:
        u = f" {unit}" if unit else ""
        raise MapError(f"{label} = {value:g}{u} is not allowed; allowed: {lo:g} to {hi:g}{u} "
                       f"({why})")


def _column(source: str, row: int, name: str):
    """``(kind, unit shown, factor, offset)`` of the header's column ``name``."""
    kind, _, suffix = name.partition("_")
    units = AXIS_UNITS.get(kind) or VALUE_UNITS.get(kind)
    where = f"{source}, row {row} (the header), column {name!r}"
    if units is None:
        allowed = [f"{a}_{u}" for a in AXES for u in AXIS_UNITS[a]]
        values = [q if not u else f"{q}_{u}" for q in VALUE_UNITS for u in VALUE_UNITS[q]]
        raise MapError(f"{where}: unknown column; allowed: axis columns "
                       f"{', '.join(allowed)} and value columns {', '.join(values)}")
    if suffix not in units:
        allowed = [kind if not u else f"{kind}_{u}" for u in units]
        raise MapError(f"{where}: unknown unit {suffix!r} for {kind}; allowed: "
                       f"{', '.join(allowed)}")
    return (kind, *units[suffix])


def _header(source: str, row: int, names: list[str], quantity: str) -> list[tuple]:
    """The columns a map of ``quantity`` reads: ``(index, name, kind, unit, factor,
    offset)``, the axes first (in the file's order), the value column last."""
    axes, values, seen = [], [], {}
    for i, name in enumerate(names):
        kind, unit, f, o = _column(source, row, name)
        if kind in seen:
            raise MapError(f"{source}, row {row} (the header), column {name!r}: a second "
                           f"{kind} column ({seen[kind]!r} is the first); keep one")
        seen[kind] = name
        col = (i, name, kind, unit, f, o)
        if kind in AXES:
            axes.append(col)
        elif kind == quantity:
            values.append(col)
    want = ", ".join(quantity if not u else f"{quantity}_{u}" for u in VALUE_UNITS[quantity])
    if not values:
        raise MapError(f"{source}, row {row} (the header), column {want}: missing; a map of "
                       f"{quantity} needs it (the header is {', '.join(names)})")
    if not axes:
        raise MapError(f"{source}, row {row} (the header), columns {', '.join(names)}: no axis "
                       "column; need one or more of p_<unit>, v_<unit>, T_<unit>")
    return axes + values


def _cells(source: str, rows: list[tuple[int, str]], cols: list[tuple],
           header: list[str]) -> np.ndarray:
    """The numbers of the ``cols`` of every row (as written), each checked."""
    out = np.empty((len(rows), len(cols)))
    for r, (n, line) in enumerate(rows):
        fields = [s.strip() for s in next(csv.reader([line]))]
        if len(fields) != len(header):
            col = header[len(fields)] if len(fields) < len(header) else f"#{len(fields)}"
            raise MapError(f"{source}, row {n}, column {col}: {len(fields)} fields; the "
                           f"header has {len(header)} ({', '.join(header)})")
        for j, (i, name, kind, unit, f, o) in enumerate(cols):
            where = f"{source}, row {n}, column {name}"
            try:
                x = float(fields[i])
            except ValueError:
                raise MapError(f"{where}: {fields[i]!r} is not a number") from None
            if not np.isfinite(x):
                raise MapError(f"{where}: {fields[i]} is not allowed; need a finite number")
            lo, hi, why = BOUNDS[kind]
            si = x * f + o
            if not lo <= si <= hi:
                # below a physical zero is impossible; beyond the bounds, a unit slip
                word = "is not allowed" if si < lo and lo == 0.0 else "is implausible"
                u = f" {unit}" if unit else ""
                raise MapError(f"{where}: {fields[i]}{u} {word}; allowed: {(lo - o) / f:g} "
                               f"to {(hi - o) / f:g}{u} ({why})")
            out[r, j] = x
    return out


def _pressures_plausible(source: str, raw: np.ndarray, rownos: list[int],
                         cols: list[tuple]) -> None:
    """Refuse a pressure column whose largest value is below 1 kPa (MPa under a Pa header)."""
    for j, (_, name, kind, unit, f, _o) in enumerate(cols):
        if kind != "p":
            continue
        r = int(np.argmax(raw[:, j]))
        if 0.0 < raw[r, j] * f < _P_LOWEST_MAX:
            raise MapError(f"{source}, row {rownos[r]}, column {name}: the largest pressure "
                           f"is {raw[r, j]:g} {unit}, implausible for a brake map (0.1 to 20 "
                           f"MPa); the values look like MPa or bar under a {unit} header")


def _tensor(source: str, raw: np.ndarray, rownos: list[int], cols: list[tuple]):
    """The grid's axes (each column's sorted distinct values) and the values on it;
    refuses a grid point given twice or missing."""
    axes = cols[:-1]
    names = ", ".join(c[1] for c in axes)
    uniq = [np.unique(raw[:, j]) for j in range(len(axes))]
    idx = [np.searchsorted(u, raw[:, j]) for j, u in enumerate(uniq)]
    seen = np.full(tuple(u.size for u in uniq), -1)

    def point(key) -> str:
        return ", ".join(f"{c[1]} = {u[k]:g}" for c, u, k in zip(axes, uniq, key))

    for r, key in enumerate(zip(*idx)):
        if seen[key] >= 0:
            raise MapError(f"{source}, row {rownos[r]}, columns {names}: the grid point "
                           f"{point(key)} is also on row {rownos[seen[key]]}; give each "
                           "combination once")
        seen[key] = r
    missing = np.argwhere(seen < 0)
    if missing.size:
        raise MapError(f"{source}, rows {rownos[0]} to {rownos[-1]}, columns {names}: no row "
                       f"for the grid point {point(tuple(missing[0]))} ({len(missing)} of "
                       f"the {seen.size} combinations of the columns' values missing); the "
                       "rows must fill a full grid, each combination once")
    grid = tuple(tuple(u * c[4] + c[5]) for c, u in zip(axes, uniq))
    return grid, raw[seen, -1] * cols[-1][4]


def parse_table(text: str, source: str, quantity: str) -> dict:
    """A map's CSV text as the arguments of a :class:`~brakewear.laws.maps.TableMap`.

    Parameters
    ----------
    text
        The file's content (see the module docstring).
    source
        The file's name, for messages.
    quantity
        ``"mu"`` (column ``mu``) or ``"k"`` (column ``k_m2_N`` or ``k_mm3_Nm``);
        the other value columns a file may hold are not read.

    Returns
    -------
    dict
        ``axes``, ``grid`` (SI), ``values`` (SI), ``quantity``, ``units`` (the
        file's, for messages) and ``source``.
    """
    if quantity not in VALUE_UNITS:
        raise MapError(f"{source}: quantity = {quantity!r} is not allowed; allowed: "
                       f"{', '.join(map(repr, VALUE_UNITS))}")
    lines = [(n, s) for n, s in enumerate(text.splitlines(), 1)
             if s.strip() and not s.lstrip().startswith("#")]
    if not lines:
        raise MapError(f"{source}, row 1, column (none): no header; the first line that is "
                       "not a comment names the columns, e.g. p_MPa,v_m_s,T_C,mu")
    (hrow, hline), rows = lines[0], lines[1:]
    header = [s.strip() for s in next(csv.reader([hline]))]
    cols = _header(source, hrow, header, quantity)
    if not rows:
        raise MapError(f"{source}, row {hrow} (the header), columns {', '.join(header)}: no "
                       "rows under the header")
    raw = _cells(source, rows, cols, header)
    rownos = [n for n, _ in rows]
    _pressures_plausible(source, raw, rownos, cols)
    grid, values = _tensor(source, raw, rownos, cols)
    return {"axes": tuple(c[2] for c in cols[:-1]), "grid": grid, "values": values,
            "quantity": quantity, "units": tuple(c[3] for c in cols[:-1]), "source": source}


def read_table(path: str | os.PathLike, quantity: str) -> dict:
    """:func:`parse_table` of the file ``path``."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except OSError as e:
        raise MapError(f"{path}: cannot read the map ({e.strerror or e})") from None
    except UnicodeDecodeError as e:
        raise MapError(f"{path}: not a text file ({e.reason} at byte {e.start})") from None
    logger.debug("reading the %s map %s", quantity, path)
    return parse_table(text, str(path), quantity)
