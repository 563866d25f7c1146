"""Closed-form reference solutions (docs/references.md), tested on their own.

* :mod:`~brakewear.analytic.contact` -- elastic contact: Hertz, the flat punch,
  Lamé's cylinder, the elastic foundation against Hertz, Mindlin;
* :mod:`~brakewear.analytic.wear` -- uniform wear and uniform pressure on a
  disc brake's pad;
* :mod:`~brakewear.analytic.heat` -- frictional heating of a slab and a
  half-space (constant flux, a stop), lumped bodies, rough contact conductance;
* :mod:`~brakewear.analytic.tribometer` -- the tribometer tests: partial slip
  (Cattaneo-Mindlin), a worn spherical cap, a conforming block on a ring.

All functions take and return SI units and accept NumPy arrays where a
coordinate is an argument; their docstrings carry examples that run as
doctests (tests/test_doctests.py).
"""

from . import contact, heat, tribometer, wear
from .contact import *  # noqa: F403
from .heat import *  # noqa: F403
from .tribometer import *  # noqa: F403
from .wear import *  # noqa: F403

__all__ = [*contact.__all__, *wear.__all__, *heat.__all__, *tribometer.__all__]
