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
from .jump import Jump, JumpControl, cycle_jumps
from .kinds import CycleResult, TestKind, register_test, test_kind, test_kinds
from .runner import run_test, test_figures
from .scene import TribometerScene, is_test, test_from_dict

__all__ = ["Jump", "JumpControl", "cycle_jumps", "CycleResult", "TestKind", "register_test",
           "test_kind", "test_kinds", "run_test", "test_figures", "TribometerScene", "is_test",
           "test_from_dict"]
