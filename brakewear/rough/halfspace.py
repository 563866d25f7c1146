"""The elastic half-space's surface compliance on a grid, applied by FFT (:class:`HalfSpace`).

A surface traction uniform over each pixel moves the surface at the pixel
centres by a discrete convolution ``u = K * p``.

* **Normal** (Boussinesq; Love 1929 for a uniform rectangle)::

      u_z(x, y) = 1 / (pi E*) int int p / r dA

* **Tangential** (Cerruti; Johnson 1985, section 3.4): a traction ``q_x``
  moves the surface along x by::

      u_x(x, y) = 1 / (pi E*) int int q_x (1/r + nu / (1 - nu) x^2 / r^3) dA

  with ``E* = E / (1 - nu^2)`` of one elastic body on a rigid one (and the
  same formula for two bodies of one material).  The normal-tangential
  coupling (a term in ``(1 - 2 nu)``) is left out: exact for ``nu = 0.5``
  or two equal materials, the usual (Goodman) approximation otherwise.

Over a pixel the integrals have closed forms: the double difference over its
corners of ``x asinh(y/|x|) + y asinh(x/|y|)`` (for ``1/r``) and of
``y asinh(x/|y|)`` (for ``x^2/r^3``).

**Free** grids (an isolated contact in an infinite half-space) embed the
``nx x ny`` grid in a ``2nx x 2ny`` circulant (zero padding), which makes
the cyclic convolution the exact linear one.  **Periodic** grids (one
period of a periodic surface) use the continuum's Fourier multipliers
``2 / (E* q)`` and ``2 (1 - nu qx^2/q^2) / (E* (1 - nu) q)``, with the mean
(``q = 0``) left out: a periodic half-space has no mean displacement.

The kernel's transform is computed once per grid and direction and kept
(``scipy.fft`` real transforms, float64, ``workers`` threads); the free
grid's transforms skip the padded half of the rows.
"""
from __future__ import annotations

import logging

import numpy as np
import scipy.fft as sfft

from ..errors import RoughnessError
from .topography import _positive, pixel_pair

logger = logging.getLogger(__name__)

__all__ = ["HalfSpace", "pixel_kernel"]

DIRECTIONS = ("normal", "tangential")


def _corner_sum(F, x, y, a, b):
    """Integral over the pixel ``[x - a, x + a] x [y - b, y + b]`` of a density whose
    mixed antiderivative is ``F``."""
    return F(x + a, y + b) - F(x + a, y - b) - F(x - a, y + b) + F(x - a, y - b)


def _xasinh(x, y):
    """``x asinh(y / |x|)``, zero on ``x = 0``."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(x == 0, 0.0, x * np.arcsinh(y / np.abs(np.where(x == 0, 1, x))))


def _F_inv_r(x, y):
    return _xasinh(x, y) + _xasinh(y, x)


def _F_x2_r3(x, y):
    return _xasinh(y, x)


def pixel_kernel(x, y, pixel, modulus: float, poisson: float = 0.0,
                 direction: str = "normal"):
    """Displacement at ``(x, y)`` (m) of a unit traction (1 Pa) on the pixel centred at 0.

    ``direction = "normal"``: ``u_z`` under a normal pressure;
    ``"tangential"``: ``u_x`` under a traction along x.
    """
    a, b = 0.5 * pixel[0], 0.5 * pixel[1]
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    K = _corner_sum(_F_inv_r, x, y, a, b)
    if direction == "tangential":
        K = K + poisson / (1.0 - poisson) * _corner_sum(_F_x2_r3, x, y, a, b)
    return K / (np.pi * modulus)


class HalfSpace:
    """Surface compliance of an elastic half-space on a regular grid.

    Parameters
    ----------
    shape
        ``(nx, ny)`` pixels.
    pixel
        Pixel size (m): a number or ``(dx, dy)``.
    modulus
        Contact modulus ``E*`` (Pa).
    poisson
        Poisson's ratio (tangential compliance only), in [0, 0.5).
    periodic
        Periodic grid (Fourier multipliers) or free (zero-padded) grid.
    workers
        Threads of ``scipy.fft`` (default 1).
    """

    def __init__(self, shape, pixel, modulus: float, poisson: float = 0.3,
                 periodic: bool = False, workers: int = 1):
        if len(shape) != 2 or min(shape) < 2 or not all(
                isinstance(s, (int, np.integer)) for s in shape):
            raise RoughnessError(f"shape = {shape!r} is not allowed; need two whole numbers "
                                 ">= 2 (pixels along x and y)")
        self.shape = (int(shape[0]), int(shape[1]))
        self.pixel = pixel_pair(pixel, "pixel")
        self.modulus = _positive("modulus", modulus, "Pa")
        if not (isinstance(poisson, (int, float)) and 0.0 <= poisson < 0.5):
            raise RoughnessError(f"poisson = {poisson!r} is not allowed; need 0 <= nu < 0.5")
        self.poisson = float(poisson)
        self.periodic = bool(periodic)
        self.workers = int(workers)
        self._hats: dict[str, np.ndarray] = {}

    @property
    def pixel_area(self) -> float:
        return self.pixel[0] * self.pixel[1]

    # ------------------------------------------------------------ kernels --
    def kernel_hat(self, direction: str = "normal") -> np.ndarray:
        """The real FFT of the kernel (cached): ``(nx, ny//2 + 1)`` periodic,
        ``(2nx, ny + 1)`` free."""
        if direction not in DIRECTIONS:
            raise RoughnessError(f"direction = {direction!r} is not allowed; allowed: "
                                 f"{', '.join(DIRECTIONS)}")
        if direction not in self._hats:
            self._hats[direction] = (self._periodic_hat(direction) if self.periodic
                                     else self._free_hat(direction))
        return self._hats[direction]

    def _periodic_hat(self, direction: str) -> np.ndarray:
        (nx, ny), (dx, dy) = self.shape, self.pixel
        qx = 2 * np.pi * np.fft.fftfreq(nx, d=dx)[:, None]
        qy = 2 * np.pi * np.fft.rfftfreq(ny, d=dy)[None, :]
        q = np.hypot(qx, qy)
        with np.errstate(divide="ignore", invalid="ignore"):
            k = 2.0 / (self.modulus * q)
            if direction == "tangential":
                nu = self.poisson
                k = k * (1.0 - nu * qx ** 2 / q ** 2) / (1.0 - nu)
        k[0, 0] = 0.0
        return k

    def _free_hat(self, direction: str) -> np.ndarray:
        (nx, ny), (dx, dy) = self.shape, self.pixel
        ix = np.fft.fftfreq(2 * nx, d=1.0 / (2 * nx))     # 0..nx-1, -nx..-1
        iy = np.fft.fftfreq(2 * ny, d=1.0 / (2 * ny))
        X, Y = np.meshgrid(ix * dx, iy * dy, indexing="ij")
        K = pixel_kernel(X, Y, self.pixel, self.modulus, self.poisson, direction)
        return sfft.rfft2(K, workers=self.workers)

    # -------------------------------------------------------- convolution --
    def forward(self, p: np.ndarray) -> np.ndarray:
        """The transform of a traction field as :meth:`apply_hat` takes it."""
        if self.periodic:
            return sfft.rfft2(p, workers=self.workers)
        nx, ny = self.shape
        P = sfft.rfft(p, n=2 * ny, axis=1, workers=self.workers)
        return sfft.fft(P, n=2 * nx, axis=0, workers=self.workers)

    def apply_hat(self, P: np.ndarray, direction: str = "normal") -> np.ndarray:
        """Displacement field of the transformed traction ``P`` (:meth:`forward`)."""
        K = self.kernel_hat(direction)
        if self.periodic:
            return sfft.irfft2(P * K, s=self.shape, workers=self.workers)
        nx, ny = self.shape
        U = sfft.ifft(P * K, axis=0, workers=self.workers)[:nx]
        u = sfft.irfft(U, n=2 * ny, axis=1, workers=self.workers)
        return np.ascontiguousarray(u[:, :ny])

    def displacement(self, p: np.ndarray, direction: str = "normal") -> np.ndarray:
        """Surface displacement (m) under the traction ``p`` (Pa) per pixel, ``(nx, ny)``:
        ``u_z`` of a normal pressure, or ``u_x`` of a traction along x."""
        p = np.asarray(p, dtype=float)
        if p.shape != self.shape:
            raise RoughnessError(f"traction has shape {p.shape}; need {self.shape}")
        return self.apply_hat(self.forward(p), direction)
