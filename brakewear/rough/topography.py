"""A rough surface on a regular grid (:class:`Topography`) and its statistics.

Heights ``h`` (m) sit on the centres of ``nx x ny`` pixels of size ``dx x dy``.
A periodic topography repeats with the period ``(nx dx, ny dy)``; a free one
is a window of a larger surface.

Statistics (ISO 25178 names in brackets):

* rms height ``sqrt(<(h - <h>)^2>)`` [Sq];
* rms slope ``sqrt(<|grad h|^2>)`` [Sdq], the areal slope (twice the mean
  square profile slope of an isotropic surface): spectral on a periodic
  grid (exact for a band-limited surface), central differences otherwise;
* the isotropic power spectral density ``C(q)`` with the normalisation
  ``<h^2> = sum_q C(q) / A`` (``A`` the area; ``C`` in m^4), so that
  ``<h^2> = int C(q) d^2q / (2 pi)^2`` in the continuum; a self-affine
  surface of Hurst exponent ``H`` has ``C ~ q^(-2 (1 + H))``
  (Jacobs, Junge and Pastewka 2017).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ..errors import RoughnessError

logger = logging.getLogger(__name__)

__all__ = ["Topography", "rms_height", "rms_slope", "radial_psd", "hurst_fit", "wavevectors"]


def _positive(name: str, value, unit: str = "m") -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise RoughnessError(f"{name} = {value!r} is not allowed; need a number > 0 "
                             f"({unit})") from None
    if not (np.isfinite(v) and v > 0):
        raise RoughnessError(f"{name} = {value!r} {unit} is not allowed; need a finite "
                             "value > 0")
    return v


def pixel_pair(pixel, name: str = "pixel_size") -> tuple[float, float]:
    """``(dx, dy)`` of a number or a pair, checked (> 0)."""
    if np.ndim(pixel) == 0:
        d = _positive(name, pixel)
        return d, d
    if len(pixel) != 2:
        raise RoughnessError(f"{name} = {pixel!r} is not allowed; need a number or a pair "
                             "(dx, dy) in m")
    return _positive(f"{name}[0]", pixel[0]), _positive(f"{name}[1]", pixel[1])


@dataclass(frozen=True)
class Topography:
    """Heights on a regular grid.

    Parameters
    ----------
    heights
        ``(nx, ny)`` array (m), finite; at least 4 x 4 pixels.
    pixel
        Pixel size ``(dx, dy)`` (m), or one number for square pixels.
    periodic
        Whether the grid is one period of a periodic surface.
    source
        Where it came from (a file, a generator and its settings), for messages.
    """

    heights: np.ndarray
    pixel: tuple[float, float]
    periodic: bool = False
    source: str = ""

    def __post_init__(self):
        h = np.asarray(self.heights, dtype=float)
        where = f" ({self.source})" if self.source else ""
        if h.ndim != 2 or min(h.shape) < 4:
            raise RoughnessError(f"heights{where} have shape {h.shape}; need a 2D grid of at "
                                 "least 4 x 4 pixels")
        bad = ~np.isfinite(h)
        if bad.any():
            i, j = np.argwhere(bad)[0]
            raise RoughnessError(f"heights{where} hold {int(bad.sum())} non-finite values, "
                                 f"the first at row {i + 1}, column {j + 1} (counting from 1) "
                                 f"({float(h[i, j])!r}); fill or crop the missing points first")
        object.__setattr__(self, "heights", h)
        object.__setattr__(self, "pixel", pixel_pair(self.pixel))
        object.__setattr__(self, "periodic", bool(self.periodic))

    @property
    def shape(self) -> tuple[int, int]:
        return self.heights.shape

    @property
    def size(self) -> tuple[float, float]:
        """Physical size ``(Lx, Ly)`` (m)."""
        return self.shape[0] * self.pixel[0], self.shape[1] * self.pixel[1]

    @property
    def pixel_area(self) -> float:
        return self.pixel[0] * self.pixel[1]

    def coordinates(self) -> tuple[np.ndarray, np.ndarray]:
        """Pixel-centre coordinates ``(X, Y)`` (m), each ``(nx, ny)``, centred on the grid."""
        (nx, ny), (dx, dy) = self.shape, self.pixel
        x = (np.arange(nx) - (nx - 1) / 2) * dx
        y = (np.arange(ny) - (ny - 1) / 2) * dy
        return np.meshgrid(x, y, indexing="ij")

    def scaled(self, factor: float) -> Topography:
        """The same surface with its heights times ``factor``."""
        return Topography(self.heights * float(factor), self.pixel, self.periodic,
                          self.source)

    def rms_height(self) -> float:
        return rms_height(self)

    def rms_slope(self) -> float:
        return rms_slope(self)


def rms_height(t: Topography) -> float:
    """Root mean square of the heights about their mean [Sq] (m)."""
    h = t.heights
    return float(np.sqrt(np.mean((h - h.mean()) ** 2)))


def wavevectors(shape, pixel) -> tuple[np.ndarray, np.ndarray]:
    """Wavevector components ``(qx, qy)`` (rad/m) of a full ``fft2`` of the grid."""
    (nx, ny), (dx, dy) = shape, pixel
    qx = 2 * np.pi * np.fft.fftfreq(nx, d=dx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, d=dy)
    return np.meshgrid(qx, qy, indexing="ij")


def rms_slope(t: Topography, method: str = "auto") -> float:
    """Areal rms slope ``sqrt(<|grad h|^2>)`` [Sdq].

    ``method``: ``"spectral"`` (exact for a band-limited periodic surface),
    ``"difference"`` (central differences inside the grid, one-sided at free
    edges; periodic wrap on a periodic grid) or ``"auto"`` (spectral if
    periodic).
    """
    if method not in ("auto", "spectral", "difference"):
        raise RoughnessError(f"method = {method!r} is not allowed; allowed: 'auto', "
                             "'spectral', 'difference'")
    if method == "spectral" or (method == "auto" and t.periodic):
        qx, qy = wavevectors(t.shape, t.pixel)
        hh = np.fft.fft2(t.heights)
        n = t.heights.size
        return float(np.sqrt(np.sum((qx ** 2 + qy ** 2) * np.abs(hh) ** 2)) / n)
    h, (dx, dy) = t.heights, t.pixel
    if t.periodic:
        gx = (np.roll(h, -1, 0) - np.roll(h, 1, 0)) / (2 * dx)
        gy = (np.roll(h, -1, 1) - np.roll(h, 1, 1)) / (2 * dy)
    else:
        gx, gy = np.gradient(h, dx, dy)
    return float(np.sqrt(np.mean(gx ** 2 + gy ** 2)))


def radial_psd(t: Topography, bins: int | None = None, window: str | None = None):
    """Isotropic power spectral density ``C(q)`` (m^4), averaged over rings of ``|q|``.

    Normalised so that ``sum_q C(q) / A = <(h - <h>)^2>`` over the grid's
    wavevectors (``A`` the grid's area).  ``window = "hann"`` tapers a
    non-periodic window first (its variance loss is compensated).

    Returns
    -------
    q, C
        Ring centres (rad/m) and the mean ``C`` in each ring (empty rings dropped).
    """
    h = t.heights - t.heights.mean()
    if window == "hann":
        w = np.outer(np.hanning(h.shape[0]), np.hanning(h.shape[1]))
        h = h * w / np.sqrt(np.mean(w ** 2))
    elif window is not None:
        raise RoughnessError(f"window = {window!r} is not allowed; allowed: None, 'hann'")
    n = h.size
    A = t.size[0] * t.size[1]
    C = A * np.abs(np.fft.fft2(h)) ** 2 / n ** 2
    qx, qy = wavevectors(t.shape, t.pixel)
    q = np.hypot(qx, qy).ravel()
    dq = 2 * np.pi / max(t.size)
    qmax = np.pi / max(t.pixel)
    nb = int(bins) if bins else max(int(qmax / dq), 2)
    edges = np.linspace(0.5 * dq, qmax, nb + 1)
    idx = np.digitize(q, edges) - 1
    keep = (idx >= 0) & (idx < nb)
    cnt = np.bincount(idx[keep], minlength=nb)
    tot = np.bincount(idx[keep], weights=C.ravel()[keep], minlength=nb)
    qs = np.bincount(idx[keep], weights=q[keep], minlength=nb)
    ok = cnt > 0
    return qs[ok] / cnt[ok], tot[ok] / cnt[ok]


def hurst_fit(t: Topography, q_min: float, q_max: float, window: str | None = None) -> float:
    """Hurst exponent from a least-squares line through ``log C(q)`` on ``q_min <= q <= q_max``.

    ``C ~ q^(-2 (1 + H))`` gives ``H = -slope / 2 - 1``.
    """
    q, C = radial_psd(t, window=window)
    sel = (q >= q_min) & (q <= q_max) & (C > 0)
    if sel.sum() < 3:
        raise RoughnessError(f"hurst_fit: {int(sel.sum())} spectrum rings in [{q_min:.4g}, "
                             f"{q_max:.4g}] rad/m; need at least 3 (the grid's wavevectors "
                             f"run from {q.min():.4g} to {q.max():.4g} rad/m)")
    slope = np.polyfit(np.log(q[sel]), np.log(C[sel]), 1)[0]
    return float(-slope / 2.0 - 1.0)
