"""Interface models: what a wear step asks of the pad-rotor interface.

A wear step gives an interface a gap offset (the worn depths), the last
active set and, for the implicit step, the wear compliance; the interface
returns the contact pressure, the active set and the displacement
(:class:`InterfaceSolution`).  Models: finite-element contact
(:class:`FEInterface`) and an elastic (Winkler) foundation
(:class:`FoundationInterface` around :class:`WinklerInterface`, calibrated
against FE contact by :func:`calibrate`).
"""

from .calibration import (
    CalibrationReport,
    calibrate,
    compare,
    fe_approach,
    fe_lever_arm,
)
from .fe import FEInterface
from .foundation import FoundationInterface
from .winkler import FoundationResult, WinklerInterface, layer_modulus

__all__ = [
    "CalibrationReport",
    "fe_approach",
    "fe_lever_arm",
    "compare",
    "calibrate",
    "FEInterface",
    "FoundationInterface",
    "layer_modulus",
    "WinklerInterface",
    "FoundationResult",
]
