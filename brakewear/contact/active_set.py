"""The active-set driver shared by every contact solve."""
from __future__ import annotations

import logging

import numpy as np

logger = logging.getLogger(__name__)

__all__ = []


def _set_key(active) -> bytes:
    return b"".join(np.packbits(a).tobytes() for a in active)


_SETTLING = 0.1  # an update changing at most this share of the active nodes: nearly settled


_FIRST = 1e-2  # relative tolerance of the first, cold solve


_MEDIUM = 1e-6  # relative tolerance of the solves after the loose phase, before the last


_INEXACT = 1e-1  # intermediate solves cut their warm-start residual by this factor


def _pdas_update(active, lam, gaps, gap_tol, ltol):
    """Primal-dual active set: stay if compressive, enter if penetrating."""
    return [(a & (l > -lt)) | (~a & (g < -gap_tol)) for a, l, g, lt in zip(active, lam, gaps, ltol)]


def _conservative_update(active, lam, gaps, gap_tol, ltol):
    """Add every penetrating node; if none, release the most tensile nodes only:
    those pulling at least half as hard as the worst one.  Adding and releasing
    never happen in the same iteration, which is what stops a cycle; releasing
    in bulk (rather than one node at a time) keeps large sets within budget."""
    pen = [(~a) & (g < -gap_tol) for a, g in zip(active, gaps)]
    if any(p.any() for p in pen):
        return [a | p for a, p in zip(active, pen)]
    worst = min((float(np.min(np.where(a, l, np.inf))) for a, l in zip(active, lam) if a.any()),
                default=0.0)
    return [a & ~((l < 0.5 * worst) & (l < -lt)) for a, l, lt in zip(active, lam, ltol)]
