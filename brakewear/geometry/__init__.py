"""Brake geometry: the parts of a disc brake and the checked TOML files that define them.

:mod:`~brakewear.geometry.parts` holds the dataclasses (rotor, pad, piston,
mesh settings), :mod:`~brakewear.caliper.geometry` the load path (caliper,
fingers, pad support, rotor hat and vents), :mod:`~brakewear.geometry.files` reads and checks
geometry
files (docs: reference/geometry) and :mod:`~brakewear.geometry.sections` their load-path keys.
"""

from ..caliper import geometry as caliper
from ..caliper.geometry import *  # noqa: F403
from . import files, parts, sections
from .files import *  # noqa: F403
from .parts import *  # noqa: F403
from .sections import *  # noqa: F403

__all__ = [*files.__all__, *parts.__all__, *caliper.__all__, *sections.__all__]
