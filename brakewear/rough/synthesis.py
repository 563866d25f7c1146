"""Self-affine random surfaces from a power spectrum (:func:`self_affine`).

The isotropic power spectral density is flat below the roll-off wavevector
``q_r``, a power law between ``q_r`` and the short-wavelength cut-off
``q_s``, and zero above it (Persson 2006; Jacobs, Junge and Pastewka 2017)::

    C(q) = C0                            0 < q < q_r
    C(q) = C0 (q / q_r)^(-2 (1 + H))     q_r <= q <= q_s
    C(q) = 0                             q > q_s (and q = 0: zero mean)

``H`` is the Hurst exponent (0 < H < 1).  ``C0`` is set so that the surface
has the asked rms height or rms slope (Sdq) exactly: with the default
random-phase amplitudes ``|h_q| = sqrt(C(q))`` and only the phases are
random, so every seed has the same spectrum; ``amplitudes = "gaussian"``
draws Gaussian Fourier coefficients (a Gaussian random field) and scales by
the expected spectrum, so the statistics scatter from seed to seed.

The random numbers are drawn per wavevector on the set ``|i|, |j| <=
L / lambda_s`` only, so the same seed, length and cut-off give the **same
continuous surface on every grid** fine enough to hold it (two pixels or
more per cut-off wavelength): a refinement study samples one surface
more finely, rather than drawing a new one.
"""
from __future__ import annotations

import logging

import numpy as np

from ..errors import RoughnessError
from .topography import Topography, _positive

logger = logging.getLogger(__name__)

__all__ = ["self_affine", "self_affine_psd"]


def self_affine_psd(q, hurst: float, rolloff: float, cutoff: float):
    """Unscaled spectrum (``C0 = 1``) at wavevectors ``q`` (rad/m): flat below
    ``rolloff``, ``(q / rolloff)^(-2 (1 + H))`` up to ``cutoff``, zero above and at 0."""
    q = np.asarray(q, dtype=float)
    with np.errstate(divide="ignore"):
        C = np.where(q < rolloff, 1.0, (q / rolloff) ** (-2.0 * (1.0 + hurst)))
    return np.where((q > 0) & (q <= cutoff * (1 + 1e-12)), C, 0.0)


def _check(n, length, hurst, rms_height, rms_slope, rolloff, cutoff, amplitudes):
    if not isinstance(n, (int, np.integer)) or n < 8:
        raise RoughnessError(f"n = {n!r} is not allowed; need a whole number of pixels >= 8")
    L = _positive("length", length)
    if not (isinstance(hurst, (int, float)) and 0.0 < hurst < 1.0):
        raise RoughnessError(f"hurst = {hurst!r} is not allowed; need 0 < H < 1")
    if (rms_height is None) == (rms_slope is None):
        raise RoughnessError("give exactly one of rms_height (m) and rms_slope (Sdq, "
                             f"dimensionless); got rms_height = {rms_height!r}, "
                             f"rms_slope = {rms_slope!r}")
    if rms_height is not None:
        _positive("rms_height", rms_height)
    else:
        _positive("rms_slope", rms_slope, unit="(dimensionless)")
    lam_r = L if rolloff is None else _positive("rolloff", rolloff)
    lam_s = 4 * L / n if cutoff is None else _positive("cutoff", cutoff)
    if lam_r > L * (1 + 1e-12):
        raise RoughnessError(f"rolloff = {lam_r:.4g} m is not allowed; need a wavelength "
                             f"<= length ({L:.4g} m)")
    if lam_s > lam_r * (1 + 1e-12):
        raise RoughnessError(f"cutoff = {lam_s:.4g} m is not allowed; need a wavelength "
                             f"<= rolloff ({lam_r:.4g} m)")
    if lam_s < 2 * L / n * (1 - 1e-12):
        raise RoughnessError(f"cutoff = {lam_s:.4g} m is not allowed on {n} pixels of "
                             f"{L / n:.4g} m; need at least two pixels per wavelength "
                             f"(cutoff >= {2 * L / n:.4g} m)")
    if amplitudes not in ("random_phase", "gaussian"):
        raise RoughnessError(f"amplitudes = {amplitudes!r} is not allowed; allowed: "
                             "'random_phase', 'gaussian'")
    return L, lam_r, lam_s


def self_affine(n: int, length: float, hurst: float, *, rms_height: float | None = None,
                rms_slope: float | None = None, rolloff: float | None = None,
                cutoff: float | None = None, seed: int = 0,
                amplitudes: str = "random_phase") -> Topography:
    """A periodic self-affine surface on ``n x n`` pixels over ``length x length``.

    Parameters
    ----------
    n, length
        Pixels per side and the period (m).
    hurst
        Hurst exponent ``H``, 0 < H < 1.
    rms_height, rms_slope
        Exactly one: the rms height (m) or the areal rms slope Sdq.
    rolloff, cutoff
        Roll-off and cut-off *wavelengths* (m): ``q_r = 2 pi / rolloff``
        (default ``length``: no plateau) and ``q_s = 2 pi / cutoff``
        (default four pixels); ``cutoff`` at least two pixels.
    seed
        Seed of the random phases (numpy ``default_rng``).
    amplitudes
        ``"random_phase"`` (default: exact spectrum, random phases) or
        ``"gaussian"`` (Gaussian Fourier coefficients).

    Returns
    -------
    Topography
        Periodic, zero mean.
    """
    L, lam_r, lam_s = _check(n, length, hurst, rms_height, rms_slope, rolloff, cutoff,
                             amplitudes)
    q_r, q_s = 2 * np.pi / lam_r, 2 * np.pi / lam_s
    M = int(np.floor(L / lam_s * (1 + 1e-12)))          # largest mode index kept
    k = np.arange(-M, M + 1)
    I, J = np.meshgrid(k, k, indexing="ij")
    q = 2 * np.pi / L * np.hypot(I, J)
    C = self_affine_psd(q, hurst, q_r, q_s)
    rng = np.random.default_rng(seed)
    if amplitudes == "random_phase":
        phi = rng.uniform(0.0, 2 * np.pi, size=I.shape)
        phi = phi - phi[::-1, ::-1]                  # h(-q) = conj h(q): a real surface
        coef = np.sqrt(C) * np.exp(1j * phi)
    else:
        z = rng.standard_normal(I.shape) + 1j * rng.standard_normal(I.shape)
        z = (z + np.conj(z[::-1, ::-1])) / 2.0       # hermitian, E|z|^2 = 1
        coef = np.sqrt(C) * z
    # the scale from the expected spectrum, so that the Gaussian surfaces scatter
    if rms_height is not None:
        scale = rms_height / np.sqrt(C.sum())
    else:
        scale = rms_slope / np.sqrt((q ** 2 * C).sum())
    F = np.zeros((n, n), dtype=complex)
    F[I % n, J % n] = scale * coef
    h = np.real(np.fft.ifft2(F)) * n * n
    src = (f"self_affine(n={n}, length={L:.4g} m, H={hurst}, rolloff={lam_r:.4g} m, "
           f"cutoff={lam_s:.4g} m, seed={seed}, {amplitudes})")
    logger.debug("%s: rms height %.4g m", src, float(np.sqrt(np.mean(h ** 2))))
    return Topography(h, (L / n, L / n), periodic=True, source=src)
