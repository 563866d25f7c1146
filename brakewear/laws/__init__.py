"""Friction and wear laws, per node: closed forms, measured maps and their files.

- :mod:`~brakewear.laws.base`: the generalised Archard law (:class:`WearLaw`),
  a friction fade (:class:`FrictionLaw`), the per-node protocols every law
  answers, and the table of named wear laws a scene chooses from;
- :mod:`~brakewear.laws.maps`: laws from measured tables over pressure, speed
  and temperature (:class:`TableMap`, :class:`FrictionMap`, :class:`WearMap`)
  and further closed forms (Stribeck friction, mild-to-severe wear);
- :mod:`~brakewear.laws.map_files`: reading and checking those tables' CSV files.
"""
from .base import *  # noqa: F403
from .base import __all__ as _base_all
from .maps import *  # noqa: F403
from .maps import __all__ as _maps_all

__all__ = [*_base_all, *_maps_all]
