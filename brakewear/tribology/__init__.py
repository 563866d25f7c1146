"""Tribometer tests as scenes: pin on disc, block on ring, a cylinder reciprocating on a flat.

The same wear loop as the brake's, on the counterfaces a wear model is
validated on (docs/validation.md):

* :mod:`~brakewear.tribology.bodies` -- each body meshed fine at its contact and
  condensed onto its contact face (its compliance there);
* :mod:`~brakewear.tribology.pair` -- the two faces paired at the master's offset;
* :mod:`~brakewear.tribology.kinds` -- the test kinds, registered by name, each a
  class with its keys and capabilities: :mod:`~brakewear.tribology.reciprocating`
  (stick and slip solved by :mod:`brakewear.contact.friction`) and
  :mod:`~brakewear.tribology.sliding` (pin on disc, block on ring);
* :mod:`~brakewear.tribology.jump` -- the cycle jump and its error control;
* :mod:`~brakewear.tribology.scene` -- the scene file (``scene.test``), read by
  :func:`brakewear.load_scene`;
* :mod:`~brakewear.tribology.runner`, :mod:`~brakewear.tribology.output` -- a run
  and its files (ParaView series, CSVs, summary.json, the profile figure).
"""
from . import reciprocating, sliding  # noqa: F401  (the built-in kinds register themselves)
from .jump import Jump, JumpControl, cycle_jumps
from .kinds import (
                    CycleResult,
                    TribometerKind,
                    register_tribometer,
                    tribometer_kind,
                    tribometer_kinds,
)
from .runner import run_tribometer, worn_figures
from .scene import TribometerScene, is_tribometer, tribometer_from_dict

__all__ = ["Jump", "JumpControl", "cycle_jumps", "CycleResult", "TribometerKind",
           "register_tribometer", "tribometer_kind", "tribometer_kinds", "run_tribometer",
           "worn_figures", "TribometerScene", "is_tribometer", "tribometer_from_dict"]
