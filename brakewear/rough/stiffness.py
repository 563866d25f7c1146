"""Normal and tangential stiffness of a contact on the half-space (:func:`contact_stiffness`).

**Normal.**  A frictionless contact's tangent stiffness ``dF/d delta`` is the
stiffness of a rigid flat punch whose face is the contact area (Barber
1974; the contact grows only at its edge, where the pressure is zero, so a
small extra approach acts on the fixed set).  On the grid: a uniform unit
displacement on the contact pixels, zero traction elsewhere, ``K_SS x = 1``,
solved by conjugate gradients (``K_SS`` symmetric positive definite), and
``K = sum x A_pixel``.  For a Hertz contact this gives ``2 E* a``.

**Tangential.**  The same on the stuck contact with the Cerruti kernel
(:class:`~brakewear.rough.HalfSpace`, ``direction = "tangential"``): the
stiffness of the contact against a small rigid shift along x with every
contact pixel stuck (no micro-slip).  For a circle it is Mindlin's
``8 G a / (2 - nu)`` (:func:`brakewear.analytic.mindlin_tangential_stiffness`).
It is the initial (small-displacement) tangential stiffness; slip at the
edge lowers it under load (Mindlin).

Why a solve rather than a formula: for one circle ``K_t / K_n = 2 (1 - nu) /
(2 - nu)`` exactly, and for rough contacts nearly so (Campana, Persson and
Muser 2011), but the foundation model is to be judged against the
half-space's own answer on the same contact set, so both come from the same
solve; the ratio is reported beside them.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceError, RoughnessError
from .halfspace import HalfSpace

logger = logging.getLogger(__name__)

__all__ = ["Stiffness", "contact_stiffness"]


@dataclass(frozen=True)
class Stiffness:
    """``stiffness`` (N/m), the ``traction`` (Pa per pixel) of a unit rigid
    displacement, ``iterations``, ``residual`` (relative) and ``seconds``."""

    stiffness: float
    traction: np.ndarray
    iterations: int
    residual: float
    seconds: float


def contact_stiffness(halfspace: HalfSpace, contact, direction: str = "normal",
                      tol: float = 1e-8, max_iter: int | None = None) -> Stiffness:
    """Stiffness of the stuck contact set ``contact`` (bool per pixel) on the half-space.

    Parameters
    ----------
    halfspace
        The elastic body.
    contact
        Pixels in contact (``NormalContact.contact``).
    direction
        ``"normal"`` (the tangent normal stiffness) or ``"tangential"`` (along x).
    tol
        Relative residual ``|1 - K_SS x| / |1|`` at convergence.
    max_iter
        CG budget (default ``max(500, 4 max(nx, ny))``).

    Raises
    ------
    ConvergenceError
        The budget ran out (``info`` holds the figures).
    """
    t0 = time.perf_counter()
    S = np.asarray(contact, dtype=bool)
    if S.shape != halfspace.shape:
        raise RoughnessError(f"contact has shape {S.shape}; need the grid {halfspace.shape}")
    if not S.any():
        raise RoughnessError("contact holds no pixel: a contact without area has no stiffness")
    if S.all() and halfspace.periodic:
        raise RoughnessError("every pixel is in contact on a periodic grid: the interface "
                             "is closed and its stiffness is unbounded")
    max_iter = max(500, 4 * max(halfspace.shape)) if max_iter is None else int(max_iter)
    Sf = S.astype(float)
    b_norm = np.sqrt(Sf.sum())
    x = np.zeros(S.shape)
    r = Sf.copy()                      # residual of K x = 1 on S (x = 0)
    d = r.copy()
    rr = _dot(r, r)
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007  (the count is reported)
        Kd = halfspace.displacement(d, direction) * Sf
        alpha = rr / _dot(d, Kd)
        x += alpha * d
        r -= alpha * Kd
        rr_new = _dot(r, r)
        if np.sqrt(rr_new) <= tol * b_norm:
            rr = rr_new
            break
        d *= rr_new / rr
        d += r
        rr = rr_new
    else:
        raise ConvergenceError(
            f"{direction} contact stiffness: conjugate gradients did not reach {tol:.1e} in "
            f"{max_iter} iterations (residual {np.sqrt(rr) / b_norm:.2e}, {int(S.sum())} "
            f"contact pixels on a {halfspace.shape[0]} x {halfspace.shape[1]} grid)",
            info={"iterations": max_iter, "residual": float(np.sqrt(rr) / b_norm),
                  "contact_pixels": int(S.sum())})
    K = float(x.sum() * halfspace.pixel_area)
    res = Stiffness(K, x, it, float(np.sqrt(rr) / b_norm), time.perf_counter() - t0)
    logger.debug("%s stiffness %.4g N/m: %d CG iterations, %.3f s", direction, K, it,
                 res.seconds)
    return res


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.einsum("ij,ij->", a, b))
