"""Brake geometry: the parts of a disc brake and the checked TOML files that define them.

:mod:`~brakewear.geometry.parts` holds the dataclasses (rotor, pad, piston,
mesh settings), :mod:`~brakewear.geometry.files` reads and checks geometry
files (docs: reference/geometry).
"""

from . import files, parts
from .files import *  # noqa: F403
from .parts import *  # noqa: F403

__all__ = [*files.__all__, *parts.__all__]
