"""Scenes: one brake model plus what to compute, from a TOML file or from Python."""

from . import build, reader, spec, starter, tables
from .build import *  # noqa: F403
from .reader import *  # noqa: F403
from .spec import *  # noqa: F403
from .starter import *  # noqa: F403
from .tables import *  # noqa: F403

__all__ = [*build.__all__, *reader.__all__, *spec.__all__, *starter.__all__, *tables.__all__]
