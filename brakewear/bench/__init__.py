"""Benchmarks behind ``brakewear bench``: timings and errors.

* :mod:`~brakewear.bench.elasticity` -- mesh, assembly, AMG setup and solve of a ring;
* :mod:`~brakewear.bench.contact` -- contact solves (Hertz, the default brake) against
  one elasticity solve, with the direct references of :mod:`~brakewear.bench.kkt`;
* :mod:`~brakewear.bench.wear` -- the cost per step of a wear history;
* :mod:`~brakewear.bench.rough` -- the half-space rough contact against tamaas and the
  foundation bed;
* :mod:`~brakewear.bench.cli` -- the command line and the fresh child processes.
"""

from . import cli, common, contact, elasticity, kkt, rough, wear
from .cli import *  # noqa: F403
from .common import *  # noqa: F403
from .contact import *  # noqa: F403
from .elasticity import *  # noqa: F403
from .kkt import *  # noqa: F403
from .rough import *  # noqa: F403
from .wear import *  # noqa: F403

__all__ = [*cli.__all__, *common.__all__, *contact.__all__, *elasticity.__all__, *kkt.__all__,
           *rough.__all__, *wear.__all__]
