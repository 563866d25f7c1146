"""Measured topographies: a plain height grid read from a file (:func:`read_topography`).

Formats (by the file's suffix):

* ``.npy``: one 2D array of heights;
* ``.npz``: the array ``heights`` and, optionally, ``pixel_size`` (a number or
  a pair, in the file's ``unit``) when no ``pixel_size`` is given;
* ``.txt``, ``.csv``, ``.dat``, ``.asc``: a grid of numbers, one row of the
  grid per line, separated by commas, semicolons, tabs or spaces; lines
  starting with ``#`` are comments.  Rows run along x (the first index),
  columns along y.

The heights and the pixel size are in ``unit`` (``"m"``, ``"mm"``, ``"um"``
or ``"nm"``).  Instrument formats (Digital Surf ``.sur``, ``.plu``, ``.opd``,
...) are not read here: export a height grid, or read them with the
SurfaceTopography package and pass the array to :class:`Topography`.
"""
from __future__ import annotations

import logging
import re
from os import PathLike
from pathlib import Path

import numpy as np

from ..errors import RoughnessError
from ..storage import load_array, load_arrays
from .topography import Topography, pixel_pair

logger = logging.getLogger(__name__)

__all__ = ["read_topography", "detrend", "LENGTH_UNITS", "TEXT_SUFFIXES"]

#: Length units of a topography file -> factor to metres.
LENGTH_UNITS = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "nm": 1e-9}

#: Suffixes read as a text grid.
TEXT_SUFFIXES = (".txt", ".csv", ".dat", ".asc")

_SPLIT = re.compile(r"[,;\s]+")


def _text_grid(path: Path) -> np.ndarray:
    rows, width, first = [], None, None
    with open(path, encoding="utf-8-sig") as f:
        for n, line in enumerate(f, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            cells = [c for c in _SPLIT.split(s) if c]
            try:
                row = [float(c) for c in cells]
            except ValueError:
                bad = next(c for c in cells if not _is_float(c))
                col = cells.index(bad) + 1
                raise RoughnessError(f"{path}: line {n}, column {col}: {bad!r} is not a "
                                     "number; a height grid holds numbers only (comments "
                                     "start with #)") from None
            if width is None:
                width, first = len(row), n
            elif len(row) != width:
                raise RoughnessError(f"{path}: line {n} has {len(row)} values, line {first} "
                                     f"has {width}; every row of the grid needs the same "
                                     "number of values")
            rows.append(row)
    if not rows:
        raise RoughnessError(f"{path}: no numbers found; expected a grid of heights")
    return np.asarray(rows, dtype=float)


def _is_float(c: str) -> bool:
    try:
        float(c)
        return True
    except ValueError:
        return False


def detrend(heights: np.ndarray, mode: str | None = "plane") -> np.ndarray:
    """Heights less their mean (``"mean"``) or their least-squares plane (``"plane"``);
    ``None`` leaves them as they are."""
    h = np.asarray(heights, dtype=float)
    if mode is None:
        return h
    if mode == "mean":
        return h - h.mean()
    if mode != "plane":
        raise RoughnessError(f"detrend = {mode!r} is not allowed; allowed: 'plane', 'mean', "
                             "None")
    nx, ny = h.shape
    X, Y = np.meshgrid(np.arange(nx) - (nx - 1) / 2, np.arange(ny) - (ny - 1) / 2,
                       indexing="ij")
    A = np.column_stack([np.ones(h.size), X.ravel(), Y.ravel()])
    c = np.linalg.lstsq(A, h.ravel(), rcond=None)[0]
    return h - (A @ c).reshape(h.shape)


def read_topography(path: str | PathLike, pixel_size=None, unit: str = "m",
                    periodic: bool = False, detrend_mode: str | None = "plane") -> Topography:
    """Read a height grid (see the module's list of formats).

    Parameters
    ----------
    path
        The file.
    pixel_size
        Pixel size in ``unit``: a number or ``(dx, dy)``; may come from an
        ``.npz`` file's ``pixel_size`` instead.
    unit
        Length unit of the heights and the pixel size: ``"m"``, ``"mm"``,
        ``"um"``, ``"nm"``.
    periodic
        Whether the grid is one period of a periodic surface.
    detrend_mode
        ``"plane"`` (default: the least-squares plane removed, the usual
        levelling of a measurement), ``"mean"`` or None.

    Raises
    ------
    RoughnessError
        Naming the file, and the line and column of a bad value.
    """
    path = Path(path)
    if unit not in LENGTH_UNITS:
        raise RoughnessError(f"{path}: unit = {unit!r} is not allowed; allowed: "
                             f"{', '.join(LENGTH_UNITS)}")
    suffix = path.suffix.lower()
    if not path.is_file():
        raise RoughnessError(f"{path}: no such file")
    file_pixel = None
    try:
        if suffix == ".npy":
            h = load_array(path, "the topography", kind=RoughnessError)
        elif suffix == ".npz":
            z = load_arrays(path, "the topography", kind=RoughnessError)
            if "heights" not in z:
                raise RoughnessError(f"{path}: no array 'heights'; arrays: "
                                     f"{', '.join(z) or 'none'}")
            h = z["heights"]
            file_pixel = z.get("pixel_size")
        elif suffix in TEXT_SUFFIXES:
            h = _text_grid(path)
        else:
            raise RoughnessError(f"{path}: suffix {suffix!r} is not read; allowed: .npy, .npz, "
                                 f"{', '.join(TEXT_SUFFIXES)} (a plain height grid)")
    except (OSError, ValueError) as exc:
        if isinstance(exc, RoughnessError):
            raise
        what = "not a text file" if isinstance(exc, UnicodeDecodeError) else "cannot read"
        raise RoughnessError(f"{path}: {what} ({exc})") from None
    h = np.asarray(h)
    if h.ndim != 2 or not np.issubdtype(h.dtype, np.number):
        raise RoughnessError(f"{path}: holds an array of shape {h.shape} ({h.dtype}); need a "
                             "2D grid of numbers")
    if pixel_size is None:
        pixel_size = file_pixel
    if pixel_size is None:
        raise RoughnessError(f"{path}: pixel_size is missing; give it (in {unit}), e.g. "
                             "pixel_size=0.5 for 0.5 um pixels with unit='um'")
    f = LENGTH_UNITS[unit]
    try:
        dx, dy = pixel_pair(pixel_size)
    except RoughnessError as exc:
        raise RoughnessError(f"{path}: {exc} (in {unit})") from None
    try:
        t = Topography(h.astype(float), (dx * f, dy * f), periodic, source=str(path))
    except RoughnessError as exc:
        raise RoughnessError(f"{path}: {exc}") from None
    t = Topography(detrend(t.heights, detrend_mode) * f, t.pixel, periodic, source=str(path))
    logger.info("read %s: %d x %d pixels of %.4g x %.4g m, rms height %.4g m", path,
                *t.shape, *t.pixel, t.rms_height())
    return t
