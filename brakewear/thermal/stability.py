"""Stability of the staggered thermal-wear coupling (the amplification of one step)."""
from __future__ import annotations

import logging

import numpy as np

logger = logging.getLogger(__name__)

__all__ = ["staggered_amplification"]


def staggered_amplification(dt, capacity: float, loss: float, gain: float):
    """Amplification per step of the staggered scheme on the scalar model problem.

    ``C dT/dt = -L T + B T`` where ``L`` (``loss``) is conduction plus
    convection and ``B`` (``gain``) the thermoelastic feedback (a hotter
    spot expands, carries more pressure and makes more heat).  The
    staggered scheme solves the heat implicitly with the pressure of the
    last step: ``(C/dt + L) T1 = (C/dt + B) T0``, so

        a(dt) = (1 + dt B / C) / (1 + dt L / C).

    For ``B < L`` (the physical system is stable) ``a`` falls monotonically
    from 1 (``dt -> 0``) to ``B / L`` (``dt -> inf``, the steady fixed-point
    iteration): the staggering is stable for every ``dt``.  For ``B > L``
    (thermoelastic instability) ``a > 1`` for every ``dt``: the scheme grows
    like the physics, never faster than ``B / L`` per step.
    """
    dt = np.asarray(dt, dtype=float)
    return (1.0 + dt * gain / capacity) / (1.0 + dt * loss / capacity)
