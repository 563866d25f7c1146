"""Brake geometry: the parts of a disc brake and the checked TOML files that define them.

:mod:`~brakewear.geometry.parts` holds the dataclasses (rotor, pad, piston,
mesh settings), :mod:`~brakewear.geometry.caliper` the load path (caliper,
fingers, pad support, rotor hat and vents), :mod:`~brakewear.geometry.files` reads and checks geometry
files (docs: reference/geometry) and :mod:`~brakewear.geometry.loadpath` their load-path keys.
"""

from . import caliper, files, loadpath, parts
from .caliper import *  # noqa: F403
from .files import *  # noqa: F403
from .loadpath import *  # noqa: F403
from .parts import *  # noqa: F403

__all__ = [*files.__all__, *parts.__all__, *caliper.__all__, *loadpath.__all__]
