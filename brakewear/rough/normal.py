"""Frictionless normal contact of a rigid indenter on an elastic half-space:
constrained conjugate gradients (Polonsky and Keer 1999) on a :class:`HalfSpace`.

The unknown is the pressure ``p >= 0`` per pixel.  With the initial
separation ``g0`` (m; the indenter's profile above the undeformed surface,
e.g. ``r^2/(2R) - h`` for a sphere on a rough plane), the rigid approach
``delta`` and the elastic displacement ``u = K * p`` (into the body), the
gap ``g = g0 + u - delta`` must satisfy::

    g >= 0,   p >= 0,   g p = 0

Each iteration is one conjugate-gradient step on the pixels in contact,
projected on ``p >= 0``; pixels that open are dropped and pixels that
overlap (``p = 0`` and ``g < 0``) enter with a steepest-descent step,
which restarts the conjugacy.  Under a prescribed **load** the rigid
approach is the mean of ``g0 + u`` over the contact and the pressure is
scaled to the load after each step; under a prescribed **approach** it is
given and the load follows.  Two FFT convolutions per iteration (the
kernel's transform is the :class:`HalfSpace`'s, computed once).

Convergence: the relative change of the pressure in one iteration,
``sum |p - p_old| / sum p``, below ``tol`` (Polonsky and Keer's measure).
The iteration budget is bounded; past it :class:`~brakewear.errors.ConvergenceError`
is raised with the figures (iterations, last change, contact size, load).
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceError, RoughnessError
from .halfspace import HalfSpace

logger = logging.getLogger(__name__)

__all__ = ["NormalContact", "solve_normal", "default_max_iter"]


@dataclass(frozen=True)
class NormalContact:
    """A converged normal contact on a :class:`HalfSpace` grid.

    ``pressure`` (Pa) and ``displacement`` (m) per pixel, ``approach``
    (m, the rigid approach ``delta``), ``load`` (N), ``contact`` (the pixels
    with ``p > 0``), ``iterations``, ``change`` (the last relative pressure
    change), ``gap_error`` (m: the largest ``|g|`` on the contact and the
    deepest overlap outside it) and ``seconds``.
    """

    pressure: np.ndarray
    displacement: np.ndarray
    approach: float
    load: float
    contact: np.ndarray
    pixel_area: float
    iterations: int
    change: float
    gap_error: float
    seconds: float

    @property
    def area(self) -> float:
        """Real contact area (m^2): pixels in contact times the pixel area."""
        return float(self.contact.sum()) * self.pixel_area

    @property
    def contact_fraction(self) -> float:
        return float(self.contact.mean())


def default_max_iter(shape) -> int:
    """Iteration budget: ``max(500, 8 max(nx, ny))`` (the conjugate gradients need a
    few times the grid's side on rough surfaces)."""
    return max(500, 8 * max(shape))


def _check(hs: HalfSpace, gap, load, approach, tol, p0):
    g0 = np.asarray(gap, dtype=float)
    if g0.shape != hs.shape:
        raise RoughnessError(f"gap has shape {g0.shape}; need the half-space grid {hs.shape}")
    if not np.all(np.isfinite(g0)):
        raise RoughnessError("gap holds non-finite values")
    if (load is None) == (approach is None):
        raise RoughnessError("give exactly one of load (N) and approach (m)")
    if load is not None and not (np.isfinite(load) and load > 0):
        raise RoughnessError(f"load = {load!r} N is not allowed; need a force > 0")
    if approach is not None:
        if not np.isfinite(approach):
            raise RoughnessError(f"approach = {approach!r} m is not allowed; need a number")
        if hs.periodic:
            raise RoughnessError("a prescribed approach needs a free grid: a periodic "
                                 "half-space has no mean displacement; prescribe the load")
    if not (0 < tol < 1):
        raise RoughnessError(f"tol = {tol!r} is not allowed; need 0 < tol < 1")
    if p0 is not None:
        p0 = np.asarray(p0, dtype=float)
        if p0.shape != hs.shape or np.any(p0 < 0) or not np.all(np.isfinite(p0)):
            raise RoughnessError(f"p0 must be a finite field >= 0 of shape {hs.shape}")
    return g0, p0


def solve_normal(halfspace: HalfSpace, gap, load: float | None = None,
                 approach: float | None = None, tol: float = 1e-8,
                 max_iter: int | None = None, p0=None) -> NormalContact:
    """Contact pressure of a rigid indenter of initial separation ``gap`` (m).

    Parameters
    ----------
    halfspace
        The elastic body (:class:`HalfSpace`), its grid that of ``gap``.
    gap
        Initial separation ``g0`` per pixel (m); its minimum touches first.
    load, approach
        Exactly one: the total force (N), or the rigid approach ``delta`` (m,
        measured on ``g0``'s datum: contact where ``g0 < delta``; free grids).
    tol
        Relative pressure change per iteration at convergence.
    max_iter
        Iteration budget (default :func:`default_max_iter`).
    p0
        A starting pressure (e.g. the last load step's).

    Raises
    ------
    ConvergenceError
        The budget ran out; ``info`` holds the figures.
    RoughnessError
        Bad input, before any work.
    """
    t0 = time.perf_counter()
    g0, p0 = _check(halfspace, gap, load, approach, tol, p0)
    max_iter = default_max_iter(halfspace.shape) if max_iter is None else int(max_iter)
    A = halfspace.pixel_area
    if load is not None:
        p = np.full(g0.shape, load / (A * g0.size)) if p0 is None or not p0.any() else \
            p0 * (load / (A * p0.sum()))
    else:
        over = np.clip(approach - g0, 0.0, None)
        if not over.any():
            z = np.zeros_like(g0)
            return NormalContact(z, z.copy(), float(approach), 0.0, z > 0, A, 0, 0.0, 0.0,
                                 time.perf_counter() - t0)
        p = p0 if p0 is not None and p0.any() else \
            halfspace.modulus * over / np.sqrt(A * g0.size)
    p, it, change = _iterate(halfspace, g0, p, load, approach, tol, max_iter)
    u = halfspace.displacement(p)
    S = p > 0
    g = g0 + u
    delta = float(g[S].mean()) if load is not None else float(approach)
    g = g - delta
    err = max(float(np.abs(g[S]).max()), float(max(-g[~S].min(), 0.0)) if (~S).any() else 0.0)
    F = float(p.sum() * A)
    res = NormalContact(p, u, delta, F, S, A, it, change, err, time.perf_counter() - t0)
    logger.debug("normal contact: %d iterations, change %.2e, %d of %d pixels in contact, "
                 "%.3f s", it, change, int(S.sum()), S.size, res.seconds)
    return res


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    """Sum of the element-wise product, without BLAS: a threaded BLAS dot stalls for
    milliseconds on a busy machine, far longer than the pass itself."""
    return float(np.einsum("ij,ij->", a, b))


def _iterate(hs: HalfSpace, g0, p, load, approach, tol, max_iter):
    """The constrained conjugate gradients; returns (p, iterations, last change).

    Written with masks (``t`` is zero off the contact) rather than gathers:
    every step is an element-wise pass over the grid besides the two FFTs.
    """
    A = hs.pixel_area
    t = np.zeros_like(p)
    G_old, conj, change = 1.0, False, np.inf
    for it in range(1, max_iter + 1):
        S = (p > 0).astype(float)
        ns = float(S.sum())
        if ns == 0:
            raise ConvergenceError(
                f"normal contact lost every pixel after {it - 1} iterations (grid {hs.shape}"
                f", approach {approach!r} m)", info={"iterations": it - 1})
        g = hs.displacement(p)
        g += g0
        g -= _dot(g, S) / ns if load is not None else approach
        gS = g * S
        G = _dot(gS, gS)
        if conj:
            t *= S
            t *= G / G_old
            t += gS
        else:
            t = gS
        G_old = G
        r = hs.displacement(t)
        if load is not None:
            r -= _dot(r, S) / ns
        rt = _dot(r, t)
        if G == 0.0 or rt <= 0.0:
            return p, it, 0.0               # already exact on this set
        tau = _dot(g, t) / rt
        p_old = p.copy()
        p -= tau * t
        np.clip(p, 0.0, None, out=p)
        over = (p == 0.0) & (g < 0.0)
        conj = not over.any()
        if not conj:
            p[over] -= tau * g[over]
        if load is not None:
            total = p.sum() * A
            if total <= 0:
                raise ConvergenceError(
                    f"normal contact: the pressure vanished at iteration {it} (grid "
                    f"{hs.shape}, load {load:.4g} N)", info={"iterations": it})
            p *= load / total
        p_old -= p
        change = float(np.abs(p_old).sum() / max(p.sum(), 1e-300))
        if change < tol:
            return p, it, change
    raise ConvergenceError(
        f"normal contact did not converge in {max_iter} iterations on a {hs.shape[0]} x "
        f"{hs.shape[1]} {'periodic' if hs.periodic else 'free'} grid: last relative "
        f"pressure change {change:.2e} > tol {tol:.1e}, {int((p > 0).sum())} pixels in "
        f"contact, load {p.sum() * A:.4g} N; raise max_iter or tol, or check the gap "
        "(a contact of a few pixels is poorly resolved)",
        info={"iterations": max_iter, "change": change, "tol": tol,
              "contact_pixels": int((p > 0).sum()), "load": float(p.sum() * A)})
