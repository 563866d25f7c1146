"""Closed forms of a worn-in disc brake: the pressure, torque and friction radius of
uniform wear (``p r`` constant over the pad) and of uniform pressure.

All functions take and return SI units and accept NumPy arrays where a
coordinate is an argument.
"""
from __future__ import annotations

import numpy as np

__all__ = [
    "uniform_wear_pressure",
    "uniform_wear_torque",
    "uniform_pressure_effective_radius",
]


def uniform_wear_pressure(r, F: float, theta: float, ri: float, ro: float):
    """Steady uniform-wear pressure of an annular-sector pad: p = F / (theta (ro - ri) r).

    Examples
    --------
    ``p r`` is the same everywhere (every point wears at ``k p omega r``), and the
    pressure carries the force over the sector:

    >>> r = np.linspace(0.1, 0.15, 6)
    >>> p = uniform_wear_pressure(r, 2000.0, 1.0, 0.1, 0.15)
    >>> bool(np.allclose(p * r, p[0] * r[0], rtol=1e-14))
    True
    >>> from scipy.integrate import quad
    >>> round(quad(lambda s: uniform_wear_pressure(s, 2000.0, 1.0, 0.1, 0.15) * s, 0.1, 0.15)[0], 9)
    2000.0
    """
    return F / (theta * (ro - ri) * np.asarray(r, dtype=float))


def uniform_wear_torque(F: float, mu: float, ri: float, ro: float) -> float:
    """Braking torque per face under uniform wear: mu F (ro + ri) / 2.

    Examples
    --------
    >>> round(uniform_wear_torque(5000.0, 0.4, 0.1, 0.15), 12)      # N m
    250.0
    """
    return mu * F * (ro + ri) / 2.0


def uniform_pressure_effective_radius(ri: float, ro: float) -> float:
    """Effective friction radius under uniform pressure: (2/3)(ro^3 - ri^3)/(ro^2 - ri^2).

    Examples
    --------
    Above the mean radius of uniform wear, by ``(ro - ri)^2 / (6 (ro + ri))``:

    >>> r = uniform_pressure_effective_radius(0.1, 0.15)
    >>> bool(np.isclose(r, 0.125 + 0.05 ** 2 / (6 * 0.25), rtol=1e-14, atol=0))
    True
    """
    return 2.0 / 3.0 * (ro ** 3 - ri ** 3) / (ro ** 2 - ri ** 2)
